// SMALBE (bound and equality constraints) on QPs with a known solution, on random SPD
// instances checked by the KKT conditions of the pair (λ, μ) computed independently of the
// solver (feasibility, Gλ = e, the natural residual ‖λ − P_Ω(λ − ∇L)‖ with ∇L = Fλ − d + Gᵀμ,
// complementarity, optimality against a known feasible point), and against projected CG (the
// FETI iteration on Ker G) when there are no bounds.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "support/qp_problems.hpp"
#include "tc/qp/smalbe.hpp"

namespace tc::test {
namespace {

using qp::Smalbe;
using qp::SmalbeOptions;

Eigen::MatrixXd dense(::Mat a) {
  PetscInt n = 0, m = 0;
  TC_PETSC(MatGetSize(a, &n, &m));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(n, m);
  for (PetscInt i = 0; i < n; ++i) {
    PetscInt nc = 0;
    const PetscInt* cols = nullptr;
    const double* vals = nullptr;
    TC_PETSC(MatGetRow(a, i, &nc, &cols, &vals));
    for (PetscInt k = 0; k < nc; ++k) out(i, cols[k]) = vals[k];
    TC_PETSC(MatRestoreRow(a, i, &nc, &cols, &vals));
  }
  return out;
}

core::Handle<::Mat, MatDestroy> matrix(const Eigen::MatrixXd& f) {
  core::Handle<::Mat, MatDestroy> a;
  const auto n = static_cast<PetscInt>(f.rows());
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, n, nullptr, a.out()));
  for (PetscInt i = 0; i < n; ++i)
    for (PetscInt j = 0; j < n; ++j) TC_PETSC(MatSetValue(a.get(), i, j, f(i, j), INSERT_VALUES));
  TC_PETSC(MatAssemblyBegin(a.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(a.get(), MAT_FINAL_ASSEMBLY));
  return a;
}

Eigen::VectorXd eigen(const core::Vector& v) {
  const auto s = v.to_std();
  return Eigen::Map<const Eigen::VectorXd>(s.data(), static_cast<Eigen::Index>(s.size()));
}

struct Kkt {
  double violation = 0;  // distance outside Ω
  double equality = 0;   // ‖Gλ − e‖
  double natural = 0;    // ‖λ − P_Ω(λ − ∇L)‖
  double objective = 0;  // f(λ)
};

Kkt check(::Mat f_mat, const qp::FeasibleSet& set, const Eigen::MatrixXd& g,
          const Eigen::VectorXd& e, const core::Vector& d, const core::Vector& x,
          const Eigen::VectorXd& mu) {
  const Eigen::MatrixXd f = dense(f_mat);
  const Eigen::VectorXd xe = eigen(x), de = eigen(d);
  const Eigen::VectorXd grad = f * xe - de + g.transpose() * mu;
  Kkt k;
  k.violation = set.violation(x);
  k.equality = (g * xe - e).norm();
  const Eigen::VectorXd step = xe - grad;
  auto y = core::Vector::from(std::vector<double>(step.data(), step.data() + step.size()));
  set.project(y);
  k.natural = (xe - eigen(y)).norm();
  k.objective = 0.5 * xe.dot(f * xe) - de.dot(xe);
  return k;
}

Eigen::SparseMatrix<double> sparse(const Eigen::MatrixXd& g) {
  return g.sparseView();
}

// ---------------------------------------------------------------- closed forms

TEST(Smalbe, EqualityAndBoundClosedForm) {
  // min ½‖λ‖² − dᵀλ, d = (1, 2, −1), λ₃ ≥ 0, λ₁ + λ₂ + λ₃ = 1. Without the bound λ = d − t𝟙
  // with t = 1/3 has λ₃ < 0; with λ₃ = 0 active, λ₁ + λ₂ = 1 gives λ = (0, 1, 0), μ = 1, and
  // ∇L = λ − d + μ𝟙 = (0, 0, 2) ≥ 0 on the active component: the KKT point.
  auto f = matrix(Eigen::MatrixXd::Identity(3, 3));
  qp::MatrixOperator op(f.get());
  core::Vector layout(3);
  qp::FeasibleSet set(layout);
  set.set_interval(2, {0.0, qp::infinity});
  const Eigen::MatrixXd g = Eigen::MatrixXd::Ones(1, 3);
  const auto d = core::Vector::from(std::vector<double>{1.0, 2.0, -1.0});
  core::Vector x(3);
  Eigen::VectorXd mu;
  SmalbeOptions o;
  o.rtol = o.equality_rtol = 1e-12;
  const auto r =
      Smalbe(op, set, sparse(g), Eigen::VectorXd::Ones(1), PETSC_COMM_SELF, o).solve(d, x, mu);
  ASSERT_TRUE(r.converged()) << r.message;
  const auto v = x.to_std();
  // ‖λ − λ*‖ ≤ ‖g^P‖/λ_min + ‖Gλ − e‖ with λ_min = 1, both ≤ 1e-12·‖d‖ ≈ 2.5e-12.
  EXPECT_NEAR(v[0], 0.0, 1e-11);
  EXPECT_NEAR(v[1], 1.0, 1e-11);
  EXPECT_NEAR(v[2], 0.0, 1e-11);
  EXPECT_NEAR(mu[0], 1.0, 1e-10);  // μ = d₂ − λ₂ to the same precision (a few operations)
}

TEST(Smalbe, EqualityAndDiscClosedForm) {
  // F = I, d = (3, 1, 2), disc ‖(λ₀, λ₁)‖ ≤ 1, equality λ₀ − λ₂ = 0. Eliminating λ₂ = λ₀:
  // min λ₀² − 5λ₀ + ½λ₁² − λ₁ on the unit disc, whose unconstrained minimiser (2.5, 1) is
  // outside; on the circle (cos θ, sin θ) the gradient (2c − 5, s − 1) is −ν(c, s), so
  // 5/c − 1/s = 1 (bisection below), λ = (c, s, c) and μ from ∇L₂ = λ₂ − d₂ − μ = 0.
  double lo = 1e-6, hi = M_PI / 2 - 1e-6;
  auto h = [](double t) { return 5 / std::cos(t) - 1 / std::sin(t) - 1; };
  for (int i = 0; i < 200; ++i) ((h(0.5 * (lo + hi)) > 0) ? hi : lo) = 0.5 * (lo + hi);
  const double th = 0.5 * (lo + hi), c = std::cos(th), s = std::sin(th);
  ASSERT_GT(5 / c - 2, 0);  // ν > 0: −∇ points outward, the circle is active

  auto f = matrix(Eigen::MatrixXd::Identity(3, 3));
  qp::MatrixOperator op(f.get());
  core::Vector layout(3);
  qp::FeasibleSet set(layout);
  set.add_disc({0, 1, {1.0}});
  Eigen::MatrixXd g(1, 3);
  g << 1, 0, -1;
  const auto d = core::Vector::from(std::vector<double>{3.0, 1.0, 2.0});
  core::Vector x(3);
  Eigen::VectorXd mu;
  SmalbeOptions o;
  o.rtol = o.equality_rtol = 1e-12;
  const auto r =
      Smalbe(op, set, sparse(g), Eigen::VectorXd::Zero(1), PETSC_COMM_SELF, o).solve(d, x, mu);
  ASSERT_TRUE(r.converged()) << r.message;
  const auto v = x.to_std();
  // As above: λ_min(F) = 1 and ‖d‖ ≈ 3.7, so the error is ≤ ~1e-11; bisection is exact to ulps.
  EXPECT_NEAR(v[0], c, 1e-10);
  EXPECT_NEAR(v[1], s, 1e-10);
  EXPECT_NEAR(v[2], c, 1e-10);
  EXPECT_NEAR(mu[0], c - 2, 1e-10);  // ∇L₂ = λ₂ − 2 − μ = 0 (Gᵀμ = (μ, 0, −μ))
}

// ---------------------------------------------------------------- random SPD, KKT

struct Case {
  const char* name;
  QpKind kind;
  PetscInt blocks;
  int rows;  // of G
};

/// A point of Ω that is not the minimiser over Ω: λ* (which is) moved randomly and projected.
/// e = G·it makes {λ ∈ Ω, Gλ = e} non-empty without making λ* feasible for the equality (with
/// e = Gλ* the equality would be inactive, μ = 0, and a wrong μ would go unnoticed).
core::Vector feasible_point(const QpProblem& p, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  auto y = p.x_star.clone();
  {
    auto v = y.view();
    for (PetscInt i = 0; i < y.local_size(); ++i) v[i] += u(rng);
  }
  p.set.project(y);
  return y;
}

/// k dense random rows with entries in (−1, 1) (a coarse space couples many multipliers).
Eigen::MatrixXd random_rows(int k, Eigen::Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd g(k, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (int i = 0; i < k; ++i) g(i, j) = u(rng);
  return g;
}

class RandomKkt : public ::testing::TestWithParam<Case> {};

TEST_P(RandomKkt, SatisfiesKktAndBeatsAFeasiblePoint) {
  const auto c = GetParam();
  auto p = random_qp(PETSC_COMM_SELF, c.blocks, c.kind, 100.0, 0.5, 0.1, 99 + c.blocks);
  const Eigen::Index n = p.d.size();
  const Eigen::MatrixXd g = random_rows(c.rows, n, 7 + c.rows);
  const auto y = feasible_point(p, c.blocks);
  const Eigen::VectorXd e = g * eigen(y);
  qp::MatrixOperator op(p.f.get());
  SmalbeOptions o;
  o.rtol = 1e-10;
  o.equality_rtol = 1e-10;
  core::Vector x = p.d.duplicate();
  Eigen::VectorXd mu;
  const auto r = Smalbe(op, p.set, sparse(g), e, PETSC_COMM_SELF, o).solve(p.d, x, mu);
  ASSERT_TRUE(r.converged()) << r.message;
  const auto k = check(p.f.get(), p.set, g, e, p.d, x, mu);
  const double dn = p.d.norm();
  EXPECT_LE(k.violation, 1e-14);  // iterates are projected or snapped onto the set
  // ‖G̃λ − ẽ‖ ≤ 1e-10‖d‖/λ_max, and ‖G‖ ≤ √(k n) for entries in (−1, 1): ‖Gλ − e‖ ≤ that
  // times ‖G‖, with λ_max ≥ 1 here (diagonal ≥ shift + degree); 1e-7‖d‖ is the margin.
  EXPECT_LE(k.equality, 1e-7 * dn);
  // The natural residual is bounded componentwise by g^P (|min(x − lo, g)| ≤ |β|, the
  // disc's likewise), and ‖g^P‖ ≤ 1e-10‖d‖ at the returned μ: 1e-9 is the margin.
  EXPECT_LE(k.natural, 1e-9 * dn);
  // y is feasible: the minimiser cannot be worse (up to the equality's round-off, which
  // moves f by ‖∇f‖·‖Gλ − e‖/σ_min(G)).
  const Kkt star = check(p.f.get(), p.set, g, e, p.d, y, Eigen::VectorXd::Zero(c.rows));
  EXPECT_GT(mu.norm(), 1e-3);  // the equality is active: y ≠ λ*
  EXPECT_LE(k.objective, star.objective + 1e-8 * std::abs(star.objective));
  EXPECT_GT(r.outer_iterations, 0);
  EXPECT_GE(r.operator_applications, r.inner_iterations);
}

INSTANTIATE_TEST_SUITE_P(Smalbe, RandomKkt,
                         ::testing::Values(Case{"lower_one_row", QpKind::lower, 200, 1},
                                           Case{"lower_six_rows", QpKind::lower, 500, 6},
                                           Case{"box", QpKind::box, 300, 4},
                                           Case{"disc", QpKind::disc, 200, 3},
                                           Case{"contact3d", QpKind::contact3d, 150, 6}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Smalbe, ComplementarityOfTheBounds) {
  // λ ≥ 0 with its multiplier ∇L_i: at the solution λ_i ∇L_i = 0 and ∇L_i ≥ 0 on every
  // component (checked one by one, not through a norm).
  auto p = random_qp(PETSC_COMM_SELF, 300, QpKind::lower, 100.0, 0.5, 0.0, 4242);
  const Eigen::MatrixXd g = random_rows(4, p.d.size(), 11);
  const Eigen::VectorXd e = g * eigen(feasible_point(p, 11));
  qp::MatrixOperator op(p.f.get());
  SmalbeOptions o;
  o.rtol = o.equality_rtol = 1e-11;
  core::Vector x = p.d.duplicate();
  Eigen::VectorXd mu;
  const auto r = Smalbe(op, p.set, sparse(g), e, PETSC_COMM_SELF, o).solve(p.d, x, mu);
  ASSERT_TRUE(r.converged()) << r.message;
  const Eigen::VectorXd xe = eigen(x);
  const Eigen::VectorXd grad = dense(p.f.get()) * xe - eigen(p.d) + g.transpose() * mu;
  const double scale = p.d.norm();
  for (Eigen::Index i = 0; i < xe.size(); ++i) {
    // |g^P_i| ≤ 1e-11‖d‖: a free component has |∇L_i| below it, an active one ∇L_i ≥ −it.
    EXPECT_GE(grad[i], -1e-9 * scale) << i;
    EXPECT_LE(std::abs(xe[i] * grad[i]), 1e-9 * scale * (1 + std::abs(xe[i]))) << i;
  }
}

// ---------------------------------------------------------------- no bounds: projected CG

TEST(Smalbe, AgreesWithProjectedCgWithoutBounds) {
  auto p = random_qp(PETSC_COMM_SELF, 400, QpKind::free, 100.0, 0.0, 0.0, 31);
  const Eigen::Index n = p.d.size();
  const Eigen::MatrixXd g = random_rows(5, n, 5);
  const Eigen::VectorXd e = Eigen::VectorXd::LinSpaced(5, -1.0, 1.0);
  const Eigen::MatrixXd f = dense(p.f.get());
  const Eigen::VectorXd d = eigen(p.d);
  // The FETI iteration (6.2): CG on P F P from λ₀ = Gᵀ(GGᵀ)⁻¹e, P = I − Gᵀ(GGᵀ)⁻¹G.
  const Eigen::LLT<Eigen::MatrixXd> ggt(g * g.transpose());
  auto project = [&](const Eigen::VectorXd& v) -> Eigen::VectorXd {
    return v - g.transpose() * ggt.solve(g * v);
  };
  Eigen::VectorXd lam = g.transpose() * ggt.solve(e);
  Eigen::VectorXd rr = project(d - f * lam), pp = rr;
  for (int it = 0; it < 2000 && rr.norm() > 1e-15 * d.norm(); ++it) {
    const Eigen::VectorXd fp = project(f * pp);
    const double a = rr.squaredNorm() / pp.dot(fp);
    lam += a * pp;
    const Eigen::VectorXd rn = rr - a * fp;
    pp = rn + (rn.squaredNorm() / rr.squaredNorm()) * pp;
    rr = rn;
  }
  qp::MatrixOperator op(p.f.get());
  SmalbeOptions o;
  o.rtol = o.equality_rtol = 1e-11;
  core::Vector x = p.d.duplicate();
  Eigen::VectorXd mu;
  const auto r = Smalbe(op, p.set, sparse(g), e, PETSC_COMM_SELF, o).solve(p.d, x, mu);
  ASSERT_TRUE(r.converged()) << r.message;
  // κ(F) ≤ 100 on Ker G: the error is ≤ κ·1e-11 relative, plus the equality residual; 1e-8.
  EXPECT_LE((eigen(x) - lam).norm(), 1e-8 * lam.norm());
  // μ from the Lagrange condition Fλ − d + Gᵀμ = 0 by least squares on the projected CG λ.
  const Eigen::VectorXd mu_ref = ggt.solve(g * (d - f * lam));
  EXPECT_LE((mu - mu_ref).norm(), 1e-7 * mu_ref.norm());  // one more factor ‖F‖/σ(G)
}

TEST(Smalbe, RhoUpdateReachesTheSameSolution) {
  auto p = random_qp(PETSC_COMM_SELF, 200, QpKind::lower, 100.0, 0.5, 0.0, 17);
  const Eigen::MatrixXd g = random_rows(3, p.d.size(), 3);
  const Eigen::VectorXd e = g * eigen(feasible_point(p, 3));
  qp::MatrixOperator op(p.f.get());
  SmalbeOptions o;
  o.rtol = o.equality_rtol = 1e-11;
  core::Vector x1 = p.d.duplicate(), x2 = p.d.duplicate();
  Eigen::VectorXd mu1, mu2;
  const auto r1 = Smalbe(op, p.set, sparse(g), e, PETSC_COMM_SELF, o).solve(p.d, x1, mu1);
  o.update = qp::SmalbeUpdate::rho;
  o.m_factor = 1.0;  // a small M forces updates, so that the ρ branch runs
  const auto r2 = Smalbe(op, p.set, sparse(g), e, PETSC_COMM_SELF, o).solve(p.d, x2, mu2);
  ASSERT_TRUE(r1.converged()) << r1.message;
  ASSERT_TRUE(r2.converged()) << r2.message;
  x2.axpy(-1.0, x1);
  // Strictly convex: one minimiser; two solves to 1e-11 with κ ≤ 100 agree to ~1e-9.
  EXPECT_LE(x2.norm(), 1e-8 * x1.norm());
  EXPECT_GT(r2.updates, 0);
}

}  // namespace
}  // namespace tc::test
