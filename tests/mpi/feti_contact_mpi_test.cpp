// The combined TFETI contact dual (feti::ContactFeti: gluing, Dirichlet and contact
// multipliers in one QP, SMALBE) against the nested form (physics::DualContactSolver on each
// body's FETI) on the two steel blocks, frictionless and with a Tresca bound; and 1 rank
// against all ranks. Run at 1 and 2 ranks (label mpi).
#include <gtest/gtest.h>

#include <cmath>

#include "../bench/support/two_block_feti.hpp"

namespace tc::test {
namespace {

double max_abs_diff(const core::Vector& a, const core::Vector& b) {
  auto d = a.clone();
  d.axpy(-1.0, b);
  return d.max_abs();
}

feti::ContactFetiOptions smalbe(double rtol, bool lumped = false) {
  feti::ContactFetiOptions o;
  o.smalbe.rtol = rtol;
  o.smalbe.equality_rtol = rtol;
  o.lumped_preconditioner = lumped;
  return o;
}

/// The contact conditions of (λ, u) checked on the rows, independently of either solver:
/// λ_n ≥ 0, B_n u ≤ c_n, λ_n (B_n u − c_n) = 0, ‖λ_τ‖ ≤ bound.
struct Contact {
  double min_normal = 0, max_penetration = 0, complementarity = 0, friction_excess = 0;
};
Contact contact_conditions(const bench::TwoBlockFeti& p, const bench::ContactSolution& s) {
  const auto& rows = p.rows();
  core::Vector bu(rows.n_rows());
  rows.slave.mult(s.u_slave, bu);
  rows.master.mult_add(s.u_master, bu);
  const auto b = bu.to_std(), l = s.lambda.to_std();
  Contact c;
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) {
    const auto i = static_cast<size_t>(3 * k);
    const double gap = rows.gap[static_cast<size_t>(k)];
    c.min_normal = std::min(c.min_normal, l[i]);
    c.max_penetration = std::max(c.max_penetration, b[i] - gap);
    c.complementarity = std::max(c.complementarity, std::abs(l[i] * (b[i] - gap)));
    c.friction_excess = std::max(c.friction_excess, std::hypot(l[i + 1], l[i + 2]) -
                                                        p.friction_bound()[static_cast<size_t>(k)]);
  }
  return c;
}

std::vector<double> tresca_bound(const bench::ContactSolution& frictionless, double f) {
  const auto l = frictionless.lambda.to_std();
  std::vector<double> b(l.size() / 3);
  for (size_t k = 0; k < b.size(); ++k) b[k] = f * std::max(l[3 * k], 0.0);
  return b;
}

// 4³ cells per block, 2³ subdomains each (H/h = 2): 75 contact rows, the whole interface
// pressed. The nested form is the reference: its FETI solves stop at 1e-10 of the dual
// residual and its QP at 1e-10‖d‖; SMALBE at 1e-10‖d‖ (gradient) and 1e-10‖d‖/λ_max (G).
// Both are then within κ·1e-10 of the same minimiser, κ the condition number of the
// respective dual operator on the face (≲ 1e3 here: F_c of the contact rows alone is a dense
// compliance, the combined F on Ker G has κ ∼ H/h times the contact rows' scale spread), so
// 1e-6 relative in u and λ (with ‖·‖∞) leaves margin for both.
TEST(ContactFeti, AgreesWithTheNestedForm) {
  bench::TwoBlockFeti p(4, 2, PETSC_COMM_WORLD);
  for (const double f : {0.0, 0.3}) {
    qp::QpResult rn;
    if (f > 0) {
      p.set_friction_bound(std::vector<double>(static_cast<size_t>(p.rows().n_nodes()), 0.0));
      auto frictionless = p.nested(1e-10, rn);
      p.set_friction_bound(tresca_bound(frictionless, f));
    } else {
      p.set_friction_bound(std::vector<double>(static_cast<size_t>(p.rows().n_nodes()), 0.0));
    }
    qp::SmalbeResult rc;
    const auto combined = p.combined(smalbe(1e-10), rc);
    ASSERT_TRUE(rc.converged()) << rc.message;
    // Both operators of the nested form: explicit (from the bodies' compliances, the default
    // at 75 rows) and matrix-free (two FETI solves per application).
    for (const PetscInt limit : {PetscInt{1500}, PetscInt{0}}) {
      physics::DualContactSettings settings;
      settings.explicit_limit = limit;
      const auto nested = p.nested(1e-10, rn, settings);
      ASSERT_TRUE(rn.converged()) << rn.message;
      const double du = std::max(max_abs_diff(combined.u_slave, nested.u_slave),
                                 max_abs_diff(combined.u_master, nested.u_master));
      const double un = std::max(nested.u_slave.max_abs(), nested.u_master.max_abs());
      EXPECT_LT(du, 1e-6 * un) << "𝔉 = " << f << ", explicit limit " << limit;
      EXPECT_LT(max_abs_diff(combined.lambda, nested.lambda), 1e-6 * nested.lambda.max_abs())
          << "𝔉 = " << f << ", explicit limit " << limit;
      EXPECT_GT(nested.lambda.max_abs(), 0.0);
    }
    const double un = std::max(combined.u_slave.max_abs(), combined.u_master.max_abs());
    const double lmax = combined.lambda.max_abs();
    // The combined solution on its own: equilibrium K u + B_cᵀλ = f on the free dofs (the
    // gluing is in u being one field per body) and the contact conditions on the rows. SMALBE
    // stops at ‖g^P‖ ≤ 1e-10‖d‖, g = −(B u − c) on the rows: penetration and complementarity
    // to 1e-8 of ‖u‖∞·weight (B carries the nodal weights) and of that times ‖λ‖∞; the
    // equilibrium to 1e-8 of the largest nodal force, λ_max·weight (FETI's primal solves).
    const double w = p.rows().weights.front();
    const auto cc = contact_conditions(p, combined);
    EXPECT_GE(cc.min_normal, 0.0);
    EXPECT_LT(cc.max_penetration, 1e-8 * un * w);
    EXPECT_LT(cc.complementarity, 1e-8 * un * w * lmax);
    EXPECT_LT(cc.friction_excess, 1e-12 * lmax);  // the set is projected onto exactly
    EXPECT_LT(p.equilibrium_residual(combined), 1e-8 * lmax * w);
    if (core::PetscSession::rank() == 0)
      std::printf("𝔉 = %.1f: nested %d MPGP its; combined: %s\n", f, rn.iterations,
                  rc.message.c_str());
  }
}

// Dealing the subdomains to the ranks changes only the order of the sums over subdomains;
// SMALBE's active-set decisions could amplify that round-off, so the iteration counts may
// differ by a few and u agree to the solver tolerance: 1e-8 relative.
TEST(ContactFeti, AllRanksGiveTheSingleRankSolution) {
  bench::TwoBlockFeti one(4, 2, PETSC_COMM_SELF), all(4, 2, PETSC_COMM_WORLD);
  qp::SmalbeResult r1, r2;
  const auto a = one.combined(smalbe(1e-10), r1);
  const auto b = all.combined(smalbe(1e-10), r2);
  ASSERT_TRUE(r1.converged()) << r1.message;
  ASSERT_TRUE(r2.converged()) << r2.message;
  const double un = std::max(a.u_slave.max_abs(), a.u_master.max_abs());
  EXPECT_LT(std::max(max_abs_diff(a.u_slave, b.u_slave), max_abs_diff(a.u_master, b.u_master)),
            1e-8 * un);
  EXPECT_LE(std::abs(r1.inner_iterations - r2.inner_iterations), 5);
}

// Warm start (ContactFetiState, the simulation's Coulomb updates and steps): the same solve
// started from its own solution (gluing, Dirichlet and contact λ, μ) is at the KKT point
// already. SMALBE's first outer iteration then finds ‖g^P‖ and ‖Gλ − e‖ within the tolerance:
// one outer iteration (≤ 2 allowed: the restarted inner solve may take one more step at the
// bound's edge), and applications of F only for the gradient evaluations (λ_max reused by
// the same ContactFeti: no Lanczos run), against hundreds cold.
TEST(ContactFeti, WarmStartFromItsOwnSolutionStopsAtOnce) {
  bench::TwoBlockFeti p(4, 2, PETSC_COMM_WORLD);
  p.set_friction_bound(std::vector<double>(static_cast<size_t>(p.rows().n_nodes()), 0.0));
  qp::QpResult rn;
  p.set_friction_bound(tresca_bound(p.nested(1e-10, rn), 0.3));
  const auto& rows = p.rows();
  const feti::ContactFeti cf(p.slave_feti(), p.master_feti(), rows.slave, rows.master, rows.dim);
  const auto& targets = p.targets();
  const auto& bs = p.b_slave();
  const auto& bm = p.b_master();
  auto xs = p.x_slave().clone(), xm = p.x_master().clone();
  core::Vector lambda(rows.n_rows());
  feti::ContactFetiState state;
  const auto cold =
      cf.solve(bs, bm, targets, p.friction_bound(), xs, xm, lambda, smalbe(1e-10), &state);
  ASSERT_TRUE(cold.converged()) << cold.message;
  const int cold_applications = cf.statistics().applications;
  EXPECT_EQ(state.body.size(), cf.n_multipliers() - cf.n_contact());
  EXPECT_EQ(state.mu.size(), cf.coarse_dimension());
  const auto u_cold = xs.clone();
  const auto warm =
      cf.solve(bs, bm, targets, p.friction_bound(), xs, xm, lambda, smalbe(1e-10), &state);
  ASSERT_TRUE(warm.converged()) << warm.message;
  EXPECT_LE(warm.outer_iterations, 2) << warm.message;
  EXPECT_LE(cf.statistics().applications, 10) << warm.message;
  EXPECT_GT(cold_applications, 50);  // the comparison means something
  EXPECT_LT(max_abs_diff(u_cold, xs), 1e-8 * u_cold.max_abs());
  if (core::PetscSession::rank() == 0)
    std::printf("cold: %d applications (%s); warm: %d (%s)\n", cold_applications,
                cold.message.c_str(), cf.statistics().applications, warm.message.c_str());
}

}  // namespace
}  // namespace tc::test
