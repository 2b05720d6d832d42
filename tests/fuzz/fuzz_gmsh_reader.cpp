// libFuzzer target: the Gmsh .msh reader (tc::mesh::read_gmsh) in 2D and 3D. The file is
// parsed by libgmsh, which is not instrumented (only our layer that copies gmsh's arrays into
// the Mesh, checks cells and attaches boundary facets is): coverage guides the fuzzer through
// our code, and AddressSanitizer still sees gmsh's heap use through its malloc interposition.
// Every input must be read or rejected with tc::MeshError.
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "tc/core/error.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"

namespace fs = std::filesystem;

namespace {

fs::path g_file;

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const auto dir = fs::temp_directory_path() / ("tc-fuzz-msh-" + std::to_string(getpid()));
  fs::create_directories(dir);
  g_file = dir / "mesh.msh";
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  // The first byte chooses the dimension, the rest is the file.
  const int dim = (data[0] & 1) ? 3 : 2;
  {
    std::ofstream out(g_file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data + 1), static_cast<std::streamsize>(size - 1));
  }
  try {
    const auto mesh = tc::mesh::read_gmsh(g_file, dim);
    (void)mesh;
  } catch (const tc::Error&) {  // MeshError: the documented rejection
  }
  return 0;
}
