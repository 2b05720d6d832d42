// [solver] contact_dual through the command line (issue 8): the quasistatic ch. 7.2.2 example
// with both bodies cut into 4 subdomains (tests/cases/feti/quasistatic.toml: pressing with
// friction 0.9, the contact sticking, interface and frictional heat on) run with the nested
// contact dual (DualContactSolver on each body's FETI) and the combined one (feti::ContactFeti,
// one SMALBE QP per Tresca bound), and the combined one at 2 ranks through the launcher.
// The case sets qp_tolerance 1e-10, coupling_tolerance 1e-8, feti_tolerance 1e-10.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

const std::filesystem::path kCase =
    std::filesystem::path(TC_SOURCE_DIR) / "tests/cases/feti/quasistatic.toml";

/// The integer after `key` in summary.json (−1 if absent).
long summary_integer(const std::string& summary, const std::string& key) {
  const auto p = summary.find("\"" + key + "\": ");
  return p == std::string::npos ? -1L : std::stol(summary.substr(p + key.size() + 4));
}

/// Every physical column of b within `tolerance` of a's peak (history.hpp's
/// column_differences), except the columns at round-off while the contact sticks (heat,
/// dissipation, thermal energy: ~1e-8 J), compared against the work the load does, 1e-9 of
/// its peak (573 J; seen 1.3e-8 J).
void expect_same_history(const History& a, const History& b, double tolerance) {
  double work = 0;
  for (const double w : column(a, "external_work")) work = std::max(work, std::abs(w));
  ASSERT_GT(work, 0.0);
  for (const auto& [name, d] : column_differences(a, b)) {
    const bool round_off =
        name.rfind("heat_", 0) == 0 || name == "frictional_dissipation" || name == "thermal_energy";
    if (!round_off) {
      EXPECT_LT(d, tolerance) << name;
      continue;
    }
    const auto va = column(a, name), vb = column(b, name);
    for (size_t k = 0; k < va.size(); ++k) EXPECT_LT(std::abs(va[k] - vb[k]), 1e-9 * work) << name;
  }
}

class FetiCombinedCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fresh_dir(fmt::format("feti-combined-{}", ::getpid()));
    const auto text = read_file(kCase);
    ASSERT_NE(text.find("contact_dual = \"nested\""), std::string::npos);
    const auto combined = dir_ / "combined.toml";
    std::ofstream(combined) << replace_all(text, "contact_dual = \"nested\"",
                                           "contact_dual = \"combined\"");
    const auto expansion = dir_ / "expansion.toml";
    ASSERT_NE(text.find("thermal_expansion = false"), std::string::npos);
    std::ofstream(expansion) << replace_all(text, "thermal_expansion = false",
                                            "thermal_expansion = true");
    nested_ = thermocontact(
        fmt::format("run {} --output {}", kCase.string(), (dir_ / "nested").string()));
    expansion_ = thermocontact(
        fmt::format("run {} --output {}", expansion.string(), (dir_ / "expansion").string()));
    one_ = thermocontact(
        fmt::format("run {} --output {}", combined.string(), (dir_ / "np1").string()));
    // A clean environment: this process is an MPI singleton, and the launcher would take its
    // OMPI_/PMIX_ variables for a job it belongs to. CI runs as root (allowed here).
    two_ = run_command(
        fmt::format("env -i PATH=/usr/bin:/bin HOME=/tmp OMPI_ALLOW_RUN_AS_ROOT=1 "
                    "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 "
                    "{} -n 2 {} run {} --output {}",
                    TC_MPIEXEC, TC_BINARY, combined.string(), (dir_ / "np2").string()));
  }
  static inline std::filesystem::path dir_;
  static inline CommandResult nested_, expansion_, one_, two_;
};

