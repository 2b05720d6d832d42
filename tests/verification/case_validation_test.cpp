// The validation contract of case-format.md on tests/cases/invalid: every malformed file is
// rejected with an InputError whose issues name file, a line > 0, the dotted key and what was
// found / expected. Each file states what it expects in `# expect: KEY SUBSTRING` lines.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "tc/core/error.hpp"
#include "tc/io/case/case_reader.hpp"

namespace {

namespace fs = std::filesystem;

struct Expectation {
  std::string key, text;
};

std::vector<Expectation> expectations_of(const fs::path& file) {
  std::ifstream in(file);
  std::vector<Expectation> out;
  std::string line;
  const std::string tag = "# expect: ";
  while (std::getline(in, line)) {
    if (line.rfind(tag, 0) != 0) continue;
    const auto rest = line.substr(tag.size());
    const auto space = rest.find(' ');
    out.push_back({rest.substr(0, space), rest.substr(space + 1)});
  }
  return out;
}

std::vector<fs::path> invalid_cases() {
  std::vector<fs::path> out;
  for (const auto& e : fs::directory_iterator(fs::path(TC_SOURCE_DIR) / "tests/cases/invalid"))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::string all_issues(const tc::InputError& e) {
  std::string s;
  for (const auto& i : e.issues()) s += "  " + i.str() + "\n";
  return s;
}

class InvalidCase : public testing::TestWithParam<fs::path> {};

TEST_P(InvalidCase, IsRejectedWithTheExpectedIssues) {
  const auto file = GetParam();
  const auto expected = expectations_of(file);
  ASSERT_FALSE(expected.empty()) << file << " has no `# expect:` line";
  try {
    (void)tc::io::read_case(file);
    FAIL() << file << " was accepted";
  } catch (const tc::InputError& e) {
    ASSERT_FALSE(e.issues().empty());
    for (const auto& i : e.issues()) {
      EXPECT_EQ(i.str().rfind(file.string() + ":", 0), 0u) << i.str();
      EXPECT_GT(i.line, 0) << i.str();
      EXPECT_FALSE(i.key.empty()) << i.str();
    }
    for (const auto& x : expected) {
      const bool found = std::any_of(e.issues().begin(), e.issues().end(), [&](const auto& i) {
        return i.key == x.key && i.line > 0 && i.message.find(x.text) != std::string::npos;
      });
      EXPECT_TRUE(found) << "expected key " << x.key << " with '" << x.text << "' in\n"
                         << all_issues(e);
    }
  }
}

std::string test_name(const testing::TestParamInfo<fs::path>& info) {
  auto s = info.param.stem().string();
  std::replace_if(
      s.begin(), s.end(), [](char c) { return !std::isalnum(c); }, '_');
  return s;
}

INSTANTIATE_TEST_SUITE_P(Files, InvalidCase, testing::ValuesIn(invalid_cases()), test_name);

TEST(CaseValidation, ThereIsOneFilePerRule) {
  EXPECT_GE(invalid_cases().size(), 24u);
}

TEST(CaseValidation, SeveralErrorsAreAllReportedInFileOrder) {
  try {
    (void)tc::io::read_case(fs::path(TC_SOURCE_DIR) / "tests/cases/invalid/27-several-errors.toml");
    FAIL();
  } catch (const tc::InputError& e) {
    EXPECT_GE(e.issues().size(), 3u);
    EXPECT_TRUE(std::is_sorted(e.issues().begin(), e.issues().end(),
                               [](const auto& a, const auto& b) { return a.line < b.line; }));
    // what() holds every issue, one per line.
    const std::string what = e.what();
    EXPECT_EQ(std::count(what.begin(), what.end(), '\n') + 1, static_cast<long>(e.issues().size()));
  }
}

}  // namespace
