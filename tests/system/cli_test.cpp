// The command line contract of case-format.md: exit codes, messages naming file:line:key,
// and what a run leaves behind. Runs every example and every malformed case file.
#include "support/cli.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <regex>
#include <sstream>

#include "support/history.hpp"

namespace fs = std::filesystem;
using tc::test::thermocontact;

namespace {

std::vector<fs::path> files_in(const fs::path& dir, const std::string& name = "") {
  std::vector<fs::path> out;
  if (!fs::exists(dir)) return out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".toml" && (name.empty() || e.path().filename() == name))
      out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

int count_lines(const std::string& s) {
  return static_cast<int>(std::count(s.begin(), s.end(), '\n'));
}

TEST(Cli, InfoNamesPetscAndTheFactorizations) {
  const auto r = thermocontact("info");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("PETSc"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Cholesky"), std::string::npos) << r.output;
  // The CHOLMOD path built in (issue 40): its own API, not PETSc's private factor.
  EXPECT_NE(r.output.find("CHOLMOD: "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("through its public API"), std::string::npos) << r.output;
}

TEST(Cli, EveryInvalidCaseExitsWithTwoNamingFileLineAndKey) {
  const auto cases = files_in(fs::path(TC_SOURCE_DIR) / "tests/cases/invalid");
  ASSERT_GE(cases.size(), 20u);
  for (const auto& c : cases) {
    const auto r = thermocontact("check " + c.string());
    EXPECT_EQ(r.exit_code, 2) << c << "\n" << r.output;
    // FILE:LINE: KEY: message, with a positive line number.
    const std::regex located(
        std::regex_replace(c.string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
        R"(:[1-9][0-9]*: [^:]+: .+)");
    EXPECT_TRUE(std::regex_search(r.output, located)) << c << "\n" << r.output;
    // Each `# expect: KEY SUBSTRING` line of the file names an issue that must be reported.
    std::istringstream lines(tc::test::read_file(c));
    std::string line;
    int expectations = 0;
    while (std::getline(lines, line)) {
      if (line.rfind("# expect: ", 0) != 0) continue;
      const auto rest = line.substr(10);
      const auto key = rest.substr(0, rest.find(' '));
      const auto text = rest.substr(rest.find(' ') + 1);
      ++expectations;
      bool found = false;
      std::istringstream out(r.output);
      std::string l;
      while (std::getline(out, l))
        found = found || (l.find(": " + key + ": ") != std::string::npos &&
                          l.find(text) != std::string::npos);
      EXPECT_TRUE(found) << c << ": expected key " << key << " with '" << text << "' in\n"
                         << r.output;
    }
    EXPECT_GE(expectations, 1) << c;
    const auto run =
        thermocontact("run " + c.string() + " --output " + tc::test::fresh_dir("invalid").string());
    EXPECT_EQ(run.exit_code, 2) << c << "\n" << run.output;
  }
}

TEST(Cli, EveryExampleRunsAndLeavesItsOutput) {
  const auto cases = files_in(fs::path(TC_SOURCE_DIR) / "examples", "case.toml");
  ASSERT_FALSE(cases.empty());
  for (const auto& c : cases) {
    // An example whose case file has a line `# test: slow` (a run of many seconds) is only
    // validated here; a test labelled slow runs it whole (example 07:
    // tests/system/example_pin_on_plate_slow.cpp).
    const auto text = tc::test::read_file(c);
    if (text.rfind("# test: slow", 0) == 0 || text.find("\n# test: slow") != std::string::npos) {
      const auto check = thermocontact("check " + c.string());
      EXPECT_EQ(check.exit_code, 0) << c << "\n" << check.output;
      continue;
    }
    const auto out = tc::test::fresh_dir(c.parent_path().filename().string());
    const auto r = thermocontact("run " + c.string() + " --output " + out.string());
    ASSERT_EQ(r.exit_code, 0) << c << "\n" << r.output;
    const auto summary = tc::test::read_file(out / "summary.json");
    EXPECT_NE(summary.find("\"status\": \"completed\""), std::string::npos) << summary;
    const auto history = tc::test::read_file(out / "history.csv");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(summary, m, std::regex(R"("steps_done": ([0-9]+))")));
    // A header and one row per step, t = 0 included.
    EXPECT_EQ(count_lines(history), std::stoi(m[1]) + 2) << c;
    EXPECT_TRUE(fs::exists(out / "result.pvd"));
    EXPECT_NE(tc::test::read_file(out / "result.pvd").find(".vtu"), std::string::npos);
  }
}

TEST(Cli, ANumericalFailureStopsWithExitOneAndKeepsTheStepsDone) {
  // A strongly coupled body and a fixed point allowed one iteration at a tolerance it
  // cannot meet: the run must stop at step 1, say so, and leave valid output.
  const auto dir = tc::test::fresh_dir("failure");
  std::ofstream(dir / "case.toml") << R"(
dimension = 2
[time]
step = 1e-6
end = 1e-5
[solver]
coupling_tolerance = 1e-14
max_coupling_iterations = 1
[materials.m]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1e-4
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "b"
material = "m"
mesh = { box = { min = [0.0, 0.0], max = [0.01, 0.01], cells = [2, 2] } }
initial_temperature = 400.0
)";
  const auto r =
      thermocontact("run " + (dir / "case.toml").string() + " --output " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("step 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("residual"), std::string::npos) << r.output;
  const auto summary = tc::test::read_file(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
  EXPECT_EQ(count_lines(tc::test::read_file(dir / "out/history.csv")), 2);  // header + t = 0
}

TEST(Cli, FilmAndRadiationRunFromACaseFileIntoTheirHistoryColumns) {
  // A Gmsh plate at 600 K cooled by a film and by radiation: both columns grow step by step,
  // and with no other heat in or out the thermal energy falls by their sum (the ledger).
  const auto dir = tc::test::fresh_dir("film_radiation");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/valid/film-radiation.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + (dir / "out").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = tc::test::read_history(dir / "out/history.csv");
  const auto film = tc::test::column(h, "heat_film");
  const auto radiation = tc::test::column(h, "heat_radiation");
  const auto energy = tc::test::column(h, "thermal_energy");
  ASSERT_EQ(film.size(), 4u);
  for (size_t k = 1; k < film.size(); ++k) {
    EXPECT_GT(film[k], film[k - 1]);
    EXPECT_GT(radiation[k], radiation[k - 1]);
    // history.csv holds 17 significant digits: the balance closes to the Newton tolerance.
    EXPECT_NEAR(energy[k] - energy[0], -(film[k] + radiation[k]), 1e-9 * film[k]);
  }
}

TEST(Cli, AnOptionNothingReadIsReportedAfterTheRun) {
  // Unknown single-dash options go to PETSc's database (for PETSc options); one that nothing
  // reads, such as `-o dir` for --output, used to vanish without a word. One that the run
  // reads (-tc_factor_package) must not be reported.
  const auto dir = tc::test::fresh_dir("unused_option");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/valid/quasistatic.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + (dir / "out").string() +
                               " -o elsewhere -tc_factor_package petsc");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("warning: option -o elsewhere was not used"), std::string::npos)
      << r.output;
  // A header and one row per step (t = 0, 0.1, 0.2, 0.3): the run went to --output.
  EXPECT_EQ(count_lines(tc::test::read_file(dir / "out/history.csv")), 5) << r.output;
  EXPECT_EQ(r.output.find("tc_factor_package"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "elsewhere"));
}

}  // namespace

TEST(Cli, AContactCaseRunsWithTheMortarPairAndWritesContactOutput) {
  // tests/cases/valid/contact-patch-2d.toml: non-matching blocks pressed by δ = 1e-4 m,
  // uniaxial plane strain, so the contact force per metre is E/(1 − ν²)·δ/(h_s + h_m) × 1 m.
  const auto out = tc::test::fresh_dir("contact-patch");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto summary = tc::test::read_file(out / "summary.json");
  EXPECT_NE(summary.find("\"dual_operator\": \"explicit\""), std::string::npos) << summary;
  std::istringstream history(tc::test::read_file(out / "history.csv"));
  std::string header, row, last;
  std::getline(history, header);
  while (std::getline(history, row))
    if (!row.empty()) last = row;
  const auto column = [](const std::string& line, size_t i) {
    std::istringstream s(line);
    std::string cell;
    for (size_t k = 0; k <= i; ++k) std::getline(s, cell, ',');
    return cell;
  };
  size_t i = 0;
  while (column(header, i) != "contact_normal_force") ++i;
  const double expected = 2.0e11 / (1 - 0.09) * 1e-4 / 1.5;
  // 1e-8: the QP tolerance of the case is 1e-12 relative; the patch test is exact otherwise.
  EXPECT_NEAR(std::stod(column(last, i)), expected, 1e-8 * expected);
  const auto vtu = tc::test::read_file(out / "upper_000001.vtu");
  for (const char* field :
       {"contact_pressure", "tangential_traction", "slip_velocity", "contact_heat_flux"})
    EXPECT_NE(vtu.find(field), std::string::npos) << field;
}

TEST(Cli, SeveralContactPairsWriteTheirColumnsAndTheirFieldsOnEveryBody) {
  // tests/cases/several-pairs/three-blocks-2d.toml: "upper" (top on middle), "lower" (middle on
  // base). The middle block is the master of one pair and the slave of the other: its .vtu
  // carry the contact fields of both, the top's those of "upper" (slave), the base's those of
  // "lower" carried to the master side.
  const auto out = tc::test::fresh_dir("several-pairs");
  const auto c = fs::path(TC_SOURCE_DIR) / "tests/cases/several-pairs/three-blocks-2d.toml";
  const auto r = thermocontact("run " + c.string() + " --output " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto h = tc::test::read_history(out / "history.csv");
  ASSERT_TRUE(h.whole);
  const auto at = [&](const std::string& name) {
    const auto it = std::find(h.columns.begin(), h.columns.end(), name);
    EXPECT_NE(it, h.columns.end()) << name;
    return it == h.columns.end() ? 0.0 : h.rows.back()[it - h.columns.begin()];
  };
  for (const char* column : {"contact_normal_force", "heat_generated", "heat_conducted"}) {
    const std::string base = column;
    // The unsuffixed column is the sum of the pairs' (round-off of one addition).
    EXPECT_NEAR(at(base), at(base + "_upper") + at(base + "_lower"),
                1e-12 * std::abs(at(base)) + 1e-300)
        << column;
  }
  EXPECT_GT(at("contact_normal_force_upper"), 0);
  EXPECT_GT(at("contact_normal_force_lower"), 0);
  EXPECT_EQ(at("heat_generated_lower"), 0.0);  // frictional_heating = false in that pair
  const auto pressure = [&](const std::string& vtu) {
    return tc::test::read_file(out / vtu).find("contact_pressure") != std::string::npos;
  };
  EXPECT_TRUE(pressure("top_000005.vtu"));
  EXPECT_TRUE(pressure("middle_000005.vtu"));
  EXPECT_TRUE(pressure("base_000005.vtu"));
}

TEST(Cli, AContactQpThatDoesNotConvergeStopsTheRunWithExitOne) {
  // The contact patch case allowed one QP iteration: the run must stop at step 1 with exit
  // code 1, name the step, the coupling iteration and the residual, and leave valid output.
  const auto dir = tc::test::fresh_dir("contact-qp-failure");
  auto text =
      tc::test::read_file(fs::path(TC_SOURCE_DIR) / "tests/cases/valid/contact-patch-2d.toml");
  text += "max_qp_iterations = 1\n";  // the [solver] table is the file's last
  std::ofstream(dir / "case.toml") << text;
  const auto r =
      thermocontact("run " + (dir / "case.toml").string() + " --output " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("contact QP"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("step 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("iteration 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("residual"), std::string::npos) << r.output;
  const auto summary = tc::test::read_file(dir / "out/summary.json");
  EXPECT_NE(summary.find("\"status\": \"stopped\""), std::string::npos) << summary;
}
