// The thesis example of ch. 7.2.2 (coarse mesh, first 0.3 s: approach, pressing, the start of
// sliding) run undecomposed and with both bodies cut into 8 subdomains (FETI), on one rank and
// through the MPI launcher on two: the histories must agree to 1e-6 (issue 8's acceptance).
// The case file sets the QP, coupling and FETI tolerances to 1e-11, 1e-10, 1e-12 so that
// differences of the runs' solver paths stay far below it.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

const std::filesystem::path kCase =
    std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/thesis-coarse.toml";

class FetiCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // ctest runs each test of the suite as its own process, possibly at the same time.
    dir_ = fresh_dir(fmt::format("feti-cli-{}", ::getpid()));
    const auto text = read_file(kCase);
    const auto cut = dir_ / "cut.toml";
    std::ofstream(cut) << replace_all(text, "subdomains = 1", "subdomains = 8");
    serial_ = thermocontact(
        fmt::format("run {} --output {}", kCase.string(), (dir_ / "serial").string()));
    one_ = thermocontact(fmt::format("run {} --output {}", cut.string(), (dir_ / "np1").string()));
    // A clean environment: this process is an MPI singleton, and the launcher would take
    // its OMPI_/PMIX_ variables for a job it belongs to. CI runs as root (allowed here).
    two_ = run_command(
        fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                    "{} -n 2 {} run {} --output {}",
                    TC_MPIEXEC, TC_BINARY, cut.string(), (dir_ / "np2").string()));
  }
  /// (solves, iterations) of summary.json's "feti" entry.
  static std::pair<long, long> feti_counts(const std::string& summary) {
    auto number_after = [&](const std::string& key) {
      const auto p = summary.find(key, summary.find("\"feti\""));
      return p == std::string::npos ? -1L : std::stol(summary.substr(p + key.size()));
    };
    return {number_after("\"solves\": "), number_after("\"iterations\": ")};
  }
  static inline std::filesystem::path dir_;
  static inline CommandResult serial_, one_, two_;
};

