// ContactLaws (physics/contact/contact_laws.hpp): the checks after every step stop a step whose
// multipliers or displacements leave the bounds the solvers guarantee, naming the node, the
// step and the setting; within the bounds they record the worst.
#include "tc/physics/contact/contact_laws.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "tc/core/error.hpp"

namespace {

using tc::physics::ContactLaws;
using tc::physics::PairLaws;

/// Two 3D contact nodes (slave nodes 7 and 9), weights 0.5, 𝔉 = 0.4 on the Tresca bound
/// 𝔉γ = 0.4 × 10, QP gradient tolerance 1e-8 per node.
struct TwoNodes {
  std::vector<int> nodes{7, 9};
  std::vector<double> weights{0.5, 0.5};
  std::vector<double> targets{1e-3, 0, 0, 2e-3, 0, 0};
  std::vector<double> bu{1e-3, 0, 0, 2e-3, 0, 0};  // gap 0 at both
  std::vector<double> lambda{10, 4, 0, 10, 0, 3};  // node 7 on its circle, node 9 inside
  std::vector<double> friction{0.4, 0.4}, bound{4, 4}, tolerance{1e-8, 1e-8};
  [[nodiscard]] PairLaws laws() const {
    return {.name = "",
            .dim = 3,
            .nodes = nodes,
            .weights = weights,
            .targets = targets,
            .constraint_values = bu,
            .lambda = lambda,
            .friction = friction,
            .qp_bound = bound,
            .gap_tolerance = tolerance,
            .held = {}};
  }
};

// ‖λ‖ = √(100 + 16 + 100 + 9) = 15; coupling tolerance 1e-6: the cone's bound is
// 𝔉 tol ‖λ‖ = 6e-6 plus round-off.
constexpr double lambda_norm = 15, tol = 1e-6, qp_tol = 1e-8;

TEST(ContactLaws, WithinTheBoundsTheWorstIsRecorded) {
  TwoNodes t;
  ContactLaws laws;
  EXPECT_NO_THROW(laws.check(t.laws(), 1.0, tol, lambda_norm, qp_tol, 3));
  // Node 7 lies on its cone exactly: violation 0 of a bound 6e-6.
  EXPECT_EQ(laws.cone.value, 0.0);
  EXPECT_NEAR(laws.cone.bound, 0.4 * tol * lambda_norm, 1e-12);
  EXPECT_EQ(laws.gap.value, -0.0);
  EXPECT_EQ(laws.gap.step, 3);
  EXPECT_GE(laws.gap.node, 7);
}

TEST(ContactLaws, APenetrationBeyondTheQpBoundStopsTheStep) {
  TwoNodes t;
  t.bu[3] += 1e-7;  // node 9 penetrates by 1e-7 (weighted), ≫ 2 × 1e-8 + round-off
  ContactLaws laws;
  try {
    laws.check(t.laws(), 1.0, tol, lambda_norm, qp_tol, 5);
    FAIL() << "no error";
  } catch (const tc::NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("penetrates"), std::string::npos) << m;
    EXPECT_NE(m.find("slave node 9"), std::string::npos) << m;
    EXPECT_NE(m.find("[solver] qp_tolerance"), std::string::npos) << m;
    // Factorised bodies: their solves leave nothing that feti_tolerance would change.
    EXPECT_EQ(m.find("feti_tolerance"), std::string::npos) << m;
  }
  EXPECT_NEAR(laws.gap.value, 1e-7 / 0.5, 1e-15);  // per unit weight: a length
  EXPECT_GT(laws.gap.ratio, 1.0);
  EXPECT_EQ(laws.gap.node, 9);
  EXPECT_EQ(laws.gap.step, 5);
}

TEST(ContactLaws, AFetiBodysMisfitWidensThePenetrationBound) {
  // The same penetration (2e-7 per unit weight) with a body solved by FETI whose step left a
  // misfit of 1e-7 m: the bound grows by 10 × 1e-7 (feti_misfit_factor), and it holds.
  TwoNodes t;
  t.bu[3] += 1e-7;
  auto p = t.laws();
  p.solve_error = ContactLaws::feti_misfit_factor * 1e-7;
  p.feti_tolerance = 1e-10;
  ContactLaws laws;
  EXPECT_NO_THROW(laws.check(p, 1.0, tol, lambda_norm, qp_tol, 5));
  EXPECT_NEAR(laws.gap.bound, 2 * 1e-8 / 0.5 + 1e-6, 1e-12);
  EXPECT_LT(laws.gap.ratio, 1.0);
  // Beyond it the message names both settings.
  t.bu[3] += 1e-6;
  p = t.laws();
  p.solve_error = ContactLaws::feti_misfit_factor * 1e-7;
  p.feti_tolerance = 1e-10;
  try {
    laws.check(p, 1.0, tol, lambda_norm, qp_tol, 6);
    FAIL() << "no error";
  } catch (const tc::NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("[solver] feti_tolerance (now 1e-10)"), std::string::npos) << m;
  }
}

TEST(ContactLaws, AConeViolationBeyondTheFixedPointBoundStopsTheStep) {
  TwoNodes t;
  t.lambda[0] = 9;  // ‖λ_τ‖ = 4 > 𝔉λ_n = 3.6 at node 7: 0.4 ≫ 6e-6
  ContactLaws laws;
  try {
    laws.check(t.laws(), 2.0, tol, lambda_norm, qp_tol, 4);
    FAIL() << "no error";
  } catch (const tc::NumericalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("friction cone"), std::string::npos) << m;
    EXPECT_NE(m.find("slave node 7"), std::string::npos) << m;
    EXPECT_NE(m.find("[solver] coupling_tolerance"), std::string::npos) << m;
  }
  EXPECT_NEAR(laws.cone.value, 2.0 * 0.4, 1e-12);  // in traction units (2 per multiplier)
}

TEST(ContactLaws, ALooseCouplingToleranceDoesNotWidenTheCone) {
  // With coupling_tolerance 1e-2 the fixed point leaves |γ − λ_n| up to 1e-2 ‖λ‖ = 0.15: a
  // cone bound of 𝔉 tol ‖λ‖ = 0.06 would pass node 7's ‖λ_τ‖ − 𝔉λ_n = 0.04. The bound stays
  // that of 1e-6 (ContactLaws::cone_tolerance): the multipliers are scaled into the cone
  // before the check (ContactCoupling::scale_into_cones), so what is left is a defect.
  TwoNodes t;
  t.lambda[0] = 9.9;  // ‖λ_τ‖ = 4 > 𝔉λ_n = 3.96
  ContactLaws laws;
  EXPECT_THROW(laws.check(t.laws(), 1.0, 1e-2, lambda_norm, qp_tol, 4), tc::NumericalError);
  EXPECT_NEAR(laws.cone.bound, 0.4 * ContactLaws::cone_tolerance * lambda_norm, 1e-12);
}

TEST(ContactLaws, AReleasedNodeIsNotACone) {
  TwoNodes t;
  t.lambda = {-1, 0, 0, 10, 0, 3};  // node 7 below 0 (a QP's tolerance), no λ_τ: its cone is
  ContactLaws laws;                 // that of max(λ_n, 0) = 0, which λ_τ = 0 obeys
  EXPECT_NO_THROW(laws.check(t.laws(), 1.0, tol, lambda_norm, qp_tol, 2));
  t.lambda = {-1, 1e-3, 0, 10, 0, 3};  // and any λ_τ there is a violation
  EXPECT_THROW(laws.check(t.laws(), 1.0, tol, lambda_norm, qp_tol, 2), tc::NumericalError);
}

}  // namespace
