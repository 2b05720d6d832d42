// Issue 20: inputs that the command line took in silently or reported wrongly, each through the
// binary as a user meets it (docs/robustness.md, "Bad input, issue 20").
#include <gtest/gtest.h>

#include <regex>

#include "support/cli.hpp"

namespace fs = std::filesystem;
using tc::test::replace_all;
using tc::test::thermocontact;

namespace {

/// A small valid case (one dynamic 2D body, 2 steps) for the variants below.
const std::string kCase = R"(dimension = 2
[time]
step = 0.001
end = 0.002
[materials.m]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "b"
material = "m"
mesh = { box = { min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2] } }
)";

/// Writes `text` as case.toml in a fresh directory named after the test.
fs::path write_case(const std::string& name, const std::string& text) {
  const auto file = tc::test::fresh_dir(name) / "case.toml";
  std::ofstream(file) << text;
  return file;
}

/// Whether `output` reports an issue as `FILE:LINE: KEY: ...TEXT...`.
bool reports(const std::string& output, const fs::path& file, const std::string& key,
             const std::string& text) {
  const auto escaped =
      std::regex_replace(file.string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)");
  const std::regex located(escaped + R"(:[1-9][0-9]*: )" +
                           std::regex_replace(key, std::regex(R"([.\[\]])"), R"(\$&)") + ": ");
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line))
    if (std::regex_search(line, located) && line.find(text) != std::string::npos) return true;
  return false;
}

/// The binary under a time limit: the old code ran some of these inputs for hours (1e8 steps),
/// and a regression should fail the test, not hang it.
tc::test::CommandResult limited(const std::string& args) {
  return tc::test::run_command("timeout 120 " + std::string(TC_BINARY) + " " + args);
}

/// `check` and `run` both refuse `file` with exit code 2, reporting KEY with TEXT.
void expect_refused(const fs::path& file, const std::string& key, const std::string& text) {
  const auto c = limited("check " + file.string());
  EXPECT_EQ(c.exit_code, 2) << c.output;
  EXPECT_TRUE(reports(c.output, file, key, text)) << key << " / " << text << "\n" << c.output;
  const auto r =
      limited("run " + file.string() + " --output " + (file.parent_path() / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(reports(r.output, file, key, text)) << key << " / " << text << "\n" << r.output;
  EXPECT_FALSE(fs::exists(file.parent_path() / "out")) << "a refused case wrote output";
}

// #5: end/step was rounded into an int, so it wrapped round: 4294967301 steps ran as 5,
// 2147483649 became negative, 1e300 "done: 0 steps".
TEST(Issue20, AStepCountBeyondTheLimitIsRefusedNamingTimeStep) {
  for (const auto& [end, step] :
       std::vector<std::pair<std::string, std::string>>{{"4294967.301", "0.001"},
                                                        {"2147483.649", "0.001"},
                                                        {"1.0", "1e-300"},
                                                        {"1e308", "1e-308"},
                                                        {"100000.001", "0.001"}}) {
    const auto file =
        write_case("steps", replace_all(replace_all(kCase, "end = 0.002", "end = " + end),
                                        "step = 0.001", "step = " + step));
    expect_refused(file, "time.step", "expected at most 100000000 steps");
  }
}

TEST(Issue20, AStepCountAtTheLimitIsAccepted) {
  const auto file = write_case("steps-limit", replace_all(kCase, "end = 0.002", "end = 100000.0"));
  const auto c = thermocontact("check " + file.string());
  EXPECT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("100000000 steps"), std::string::npos) << c.output;
}

}  // namespace
