// A newcomer's path (issue 9): the README's one-minute example, run with exactly the commands
// the README shows, produces the picture the README shows. The commands are read from the
// README itself (the ```sh block after "## One minute"), and run in a scratch directory that
// mirrors the repository's layout (build/, examples/01-heated-plate/, scripts/), so that the
// source tree stays clean.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include "support/cli.hpp"

namespace tc::test {
namespace {

namespace fs = std::filesystem;
const fs::path source(TC_SOURCE_DIR);

/// The shell commands of the first ```sh block after `heading`, continuation lines joined.
std::vector<std::string> readme_commands(const std::string& heading) {
  const auto text = read_file(source / "README.md");
  const auto at = text.find(heading);
  const auto begin = text.find("```sh\n", at);
  const auto end = text.find("```", begin + 6);
  std::vector<std::string> out;
  std::istringstream block(text.substr(begin + 6, end - begin - 6));
  std::string line, command;
  while (std::getline(block, line)) {
    const bool more = !line.empty() && line.back() == '\\';
    command += more ? line.substr(0, line.size() - 1) : line;
    if (!more) {
      if (command.find_first_not_of(' ') != std::string::npos) out.push_back(command);
      command.clear();
    }
  }
  return out;
}

TEST(Newcomer, TheReadmeCommandsDrawTheReadmePicture) {
  const auto commands = readme_commands("## One minute");
  ASSERT_EQ(commands.size(), 2u);
  const auto dir = fresh_dir(fmt::format("newcomer-{}", ::getpid()));
  const fs::path build = fs::path(TC_BINARY).parent_path().parent_path();
  fs::create_directory_symlink(build, dir / "build");
  fs::create_directory_symlink(source / "scripts", dir / "scripts");
  fs::create_directories(dir / "examples");
  fs::copy(source / "examples/01-heated-plate", dir / "examples/01-heated-plate",
           fs::copy_options::recursive);
  fs::remove_all(dir / "examples/01-heated-plate/out");
  for (const auto& c : commands) {
    const auto r = run_command(fmt::format("cd {} && {}", dir.string(), c));
    ASSERT_EQ(r.exit_code, 0) << c << "\n" << r.output;
  }
  ASSERT_TRUE(fs::exists(dir / "plate.png"));
  // The same plot of the same field by the same script: the images agree pixel for pixel up
  // to colour rounding; 0.01 of the colour range on average leaves room for the last digits
  // of the stress and nothing else (a different step or field differs by > 0.05).
  const auto r = run_command(fmt::format(
      "/usr/bin/python3 -c \"import sys; import matplotlib.image as m; import numpy as np; "
      "a = m.imread(sys.argv[1]); b = m.imread(sys.argv[2]); "
      "print('shape', a.shape == b.shape); "
      "print('diff', float(np.abs(a - b).mean()) if a.shape == b.shape else 1.0)\" {} {}",
      (dir / "plate.png").string(), (source / "docs/images/heated-plate.png").string()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("shape True"), std::string::npos) << r.output;
  const auto d = r.output.find("diff ");
  ASSERT_NE(d, std::string::npos) << r.output;
  EXPECT_LT(std::stod(r.output.substr(d + 5)), 0.01) << r.output;
}

}  // namespace
}  // namespace tc::test
