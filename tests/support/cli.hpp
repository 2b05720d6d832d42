#pragma once
// Running the thermocontact binary from tests.
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace tc::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  std::FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), buf.size(), pipe)) r.output += buf.data();
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

inline CommandResult thermocontact(const std::string& args) {
  // Appended, not `std::string(TC_BINARY) + " " + args`: GCC 12 inlines that operator+ into a
  // false -Warray-bounds in some files (seen with the precompiled header).
  std::string command = TC_BINARY;
  command += ' ';
  command += args;
  return run_command(command);
}

/// `s` with every occurrence of `from` replaced by `to` (variants of a case file).
inline std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

inline std::string read_file(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The directories fresh_dir made, removed when the test process ends (each run left its own
/// behind: 9 000 of them had gathered in /tmp); TC_KEEP_TEST_DIRS=1 keeps them to look into.
struct FreshDirs {
  std::vector<std::filesystem::path> dirs;
  FreshDirs() = default;
  FreshDirs(const FreshDirs&) = delete;
  FreshDirs& operator=(const FreshDirs&) = delete;
  ~FreshDirs() {
    if (std::getenv("TC_KEEP_TEST_DIRS") != nullptr) return;
    std::error_code ignored;  // a directory a test removed itself is fine
    for (const auto& d : dirs) std::filesystem::remove_all(d, ignored);
  }
};
inline FreshDirs& fresh_dirs() {
  static FreshDirs dirs;
  return dirs;
}

/// A fresh empty directory under the system's temporary directory, private to this process:
/// ctest runs the tests of one binary in parallel processes, and other checkouts' test runs
/// may share the machine (a shared name let one run delete another's output mid-run).
inline std::filesystem::path fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() /
                 ("tc-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  fresh_dirs().dirs.push_back(d);
  return d;
}

}  // namespace tc::test
