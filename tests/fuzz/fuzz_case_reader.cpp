// libFuzzer target: the case-file reader (toml++ parse, validation, box meshes, referenced
// Gmsh files). Every input must either be read or be rejected with a tc::Error (InputError
// or MeshError, exit code 2 in the CLI); any other exception, crash, leak or hang is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "tc/core/error.hpp"
#include "tc/io/case/case_reader.hpp"

namespace fs = std::filesystem;

namespace {

fs::path g_dir;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // One directory per process holding the case and the .msh files cases may name.
  g_dir = fs::temp_directory_path() / ("tc-fuzz-case-" + std::to_string(getpid()));
  fs::create_directories(g_dir);
  fs::copy_file(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/square.msh", g_dir / "square.msh",
                fs::copy_options::overwrite_existing);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = g_dir / "case.toml";
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    const auto problem = tc::io::read_case(file);
    (void)problem;
  } catch (const tc::Error&) {  // InputError, MeshError: the documented rejection
  }
  return 0;
}
