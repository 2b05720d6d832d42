// The inputs the fuzzers found (tests/fuzz/regressions, docs/robustness.md), in the default
// suite: each must be read or refused with a tc::Error, as the fuzz targets demand.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tc/core/error.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> files(const std::string& dir) {
  std::vector<fs::path> out;
  for (const auto& e :
       fs::directory_iterator(fs::path(TC_SOURCE_DIR) / "tests/fuzz/regressions" / dir))
    out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(FuzzRegression, EveryCaseFileFoundIsReadOrRefusedWithAnInputError) {
  const auto found = files("case");
  ASSERT_FALSE(found.empty());
  for (const auto& f : found) {
    try {
      (void)tc::io::read_case(f);
    } catch (const tc::Error&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": " << e.what();
    }
  }
}

TEST(FuzzRegression, EveryMeshFileFoundIsReadOrRefusedWithAMeshError) {
  // First byte: the dimension (0 → 2D, 1 → 3D), as fuzz_gmsh_reader reads them.
  const auto found = files("msh");
  ASSERT_FALSE(found.empty());
  const auto tmp = fs::temp_directory_path() / "tc-fuzz-regression.msh";
  for (const auto& f : found) {
    std::ifstream in(f, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    const auto bytes = s.str();
    ASSERT_FALSE(bytes.empty());
    std::ofstream(tmp, std::ios::binary) << bytes.substr(1);
    try {
      (void)tc::mesh::read_gmsh(tmp, (bytes[0] & 1) ? 3 : 2);
    } catch (const tc::MeshError&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << f << ": " << e.what();
    }
  }
}

TEST(FuzzRegression, AFileOnWhichLibgmshCrashesIsAMeshError) {
  // Through gmsh's C++ API libgmsh 4.8 freed an invalid pointer in gmsh::finalize after
  // reading this file (glibc aborted): the reader's child process died and the solver reported
  // "crashed on it (signal 6)". Through its C API (loaded with dlopen since issue 22) the same
  // read fails cleanly with gmsh's own message ("Could not read nodes"). Either way it must be
  // a MeshError naming the file, never a crash of the solver.
  const auto f = fs::path(TC_SOURCE_DIR) / "tests/fuzz/regressions/msh/gmsh-invalid-free-2d.msh";
  std::ifstream in(f, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  const auto tmp = fs::temp_directory_path() / "tc-gmsh-crash.msh";
  std::ofstream(tmp, std::ios::binary) << s.str().substr(1);
  try {
    (void)tc::mesh::read_gmsh(tmp, 2);
    ADD_FAILURE() << "read";
  } catch (const tc::MeshError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("cannot read mesh file '" + tmp.string() + "'"), std::string::npos) << what;
    EXPECT_TRUE(what.find("crashed on it (signal 6)") != std::string::npos ||
                what.find("Could not read nodes") != std::string::npos)
        << what;
  }
}

TEST(FuzzRegression, NonAsciiOutsideStringsAndCommentsIsRefusedBeforeTomlpp) {
  // toml++ 3.3.0 reaches __builtin_unreachable on these (fuzz_case_reader, UBSan).
  const auto f =
      fs::path(TC_SOURCE_DIR) / "tests/fuzz/regressions/case/toml-unreachable-whitespace.toml";
  try {
    (void)tc::io::read_case(f);
    ADD_FAILURE() << "read";
  } catch (const tc::InputError& e) {
    ASSERT_EQ(e.issues().size(), 1u);
    EXPECT_EQ(e.issues()[0].line, 23);
    EXPECT_NE(e.issues()[0].message.find("\\xCE\\xB4"), std::string::npos) << e.what();
  }
}

TEST(FuzzRegression, StrayNonAsciiFindsOnlyTextOutsideStringsAndComments) {
  using tc::io::stray_non_ascii;
  // Allowed: comments, basic and literal strings, multi-line ones, escaped quotes in them.
  EXPECT_FALSE(stray_non_ascii("# ν θ₀\na = \"ν\"\nb = 'θ'\n"));
  EXPECT_FALSE(stray_non_ascii("a = \"\"\"\nν \\\"\"\" still\n\"\"\"\nb = '''\nθ\n'''\n"));
  EXPECT_FALSE(stray_non_ascii("a = \"x\\\"ν\" # ν\n"));
  // Refused, with the line: a value, a key, after a closed string, after a multi-line string.
  EXPECT_EQ(stray_non_ascii("a = 1\nb = 2ν\n")->first, 2);
  EXPECT_EQ(stray_non_ascii("aν = 1\n")->first, 1);
  EXPECT_EQ(stray_non_ascii("a = \"x\"ν\n")->first, 1);
  EXPECT_EQ(stray_non_ascii("a = \"\"\"\n\n\"\"\"ν\n")->first, 3);
  EXPECT_EQ(stray_non_ascii("a = 1 \xE3\x80\x80\n")->second, "\\xE3\\x80\\x80");
  // An unterminated single-line string ends at its line (toml++ reports it).
  EXPECT_EQ(stray_non_ascii("a = \"x\nν = 1\n")->first, 2);
}

}  // namespace