TEST_F(FetiCombinedCli, CombinedDualReproducesTheNestedHistory) {
  ASSERT_EQ(nested_.exit_code, 0) << nested_.output;
  ASSERT_EQ(one_.exit_code, 0) << one_.output;
  const auto sn = read_file(dir_ / "nested/summary.json");
  const auto sc = read_file(dir_ / "np1/summary.json");
  EXPECT_NE(sn.find("\"contact_dual\": \"nested\""), std::string::npos) << sn;
  EXPECT_NE(sc.find("\"contact_dual\": \"combined\""), std::string::npos) << sc;
  EXPECT_EQ(summary_integer(sn, "smalbe_outer_iterations"), 0);
  EXPECT_GT(summary_integer(sc, "smalbe_outer_iterations"), 0);
  const auto a = read_history(dir_ / "nested/history.csv");
  const auto b = read_history(dir_ / "np1/history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_GT(column(a, "contact_normal_force").back(), 0.0);  // the run reached contact
  ASSERT_GT(column(b, "friction_iterations").back(), 1.0);   // and the Coulomb loop ran
  // Both solve the same QPs to qp_tolerance 1e-10 (nested: ‖g^P‖ of the contact dual; combined:
  // ‖g^P‖ and ‖Gλ − e‖ of the whole dual), each within κ·1e-10 of the same minimiser with κ ≲
  // 1e3 (feti_contact_mpi_test), and the coupling loop stops at 1e-8: 1e-7 of each column's
  // peak (seen: 3e-9, the reactions). The heat columns and the dissipation are at round-off
  // (the contact sticks: ~1e-8 J of slip work, thermal energy 2.5e-8 J).
  expect_same_history(a, b, 1e-7);
  // The contact conditions the history shows: the same nodes in contact, none sliding, and
  // Σ w‖λ_τ‖ ≤ 𝔉 Σ w λ_n (node by node ‖λ_τ‖ ≤ 𝔉λ_n, which the QP's projection onto the
  // discs makes exact; 1e-12 for the sums' round-off). Penetration is checked on the rows in
  // feti_contact_mpi_test.
  const auto an = column(a, "active_nodes"), bn = column(b, "active_nodes");
  const auto normal = column(b, "contact_normal_force"),
             tangential = column(b, "contact_tangential_force");
  for (size_t k = 0; k < an.size(); ++k) {
    EXPECT_EQ(an[k], bn[k]) << k;
    EXPECT_LE(tangential[k], 0.9 * normal[k] * (1 + 1e-12)) << k;
  }
}

TEST_F(FetiCombinedCli, NestedWithThermalExpansionAtTheReferenceTemperature) {
  // Thermal expansion on, the temperature at θ_ref but for round-off (the contact sticks: the
  // frictional heat is ~1e-8 J). The load K_uθ(θ − θ_ref) is then at the round-off of the
  // data, and the slave, moved rigidly by its Dirichlet data before contact, used to stall
  // FETI's projected CG (3e-5 of the relative criterion after 1000 iterations: exit 1) —
  // docs/choices.md, FETI. The run must complete and give the history without expansion:
  // α E (θ − θ_ref) ≈ 1.2e-5 · 2e11 · 1e-10 K is ~1e-4 Pa against ~1e8 Pa of contact
  // pressure, so the physical columns agree to the coupling tolerance 1e-8 (1e-7 of each
  // peak, as above); the round-off columns (x reactions ~1e-4 N, heat ~1e-8 J) are left out.
  ASSERT_EQ(nested_.exit_code, 0) << nested_.output;
  ASSERT_EQ(expansion_.exit_code, 0) << expansion_.output;
  const auto a = read_history(dir_ / "nested/history.csv");
  const auto b = read_history(dir_ / "expansion/history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  ASSERT_GT(column(a, "contact_normal_force").back(), 0.0);
  const auto d = column_differences(a, b);
  for (const char* name :
       {"strain_energy", "external_work", "contact_normal_force", "contact_tangential_force",
        "reaction_slave_zmax_y", "reaction_slave_zmax_z", "reaction_master_zmin_z"})
    EXPECT_LT(d.at(name), 1e-7) << name;
}

TEST_F(FetiCombinedCli, TwoRanksGiveTheOneRankHistory) {
  ASSERT_EQ(one_.exit_code, 0) << one_.output;
  ASSERT_EQ(two_.exit_code, 0) << two_.output;
  const auto s1 = read_file(dir_ / "np1/summary.json");
  const auto s2 = read_file(dir_ / "np2/summary.json");
  EXPECT_NE(s2.find("\"ranks\": 2"), std::string::npos) << s2;
  const auto a = read_history(dir_ / "np1/history.csv");
  const auto b = read_history(dir_ / "np2/history.csv");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  // Two ranks sum F·x over their subdomains in another order: round-off, which SMALBE at
  // 1e-10 and the coupling at 1e-8 keep below 1e-8 of each column's peak — except the
  // round-off columns of the test above, compared against the load's work likewise.
  expect_same_history(a, b, 1e-8);
  // SMALBE's outer iterations over the run (10 steps, ~46 QPs): round-off can move an inner
  // solve's stop by an iteration and with it an M update, i.e. one outer iteration of a QP now
  // and then (seen: 138 against 141). The issue's ±2, taken per step on average, bounds the
  // total by 20; 5 % of it (7 here) is the tighter test used.
  const long o1 = summary_integer(s1, "smalbe_outer_iterations");
  const long o2 = summary_integer(s2, "smalbe_outer_iterations");
  EXPECT_GT(o1, 0);
  EXPECT_LE(std::abs(o1 - o2), std::max(2L, o1 / 20));
}

}  // namespace
}  // namespace tc::test
