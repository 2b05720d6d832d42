// Total FETI (6.2) against the undecomposed direct solve, and 1 rank against all ranks. Run at
// 1 and 2 ranks (label mpi): at 2 ranks the subdomains are dealt to both and every product
// with F is summed over them.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/physics/body/body_system.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

using physics::Scheme;

/// A thermo-elastic block: clamped at xmin, pulled and heated on xmax, heated inside, with
/// thermal expansion and thermoelastic heating on, so both fields and their coupling enter
/// every FETI solve.
physics::Problem heated_block(int dim, Scheme scheme, int subdomains) {
  const std::array<int, 3> cells =
      dim == 2 ? std::array<int, 3>{12, 6, 1} : std::array<int, 3>{6, 6, 6};
  auto p = box_problem(dim, {0.2, 0.1, 0.1}, cells, steel(), scheme, 1e-3, 3);
  p.physics.thermal_expansion = true;
  p.physics.thermoelastic_heating = true;
  p.bodies[0].subdomains = subdomains;
  p.bodies[0].heat_source = 5e7;
  p.boundaries.push_back(hold("xmin", {0, 1, 2}));
  physics::BoundaryCondition pull;
  pull.where = "xmax";
  pull.traction[0] = core::TimeTable(2e7);
  pull.traction[1] = core::TimeTable(-1e7);
  pull.heat_flux = core::TimeTable(1e5);
  p.boundaries.push_back(pull);
  physics::BoundaryCondition cold;
  cold.where = "ymin";
  cold.temperature = core::TimeTable(300.0);
  p.boundaries.push_back(cold);
  p.solver.feti_tolerance = 1e-12;
  return p;
}

double relative_difference(const core::Vector& a, const core::Vector& b) {
  auto d = a.clone();
  d.axpy(-1.0, b);
  return d.norm() / b.norm();
}

struct Case {
  int dim;
  Scheme scheme;
  int subdomains;
};

class Decomposed : public ::testing::TestWithParam<Case> {};

// The FETI solve stops when the gluing jumps and the Dirichlet misfit ‖Bu − c‖ fall below
// 1e-12 of ‖Pd‖; the primal error is that times the dual condition number (≤ 1e3 for these
// H/h), so 1e-8 — the acceptance bound — holds with margin after three steps.
TEST_P(Decomposed, GivesTheUndecomposedDisplacementAndTemperature) {
  const auto c = GetParam();
  const auto whole = heated_block(c.dim, c.scheme, 1);
  const auto cut = heated_block(c.dim, c.scheme, c.subdomains);
  physics::Simulation a(whole), b(cut);
  ASSERT_EQ(b.system(0).subdomains().size(), static_cast<size_t>(c.subdomains));
  for (int k = 0; k < 3; ++k) {
    a.advance();
    b.advance();
  }
  const double du = relative_difference(b.state(0).u, a.state(0).u);
  auto ta = a.state(0).theta.clone(), tb = b.state(0).theta.clone();
  ta.shift(-293.15);  // compare the temperature change, not the absolute value
  tb.shift(-293.15);
  const double dt = relative_difference(tb, ta);
  EXPECT_LT(du, 1e-8) << "displacement";
  EXPECT_LT(dt, 1e-8) << "temperature";
  EXPECT_GT(a.state(0).u.norm(), 0.0);
}

INSTANTIATE_TEST_SUITE_P(
    Feti, Decomposed,
    ::testing::Values(Case{2, Scheme::dynamic, 2}, Case{2, Scheme::quasistatic, 2},
                      Case{2, Scheme::quasistatic, 8}, Case{3, Scheme::dynamic, 2},
                      Case{3, Scheme::dynamic, 8}, Case{3, Scheme::dynamic, 27},
                      Case{3, Scheme::quasistatic, 2}, Case{3, Scheme::quasistatic, 8},
                      Case{3, Scheme::quasistatic, 27}),
    [](const auto& info) {
      return fmt::format("d{}_{}_{}", info.param.dim,
                         info.param.scheme == Scheme::dynamic ? "dynamic" : "quasistatic",
                         info.param.subdomains);
    });

/// K of a clamped 3D block by FETI on one rank (PETSC_COMM_SELF) and on all ranks.
struct RankRun {
  std::vector<double> x;
  int iterations;
};

RankRun solve_on(MPI_Comm comm, feti::Preconditioner pc) {
  const auto p = heated_block(3, Scheme::quasistatic, 27);
  const physics::BodySystem sys(p, 0);
  feti::FetiOptions o;
  o.comm = comm;
  o.tolerance = 1e-10;
  o.preconditioner = pc;
  const feti::Feti f(
      sys.subdomains(), sys.body().mesh.n_nodes(), 3, sys.u_dirichlet_dofs(), feti::Kernel::rigid,
      feti::Singular::yes, [&](int s) { return sys.subdomain_matrices(s).stiffness_u.copy(); }, o);
  core::Vector b(sys.n_u()), x(sys.n_u());
  sys.mechanical_load(0.0, b);
  f.solve(b, x);
  return {x.to_std(), f.statistics().last_iterations};
}

// Dealing the subdomains to the ranks changes only the order of the sums over subdomains:
// round-off, amplified by the CG recurrences over ≤ 100 iterations, stays far below 1e-9.
TEST(Feti, AllRanksGiveTheSingleRankSolution) {
  for (const auto pc : {feti::Preconditioner::lumped, feti::Preconditioner::dirichlet}) {
    const auto one = solve_on(PETSC_COMM_SELF, pc);
    const auto all = solve_on(PETSC_COMM_WORLD, pc);
    double diff = 0, norm = 0;
    for (size_t i = 0; i < one.x.size(); ++i) {
      diff = std::max(diff, std::abs(one.x[i] - all.x[i]));
      norm = std::max(norm, std::abs(one.x[i]));
    }
    EXPECT_LT(diff, 1e-9 * norm) << feti::name(pc);
    EXPECT_LE(std::abs(one.iterations - all.iterations), 2) << feti::name(pc);
  }
}

}  // namespace
}  // namespace tc::test
