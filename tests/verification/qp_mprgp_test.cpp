// MPRGP/MPGP against QPs whose solution is known by construction (tests/support/
// qp_problems.hpp), and the KKT conditions checked independently of the solver's own
// gradient splitting: feasibility, the natural residual ‖x − P(x − g)‖ and complementarity.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "support/qp_problems.hpp"
#include "tc/qp/mpgp.hpp"

namespace tc::test {
namespace {

using qp::QpOptions;

struct Outcome {
  qp::QpResult result;
  double error = 0;            // ‖x − x*‖∞
  double residual = 0;         // ‖x − P(x − g)‖₂ with g = Fx − d recomputed
  double violation = 0;        // distance outside the set
  double complementarity = 0;  // |Σ (x − x_proj_bound)·g| over the active blocks, see below
};

Outcome solve(QpProblem& p, QpOptions opt = {}) {
  qp::MatrixOperator f(p.f.get());
  Outcome o;
  core::Vector x = p.x_star.duplicate();
  o.result = qp::Mpgp(f, p.set, opt).solve(p.d, x);
  core::Vector g = x.duplicate(), y = x.duplicate(), e = x.clone();
  f.apply(x, g);
  g.axpy(-1.0, p.d);
  y.copy_from(x);
  y.axpy(-1.0, g);
  p.set.project(y);
  y.axpy(-1.0, x);
  o.residual = y.norm();
  e.axpy(-1.0, p.x_star);
  o.error = e.max_abs();
  o.violation = p.set.violation(x);
  // xᵀg − x*ᵀg: at the solution ⟨g, x' − x⟩ ≥ 0 ∀x' ∈ Ω; with x' = x* it is ≈ 0 when x ≈ x*.
  o.complementarity = std::abs(x.dot(g) - p.x_star.dot(g));
  return o;
}

// ---------------------------------------------------------------- small, known solutions

struct Case {
  const char* name;
  QpKind kind;
  double active;
  double degenerate;
};

class KnownSolution : public ::testing::TestWithParam<Case> {};

TEST_P(KnownSolution, ReachesTheSolutionBuiltIn) {
  const auto c = GetParam();
  auto p = random_qp(PETSC_COMM_SELF, 12, c.kind, 100.0, c.active, c.degenerate, 7);
  QpOptions opt;
  opt.rtol = 1e-12;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  // ‖x − x*‖ ≲ κ ‖g^P‖/λ_max-scale: κ ≤ 100 and ‖g^P‖ ≤ 1e-12 ‖d‖ with ‖d‖, ‖x*‖ = O(1..10)
  // leave 1e-9; 1e-8 is the margin.
  EXPECT_LT(o.error, 1e-8);
  // Iterates are projected or snapped; a disc projection lands on r to a few ulps.
  EXPECT_LE(o.violation, 1e-14);
  EXPECT_LT(o.residual, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Qp, KnownSolution,
                         ::testing::Values(Case{"all_free", QpKind::free, 0.0, 0.0},
                                           Case{"all_active", QpKind::lower, 1.0, 0.0},
                                           Case{"none_active", QpKind::lower, 0.0, 0.0},
                                           Case{"mixed", QpKind::lower, 0.5, 0.0},
                                           Case{"degenerate", QpKind::lower, 0.6, 0.5},
                                           Case{"box_2d_friction", QpKind::box, 0.5, 0.0},
                                           Case{"box_all_at_bounds", QpKind::box, 1.0, 0.0},
                                           Case{"disc_mixed", QpKind::disc, 0.5, 0.0},
                                           Case{"disc_on_circle", QpKind::disc, 1.0, 0.0},
                                           Case{"disc_inside", QpKind::disc, 0.0, 0.0},
                                           Case{"disc_degenerate", QpKind::disc, 1.0, 0.5},
                                           Case{"contact_3d", QpKind::contact3d, 0.5, 0.0}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Qp, DiscAtItsCentreWithZeroRadius) {
  // One disc of radius 0 (γ = 0: a node out of contact has no friction): x = 0 whatever d.
  core::Vector layout(2);
  qp::FeasibleSet set(layout);
  set.add_disc({0, 1, {0.0}});
  core::Handle<::Mat, MatDestroy> a;
  TC_PETSC(MatCreateSeqAIJ(PETSC_COMM_SELF, 2, 2, 2, nullptr, a.out()));
  const PetscInt idx[2] = {0, 1};
  const double vals[4] = {2, 1, 1, 3};
  TC_PETSC(MatSetValues(a.get(), 2, idx, 2, idx, vals, INSERT_VALUES));
  TC_PETSC(MatAssemblyBegin(a.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(a.get(), MAT_FINAL_ASSEMBLY));
  qp::MatrixOperator f(a.get());
  const auto d = core::Vector::from(std::vector<double>{3.0, -4.0});
  core::Vector x = core::Vector::from(std::vector<double>{1.0, 1.0});
  const auto r = qp::Mpgp(f, set, {}).solve(d, x);
  ASSERT_TRUE(r.converged()) << r.message;
  EXPECT_EQ(x.max_abs(), 0.0);
}

TEST(Qp, TwoVariablesOnTheCircleClosedForm) {
  // F = I, d outside the unit disc: the solution is the projection d/‖d‖ (exactly).
  core::Vector layout(2);
  qp::FeasibleSet set(layout);
  set.add_disc({0, 1, {1.0}});
  core::Handle<::Mat, MatDestroy> a;
  TC_PETSC(MatCreateConstantDiagonal(PETSC_COMM_SELF, 2, 2, 2, 2, 1.0, a.out()));
  qp::MatrixOperator f(a.get());
  const auto d = core::Vector::from(std::vector<double>{3.0, 4.0});
  core::Vector x(2);
  QpOptions opt;
  opt.rtol = 1e-14;
  const auto r = qp::Mpgp(f, set, opt).solve(d, x);
  ASSERT_TRUE(r.converged()) << r.message;
  const auto v = x.to_std();
  EXPECT_NEAR(v[0], 0.6, 1e-13);  // round-off of a few operations on O(1) numbers
  EXPECT_NEAR(v[1], 0.8, 1e-13);
}

// ------------------------------------------------------------- KKT at sizes 10 … 10⁴

struct KktCase {
  QpKind kind;
  PetscInt blocks;
};

class Kkt : public ::testing::TestWithParam<KktCase> {};

TEST_P(Kkt, RandomSpdInstance) {
  const auto c = GetParam();
  auto p = random_qp(PETSC_COMM_SELF, c.blocks, c.kind, 1e3, 0.5, 0.1, 1234 + c.blocks);
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.max_iterations = 20000;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  const double tol = o.result.tolerance;
  EXPECT_LE(o.result.projected_gradient, tol);
  EXPECT_LE(o.violation, 1e-14);  // a few ulps of the radius (discs), see KnownSolution
  // The natural residual is bounded by ‖g^P‖ (componentwise for intervals and discs); the
  // recomputed gradient differs from the updated one by round-off of ~iterations·ε‖d‖.
  EXPECT_LE(o.residual, 2 * tol + 1e-13 * p.d.norm());
  // κ ≤ 1e3 and ‖g^P‖ ≤ 1e-10‖d‖: the error in x is ≲ κ ‖g^P‖/λ_max ~ 1e-7·‖x*‖-scale.
  EXPECT_LT(o.error, 1e-6);
  EXPECT_LT(o.complementarity, 1e-6 * p.d.norm());
}

std::vector<KktCase> kkt_cases() {
  std::vector<KktCase> out;
  for (const auto k : {QpKind::lower, QpKind::box, QpKind::disc, QpKind::contact3d})
    for (const PetscInt n : {10, 100, 1000, 10000}) out.push_back({k, n / block_size(k) + 1});
  return out;
}

const char* kind_name(QpKind k) {
  switch (k) {
    case QpKind::free:
      return "free";
    case QpKind::lower:
      return "lower";
    case QpKind::box:
      return "box";
    case QpKind::disc:
      return "disc";
    case QpKind::contact3d:
      return "contact3d";
  }
  return "?";
}

INSTANTIATE_TEST_SUITE_P(Qp, Kkt, ::testing::ValuesIn(kkt_cases()), [](const auto& info) {
  return std::string(kind_name(info.param.kind)) + "_" +
         std::to_string(info.param.blocks * block_size(info.param.kind));
});

// ------------------------------------------------------------------ options and failures

TEST(Qp, FullGradientExpansionReachesTheSameSolution) {
  auto p = random_qp(PETSC_COMM_SELF, 500, QpKind::contact3d, 1e3, 0.5, 0.0, 99);
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.expansion = qp::Expansion::full_gradient;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  EXPECT_LT(o.error, 1e-6);  // as in Kkt
}

// Every strategy of QpOptions (expansion length, the move on circles, the proportioning test,
// projected-CG expansions) must reach the same known solution with the same KKT quality: the
// longer moves are safeguarded (kept only if f falls), never trusted.
struct StrategyCase {
  const char* name;
  void (*set)(QpOptions&);
};

const StrategyCase strategies[] = {
    {"cauchy_length",
     [](QpOptions& o) {
       o.expansion_step = qp::ExpansionStep::cauchy;
       o.arc_step = qp::ExpansionStep::cauchy;
     }},
    {"bb_length",
     [](QpOptions& o) {
       o.expansion_step = qp::ExpansionStep::barzilai_borwein;
       o.arc_step = qp::ExpansionStep::barzilai_borwein;
     }},
    {"free_gradient_test",
     [](QpOptions& o) { o.proportioning_test = qp::ProportioningTest::free; }},
    {"projected_cg", [](QpOptions& o) { o.expansion = qp::Expansion::projected_cg; }},
    {"projected_cg_gamma4",
     [](QpOptions& o) {
       o.expansion = qp::Expansion::projected_cg;
       o.gamma = 4;
     }},
    {"lambda_deferred",
     [](QpOptions& o) { o.eigenvalue_estimate = qp::EigenvalueEstimate::deferred; }},
    {"slide_on_circles", [](QpOptions& o) { o.circle_face = qp::CircleFace::slide; }},
    {"slide_bb_length",
     [](QpOptions& o) {
       o.circle_face = qp::CircleFace::slide;
       o.expansion_step = qp::ExpansionStep::barzilai_borwein;
       o.arc_step = qp::ExpansionStep::barzilai_borwein;
     }},
};

class Strategy : public ::testing::TestWithParam<std::tuple<QpKind, int>> {};

TEST_P(Strategy, ReachesTheKnownSolution) {
  const auto [kind, which] = GetParam();
  auto p = random_qp(PETSC_COMM_SELF, 1000 / block_size(kind), kind, 1e3, 0.5, 0.1, 4321);
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.max_iterations = 20000;
  strategies[which].set(opt);
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  // The same bounds as Kkt (same κ ≤ 1e3 and rtol).
  EXPECT_LE(o.violation, 1e-14);
  EXPECT_LE(o.residual, 2 * o.result.tolerance + 1e-13 * p.d.norm());
  EXPECT_LT(o.error, 1e-6);
  EXPECT_LT(o.complementarity, 1e-6 * p.d.norm());
  // Every projected-CG expansion is either kept or undone (then the standard one follows).
  if (opt.expansion == qp::Expansion::projected_cg && kind == QpKind::lower) {
    EXPECT_EQ(o.result.long_expansions + o.result.fallbacks, o.result.expansion_steps);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Qp, Strategy,
    ::testing::Combine(::testing::Values(QpKind::lower, QpKind::box, QpKind::disc,
                                         QpKind::contact3d),
                       ::testing::Range(0, static_cast<int>(std::size(strategies)))),
    [](const auto& info) {
      return std::string(kind_name(std::get<0>(info.param))) + "_" +
             strategies[std::get<1>(info.param)].name;
    });

TEST(Qp, LongExpansionMovesAreTakenAndRejected) {
  // On an ill-conditioned instance the Barzilai–Borwein length ≫ ᾱ: some moves lower f and
  // are kept, others raise it and fall back to ᾱ. Both branches must occur here, or the
  // option is not exercised (a regression to "always ᾱ" would pass the KKT checks above).
  auto p = random_qp(PETSC_COMM_SELF, 2000, QpKind::contact3d, 1e5, 0.5, 0.0, 17);
  QpOptions opt;
  opt.rtol = 1e-8;
  opt.max_iterations = 50000;
  opt.expansion_step = qp::ExpansionStep::barzilai_borwein;
  opt.arc_step = qp::ExpansionStep::barzilai_borwein;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  EXPECT_GT(o.result.long_expansions, 0);
  EXPECT_GT(o.result.fallbacks, 0);
  EXPECT_LT(o.error, 1e-3);  // κ ≤ 1e5, rtol 1e-8: ≲ κ·rtol-scale
}

/// y = diag(F)⁻¹ x: Jacobi, the simplest preconditioner in face.
class Jacobi final : public qp::LinearOperator {
 public:
  explicit Jacobi(::Mat a) {
    ::Vec v = nullptr;
    TC_PETSC(MatCreateVecs(a, &v, nullptr));
    inv_ = core::Vector::adopt(v);
    TC_PETSC(MatGetDiagonal(a, inv_.get()));
    TC_PETSC(VecReciprocal(inv_.get()));
  }
  void apply(const core::Vector& x, core::Vector& y) const override {
    TC_PETSC(VecPointwiseMult(y.get(), inv_.get(), x.get()));
  }
  [[nodiscard]] core::Vector make_vector() const override { return inv_.duplicate(); }

 private:
  core::Vector inv_;
};

TEST(Qp, PreconditioningInFaceHelpsABadlyScaledProblem) {
  // D F D with D spanning two decades: Jacobi undoes most of the scaling.
  auto p = random_qp(PETSC_COMM_SELF, 2000, QpKind::lower, 1e2, 0.5, 0.0, 5);
  core::Vector s = p.d.duplicate();
  {
    auto v = s.view();
    for (PetscInt i = 0; i < s.local_size(); ++i) v[i] = std::pow(10.0, std::sin(0.37 * i));
  }
  TC_PETSC(MatDiagonalScale(p.f.get(), s.get(), s.get()));
  // With y = D⁻¹x the solution x* maps to D⁻¹x* and bounds at 0 stay at 0; rebuild d.
  TC_PETSC(VecPointwiseDivide(p.x_star.get(), p.x_star.get(), s.get()));
  TC_PETSC(VecPointwiseMult(p.g_star.get(), p.g_star.get(), s.get()));
  TC_PETSC(MatMult(p.f.get(), p.x_star.get(), p.d.get()));
  p.d.axpy(-1.0, p.g_star);

  QpOptions plain;
  plain.rtol = 1e-9;
  plain.max_iterations = 50000;
  const auto a = solve(p, plain);
  Jacobi jacobi(p.f.get());
  QpOptions pre = plain;
  pre.preconditioner = &jacobi;
  const auto b = solve(p, pre);
  ASSERT_TRUE(a.result.converged()) << a.result.message;
  ASSERT_TRUE(b.result.converged()) << b.result.message;
  EXPECT_LT(b.result.operator_applications, a.result.operator_applications / 2)
      << "plain " << a.result.operator_applications << ", Jacobi in face "
      << b.result.operator_applications;
  // x* has entries up to 1e2·O(1): the relative accuracy of Kkt (1e-6) on that scale.
  EXPECT_LT(b.error, 1e-6 * p.x_star.max_abs());
}

// ------------------------------------------- friction discs, badly scaled (issue 4, MPGP)

/// The Jacobi change of variables of QpOptions::scaling for an explicit F.
core::Vector jacobi_scaling(const QpProblem& p) {
  core::Vector diagonal = p.d.duplicate();
  TC_PETSC(MatGetDiagonal(p.f.get(), diagonal.get()));
  return p.set.jacobi_scaling(diagonal);
}

/// scaled_disc_qp: 3D contact nodes (free multiplier, λ_n ≥ 0, friction disc) scaled by one
/// factor per node so that κ(F) ≤ κ; x* known by construction. 150 nodes = 600 variables:
/// small enough that even the unpreconditioned runs take well under a second.
struct DiscCase {
  double kappa;
  bool scaled;  // Jacobi change of variables (QpOptions::scaling)
  bool slide;   // QpOptions::circle_face = slide
};

class ScaledDiscs : public ::testing::TestWithParam<DiscCase> {};

TEST_P(ScaledDiscs, KktAndTheKnownSolution) {
  const auto c = GetParam();
  auto p = scaled_disc_qp(150, c.kappa, 0.5, 2026);
  const core::Vector s = jacobi_scaling(p);
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.max_iterations = 200000;
  if (c.scaled) opt.scaling = &s;
  if (c.slide) opt.circle_face = qp::CircleFace::slide;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  // The stopping test is on the original variables' ‖g^P‖ even when the solver works in
  // scaled ones (a test on ĝ^P = S g^P alone would be off by up to max s_i = 1/√min F_ii).
  EXPECT_LE(o.result.projected_gradient, o.result.tolerance);
  EXPECT_LE(o.residual, 2 * o.result.tolerance + 1e-13 * p.d.norm());  // as in Kkt
  // Discs are projected onto radius r/s_b: a few ulps of r, r ≤ 1.
  EXPECT_LE(o.violation, 1e-14);
  // ‖x − x*‖ ≤ ‖g^P‖/λ_min-scale: λ_min(F) ≥ λ_max/κ, ‖g^P‖ ≤ 1e-10‖d‖ and ‖d‖ ≲ λ_max‖x*‖
  // give ‖x − x*‖ ≲ κ·1e-10·‖x*‖-scale, i.e. 1e-6 and 1e-4 of max|x*| at κ 1e4 and 1e6
  // (x* has entries up to 1 in the unscaled variables, up to 10^(½·log10(κ/10)) here).
  const double scale = p.x_star.max_abs();
  EXPECT_LT(o.error, c.kappa * 1e-10 * scale) << "‖x*‖∞ = " << scale;
  EXPECT_LT(o.complementarity, c.kappa * 1e-10 * p.d.norm());
}

INSTANTIATE_TEST_SUITE_P(Qp, ScaledDiscs,
                         ::testing::Values(DiscCase{1e4, false, false}, DiscCase{1e4, true, false},
                                           DiscCase{1e6, true, false}, DiscCase{1e4, false, true},
                                           DiscCase{1e6, false, true}, DiscCase{1e6, true, true}),
                         [](const auto& info) {
                           return std::string(info.param.kappa < 1e5 ? "kappa1e4" : "kappa1e6") +
                                  (info.param.scaled ? "_jacobi_variables" : "_plain") +
                                  (info.param.slide ? "_slide" : "");
                         });

TEST(Qp, SlidingOnCirclesCutsTheDiscWork) {
  // CircleFace::slide keeps CG running while nodes slide along their circles; with the
  // chopped tangent (the default) 91–99 % of the steps are proportioning or projected moves.
  // bench/qp measured 7438 → 639 at 250 nodes, κ ≤ 1e4; a regression that dropped the
  // tangent from φ, or the retraction, would fall back to the default's count.
  auto p = scaled_disc_qp(150, 1e4, 0.5, 2026);
  QpOptions chopped;
  chopped.rtol = 1e-8;
  chopped.max_iterations = 200000;
  QpOptions slide = chopped;
  slide.circle_face = qp::CircleFace::slide;
  const auto a = solve(p, chopped);
  const auto b = solve(p, slide);
  ASSERT_TRUE(a.result.converged()) << a.result.message;
  ASSERT_TRUE(b.result.converged()) << b.result.message;
  EXPECT_GT(b.result.slides, 0);
  EXPECT_LT(b.result.operator_applications, a.result.operator_applications / 3)
      << "chopped " << a.result.operator_applications << ", slide "
      << b.result.operator_applications;
}

TEST(Qp, ChangeOfVariablesCutsTheDiscWork) {
  // The point of QpOptions::scaling: on a per-node scaled instance the Jacobi variables undo
  // the scaling (κ 1e4 → ≈ 10), so MPGP needs a fraction of the plain run's applications. A
  // regression that ignored `scaling` (or applied it only in the face) would fail here.
  auto p = scaled_disc_qp(150, 1e4, 0.5, 2026);
  const core::Vector s = jacobi_scaling(p);
  QpOptions plain;
  plain.rtol = 1e-8;
  plain.max_iterations = 200000;
  QpOptions scaled = plain;
  scaled.scaling = &s;
  const auto a = solve(p, plain);
  const auto b = solve(p, scaled);
  ASSERT_TRUE(a.result.converged()) << a.result.message;
  ASSERT_TRUE(b.result.converged()) << b.result.message;
  EXPECT_LT(b.result.operator_applications, a.result.operator_applications / 5)
      << "plain " << a.result.operator_applications << ", Jacobi variables "
      << b.result.operator_applications;
}

TEST(Qp, ChangeOfVariablesOnEverySetKind) {
  // Bounds, boxes, discs, 3D contact nodes, with a scaling that is not Jacobi (a smooth
  // pattern in [1/2, 2], one factor per block, so κ grows by 16 at most and the instances stay
  // easy): the same known solution and KKT quality as Kkt, so the scaled set, operator,
  // gradient and stopping test are consistent.
  for (const auto kind : {QpKind::lower, QpKind::box, QpKind::disc, QpKind::contact3d}) {
    auto p = random_qp(PETSC_COMM_SELF, 400 / block_size(kind), kind, 1e3, 0.5, 0.1, 77);
    core::Vector s = p.d.duplicate();
    {
      auto v = s.view();
      const PetscInt bs = block_size(kind);
      for (PetscInt i = 0; i < s.local_size(); ++i)
        v[i] = std::pow(2.0, std::sin(0.37 * static_cast<double>(i / bs)));
    }
    QpOptions opt;
    opt.rtol = 1e-10;
    opt.max_iterations = 50000;
    opt.scaling = &s;
    const auto o = solve(p, opt);
    ASSERT_TRUE(o.result.converged()) << kind_name(kind) << ": " << o.result.message;
    EXPECT_LE(o.violation, 1e-14) << kind_name(kind);
    EXPECT_LE(o.residual, 2 * o.result.tolerance + 1e-13 * p.d.norm()) << kind_name(kind);
    EXPECT_LT(o.error, 1e-6) << kind_name(kind);  // κ ≤ 1e3, rtol 1e-10: as in Kkt
  }
}

TEST(Qp, ReportsNonConvergenceWithItsNumbers) {
  auto p = random_qp(PETSC_COMM_SELF, 1000, QpKind::lower, 1e4, 0.5, 0.0, 3);
  QpOptions opt;
  opt.max_iterations = 5;
  const auto o = solve(p, opt);
  EXPECT_EQ(o.result.status, qp::QpStatus::max_iterations);
  EXPECT_EQ(o.result.iterations, 5);
  EXPECT_GT(o.result.projected_gradient, o.result.tolerance);
  EXPECT_NE(o.result.message.find("5 iterations"), std::string::npos) << o.result.message;
}

TEST(Qp, StopsOnAnIndefiniteOperator) {
  core::Handle<::Mat, MatDestroy> a;
  TC_PETSC(MatCreateConstantDiagonal(PETSC_COMM_SELF, 4, 4, 4, 4, -1.0, a.out()));
  qp::MatrixOperator f(a.get());
  core::Vector x(4);
  qp::FeasibleSet set(x);
  const auto d = core::Vector::from(std::vector<double>{1, 2, 3, 4});
  QpOptions opt;
  opt.max_eigenvalue = 1.0;  // the estimate of an indefinite F is meaningless
  const auto r = qp::Mpgp(f, set, opt).solve(d, x);
  EXPECT_EQ(r.status, qp::QpStatus::breakdown);
  EXPECT_FALSE(r.message.empty());
}

/// diag(1, 2, …, 1000): λ_max = 1000, a spectrum Lanczos must resolve at its upper end.
core::Handle<::Mat, MatDestroy> diagonal_1_to_1000() {
  const PetscInt n = 1000;
  core::Handle<::Mat, MatDestroy> a;
  TC_PETSC(MatCreateSeqAIJ(PETSC_COMM_SELF, n, n, 1, nullptr, a.out()));
  for (PetscInt i = 0; i < n; ++i) TC_PETSC(MatSetValue(a.get(), i, i, i + 1.0, INSERT_VALUES));
  TC_PETSC(MatAssemblyBegin(a.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(a.get(), MAT_FINAL_ASSEMBLY));
  return a;
}

TEST(Qp, LanczosBracketsTheLargestEigenvalue) {
  // diag(1, …, 1000): λ_max = 1000; 20 Lanczos steps find it to far better than 1 %.
  const auto a = diagonal_1_to_1000();
  const auto est = qp::estimate_max_eigenvalue(qp::MatrixOperator(a.get()), 20);
  EXPECT_LE(est.ritz, 1000.0 * (1 + 1e-12));  // a Ritz value never exceeds λ_max
  EXPECT_GE(est.bound, 1000.0 * (1 - 1e-3));
  EXPECT_LT(est.bound, 1000.0 * 1.01);
  EXPECT_EQ(est.applications, 20);
}

TEST(Qp, LanczosStopsOnceTheBoundIsWithinTolerance) {
  // diag(1, …, 1000) again: with a 5 % tolerance the estimate stops as soon as the residual
  // bound is within 5 % of the Ritz value, before the 20 steps, and still brackets: the Ritz
  // value is below λ_max = 1000 and the bound at most 5 % above it.
  const auto a = diagonal_1_to_1000();
  const auto est = qp::estimate_max_eigenvalue(qp::MatrixOperator(a.get()), 20, 0.05);
  EXPECT_LT(est.applications, 20);
  EXPECT_LE(est.ritz, 1000.0 * (1 + 1e-12));
  EXPECT_LE(est.bound, 1.05 * est.ritz);
  EXPECT_GT(est.bound, est.ritz);
}

// ------------------------------------------------- λ_max deferred (EigenvalueEstimate)

/// λ_max(F) to 1e-6 relative: 300 Lanczos steps without early stop on n ≤ 1000 (the bound
/// ritz + residual; the residual of a converged Ritz pair is far below 1e-6·λ).
double reference_max_eigenvalue(::Mat f) {
  const auto est = qp::estimate_max_eigenvalue(qp::MatrixOperator(f), 300, 1e-9);
  return est.bound;
}

TEST(Qp, DeferredEstimateIsNotPaidWithoutExpansions) {
  // No constraints: CG alone, never an expansion step, so ᾱ is never needed and no
  // application of F goes to λ_max (the up-front estimate pays for it anyway).
  auto p = random_qp(PETSC_COMM_SELF, 500, QpKind::free, 1e3, 0.0, 0.0, 11);
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.eigenvalue_estimate = qp::EigenvalueEstimate::deferred;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  EXPECT_EQ(o.result.expansion_steps, 0);
  EXPECT_EQ(o.result.estimate_applications, 0);
  EXPECT_EQ(o.result.max_eigenvalue, 0.0);
  EXPECT_LT(o.error, 1e-6);  // κ ≤ 1e3, rtol 1e-10, as in Kkt

  opt.eigenvalue_estimate = qp::EigenvalueEstimate::upfront;
  const auto u = solve(p, opt);
  ASSERT_TRUE(u.result.converged()) << u.result.message;
  EXPECT_GT(u.result.estimate_applications, 0);
  EXPECT_EQ(u.result.operator_applications,
            o.result.operator_applications + u.result.estimate_applications);
}

TEST(Qp, EstimateFromTheConjugateGradientsBracketsTheFace) {
  // Bounds with expansions: ᾱ comes from the CG run before the first expansion (its
  // Lanczos tridiagonal, continued in that face while the bound is loose). That is λ_max of
  // a face, at most λ_max(F): the Ritz value is below it and the bound at most
  // lanczos_tolerance above the Ritz value, so ≤ 1.05 λ_max(F) (+ the reference's 1e-6).
  // It must cost fewer applications than the up-front estimate on F, and the solve must
  // meet the same KKT bounds as Kkt.
  auto p = random_qp(PETSC_COMM_SELF, 1000, QpKind::lower, 1e3, 0.5, 0.1, 4321);
  const double lambda = reference_max_eigenvalue(p.f.get());
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.max_iterations = 20000;
  opt.eigenvalue_estimate = qp::EigenvalueEstimate::deferred;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  ASSERT_GT(o.result.expansion_steps, 0);
  EXPECT_TRUE(o.result.face_eigenvalue);
  EXPECT_EQ(o.result.reestimates, 0);
  EXPECT_GT(o.result.max_eigenvalue, 0.0);
  EXPECT_LE(o.result.max_eigenvalue, 1.05 * lambda * (1 + 1e-6));
  EXPECT_LE(o.residual, 2 * o.result.tolerance + 1e-13 * p.d.norm());
  EXPECT_LT(o.error, 1e-6);
  EXPECT_LT(o.complementarity, 1e-6 * p.d.norm());

  opt.eigenvalue_estimate = qp::EigenvalueEstimate::upfront;
  const auto u = solve(p, opt);
  ASSERT_TRUE(u.result.converged()) << u.result.message;
  EXPECT_FALSE(u.result.face_eigenvalue);
  EXPECT_LT(o.result.estimate_applications, u.result.estimate_applications);
}

TEST(Qp, AnUnderestimatedEigenvalueIsReplacedByAFullEstimate) {
  // λ_max given 10× too small (ᾱ = 19/λ_max, far outside (0, 2/λ_max]): an expansion raises
  // f, which triggers one full Lanczos estimate on F (not a cascade of halvings), after
  // which ᾱ = 1.9/bound with bound ≥ the Ritz value of F. The solution is still reached.
  auto p = random_qp(PETSC_COMM_SELF, 1000, QpKind::lower, 1e3, 0.5, 0.1, 4321);
  const double lambda = reference_max_eigenvalue(p.f.get());
  QpOptions opt;
  opt.rtol = 1e-10;
  opt.max_iterations = 20000;
  opt.max_eigenvalue = 0.1 * lambda;
  const auto o = solve(p, opt);
  ASSERT_TRUE(o.result.converged()) << o.result.message;
  EXPECT_EQ(o.result.reestimates, 1);
  EXPECT_EQ(o.result.step_halvings, 0);
  EXPECT_FALSE(o.result.face_eigenvalue);
  EXPECT_GT(o.result.estimate_applications, 0);
  // A full estimate with lanczos_tolerance 0.05: Ritz value ≥ 0.5 λ_max on any start vector
  // with weight on the top eigenvectors is far below what Lanczos gives after ≥ 2 steps;
  // 0.9 is the margin used here (the estimate tests above find it within 1 %).
  EXPECT_GE(o.result.max_eigenvalue, 0.9 * lambda);
  EXPECT_LT(o.error, 1e-6);
}

/// F of `p` as a dense matrix whose strictly lower triangle is NaN: any read of it shows.
core::Handle<::Mat, MatDestroy> upper_triangle_only(const QpProblem& p) {
  core::Handle<::Mat, MatDestroy> a;
  TC_PETSC(MatConvert(p.f.get(), MATSEQDENSE, MAT_INITIAL_MATRIX, a.out()));
  PetscScalar* v = nullptr;
  PetscInt n = 0, ld = 0;
  TC_PETSC(MatGetSize(a.get(), &n, nullptr));
  TC_PETSC(MatDenseGetLDA(a.get(), &ld));
  TC_PETSC(MatDenseGetArray(a.get(), &v));
  for (PetscInt j = 0; j < n; ++j)
    for (PetscInt i = j + 1; i < n; ++i) v[j * ld + i] = std::nan("");
  TC_PETSC(MatDenseRestoreArray(a.get(), &v));
  return a;
}

TEST(Qp, SymmetricDenseOperatorReadsTheUpperTriangleOnly) {
  // The product with the upper triangle equals the general product of the full F: the same
  // sums in another order, so within n·ε·‖F‖‖x‖ (n = 300, ε = 2.2e-16: 7e-14; 1e-12 leaves
  // the margin). A read of the NaN lower triangle would make the difference NaN.
  auto p = random_qp(PETSC_COMM_SELF, 300, QpKind::contact3d, 1e3, 0.5, 0.0, 99);
  const auto a = upper_triangle_only(p);
  const qp::SymmetricDenseOperator sym(a.get());
  const qp::MatrixOperator full(p.f.get());
  core::Vector x = p.x_star.clone(), y1 = x.duplicate(), y2 = sym.make_vector();
  full.apply(x, y1);
  sym.apply(x, y2);
  ASSERT_TRUE(y2.all_finite());
  y2.axpy(-1.0, y1);
  EXPECT_LT(y2.max_abs(), 1e-12 * y1.max_abs());
}

TEST(Qp, MpgpOnTheSymmetricDenseOperatorReachesTheSolution) {
  // The contact QP (bounds and friction discs) with F stored as the explicit dual operators
  // are: the same tolerance argument as KnownSolution (κ ≤ 100, rtol 1e-12).
  auto p = random_qp(PETSC_COMM_SELF, 120, QpKind::contact3d, 100.0, 0.5, 0.0, 7);
  const auto a = upper_triangle_only(p);
  const qp::SymmetricDenseOperator f(a.get());
  QpOptions opt;
  opt.rtol = 1e-12;
  core::Vector x = p.x_star.duplicate();
  const auto r = qp::Mpgp(f, p.set, opt).solve(p.d, x);
  ASSERT_TRUE(r.converged()) << r.message;
  x.axpy(-1.0, p.x_star);
  EXPECT_LT(x.max_abs(), 1e-8);
}

}  // namespace
}  // namespace tc::test