TEST_F(FetiCli, TheCutRunReproducesTheSerialHistory) {
  ASSERT_EQ(serial_.exit_code, 0) << serial_.output;
  ASSERT_EQ(one_.exit_code, 0) << one_.output;
  const auto summary = read_file(dir_ / "np1/summary.json");
  EXPECT_NE(summary.find("\"subdomains\": 16"), std::string::npos) << summary;
  const auto a = read_history(dir_ / "serial/history.csv");
  const auto b = read_history(dir_ / "np1/history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_GT(column(a, "heat_generated").back(), 0.0);  // the run reached sliding
  // The 1e-6 for every physical column (largest seen: kinetic energy 5.5e-7; the heat
  // columns 7e-8 since the generated heat is the friction work λ_τᵀB_τΔu).
  for (const auto& [name, d] : column_differences(a, b)) EXPECT_LT(d, 1e-6) << name;
}

TEST_F(FetiCli, TwoRanksGiveTheOneRankHistory) {
  ASSERT_EQ(one_.exit_code, 0) << one_.output;
  ASSERT_EQ(two_.exit_code, 0) << two_.output;
  EXPECT_NE(read_file(dir_ / "np2/summary.json").find("\"ranks\": 2"), std::string::npos);
  const auto a = read_history(dir_ / "np1/history.csv");
  const auto b = read_history(dir_ / "np2/history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  // Two ranks sum F·x over their subdomains in another order: round-off only, which the
  // QP and coupling tolerances (1e-11, 1e-10) keep far below 1e-8.
  for (const auto& [name, d] : column_differences(a, b)) EXPECT_LT(d, 1e-8) << name;
  // Iterations: FETI's projected CG within ±2 per solve on average, the coupling within ±2 per
  // step. MPGP's counts follow the round-off of F (summed over the ranks in another order)
  // through its active-set decisions on the friction discs, and since the Tresca → Coulomb
  // updates are nested, through each update's QP tolerance, which follows the last fixed-point
  // residual (docs/choices.md): per step within 15 % (11.5 % seen, 218 against 193), over the
  // run within 2 % — except that one QP may crawl in one run and not in the other: MPGP's
  // fixed steps along friction circles (docs/choices.md, "QP") took 1127–1263 iterations at
  // step 26 in singleton runs of this case, before and after unrelated round-off changes, and
  // 261 at 2 ranks. So one step may leave the band, and the total is compared without it.
  const auto feti_one = feti_counts(read_file(dir_ / "np1/summary.json"));
  const auto feti_two = feti_counts(read_file(dir_ / "np2/summary.json"));
  ASSERT_GT(feti_one.first, 0);
  ASSERT_GT(feti_two.first, 0);
  const double mean_one = double(feti_one.second) / double(feti_one.first);
  const double mean_two = double(feti_two.second) / double(feti_two.first);
  EXPECT_GT(mean_one, 5.0);  // the count is real: a FETI solve takes tens of iterations
  EXPECT_NEAR(mean_one, mean_two, 2.0);
  const auto coupling_a = column(a, "coupling_iterations"),
             coupling_b = column(b, "coupling_iterations");
  const auto qp_a = column(a, "qp_iterations"), qp_b = column(b, "qp_iterations");
  size_t worst = 0, outside = 0;
  for (size_t k = 0; k < a.rows.size(); ++k) {
    EXPECT_NEAR(coupling_a[k], coupling_b[k], 2) << k;
    if (std::abs(qp_a[k] - qp_b[k]) > std::max(10.0, 0.15 * qp_a[k])) ++outside;
    if (std::abs(qp_a[k] - qp_b[k]) > std::abs(qp_a[worst] - qp_b[worst])) worst = k;
  }
  EXPECT_LE(outside, 1u) << "steps whose QP counts differ by more than 15 %";
  double total_a = 0, total_b = 0;
  for (size_t k = 0; k < qp_a.size(); ++k)
    if (k != worst) total_a += qp_a[k], total_b += qp_b[k];
  EXPECT_NEAR(total_a, total_b, 0.02 * total_a);
}

TEST(DirectCli, RanksShareTheFactorAndRepeatTheSerialHistory) {
  // Undecomposed bodies on N > 1 ranks: each body is factorised once by MUMPS over the ranks
  // (linalg::CholeskySolver, FactorRanks::all_ranks), and the rest is replicated. The factor is
  // another package's than the serial CHOLMOD one, so the histories differ by round-off carried
  // through the QPs' and the fixed points' stopping tests: issue 22 asks for the same history to
  // 1e-6 at 1, 2 and 4 ranks (differences_by_unit; 1e-11 seen on the coarse case to 0.3 s).
  // With a package that factorises on one rank (-tc_factor_package cholmod) every rank does the
  // serial arithmetic, bit for bit. The coarse ch. 7 case, first 0.1 s (the approach and the
  // impact, contact in the last steps). At 2 ranks here; 4 ranks oversubscribe the 2-core
  // machine (189 s of this test under load): direct_cli_ranks_slow.cpp (label slow).
  const auto dir = fresh_dir("direct-cli-ranks");
  const auto file = dir / "case.toml";
  std::ofstream(file) << replace_all(read_file(kCase), "end = 0.3", "end = 0.1");
  auto run = [&](int n, const std::string& options) {
    const auto out = dir / fmt::format("np{}{}", n, options.empty() ? "" : "-own");
    const auto r = run_command(
        fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                    "{} -n {} {} run {} --output {} {}",
                    TC_MPIEXEC, n, TC_BINARY, file.string(), out.string(), options));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return read_history(out / "history.csv");
  };
  const auto serial = run(1, "");
  ASSERT_GT(column(serial, "active_nodes").back(), 0.0);  // contact was reached
  for (const int n : {2}) {
    const auto spread = run(n, "");
    ASSERT_EQ(serial.rows.size(), spread.rows.size());
    for (const auto& [name, d] : differences_by_unit(serial, spread))
      EXPECT_LT(d, 1e-6) << name << " at " << n << " ranks";
  }
  const auto own = run(2, "-tc_factor_package cholmod");
  ASSERT_EQ(serial.rows.size(), own.rows.size());
  for (const auto& [name, d] : column_differences(serial, own))
    EXPECT_EQ(d, 0.0) << name << " at 2 ranks, each with its own factor";
  EXPECT_EQ(column(serial, "qp_iterations"), column(own, "qp_iterations"));
}

TEST(DirectCli, AFactorOverRanksThatFailsStopsEveryRankAndIsReportedOnce) {
  // MUMPS given 1 MB of work space per rank (ICNTL(23)) fails the same way on both ranks
  // (INFOG(1) = −19): one report, naming the package and MUMPS's code, exit code 1.
  const auto dir = fresh_dir("direct-cli-mumps-fails");
  const auto r = run_command(
      fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                  "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                  "{} -n 2 {} run {} --output {} -mat_mumps_icntl_23 1",
                  TC_MPIEXEC, TC_BINARY, kCase.string(), (dir / "out").string()));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const std::string what = "MUMPS Cholesky over 2 ranks failed (INFOG(1) = -19)";
  size_t count = 0;
  for (auto at = r.output.find(what); at != std::string::npos; at = r.output.find(what, at + 1))
    ++count;
  EXPECT_EQ(count, 1u) << r.output;
}

}  // namespace
}  // namespace tc::test
