// The shared part of qp_tao_test.cpp (the small instances, default suite) and qp_tao_slow.cpp
// (the large ones, label slow): each lists its instances and instantiates AgreesWithTao.
//
// MPRGP against PETSc TAO (TAOBQPIP, TAOGPCG, TAOBLMVM) on bound-constrained QPs with a known
// solution (tests/support/qp_problems.hpp): both reach the KKT point, and the two solutions
// agree within the distance that their measured residuals allow (error bound below).
//
// The error bound. F is SPD with μ = λ_min(F) ≥ shift and L = λ_max(F) ≤ ‖F‖_∞ (random_qp
// builds ‖F‖_∞ = 2·max degree + shift exactly, so μ ≥ ‖F‖_∞/κ_bound). For the natural
// residual r(x) = x − P(x − g(x)/L), g = Fx − d, of a μ-strongly monotone, L-Lipschitz affine
// variational inequality over a convex set (Pang 1987; Facchinei & Pang 2003, Prop. 6.3.1,
// applied to the operator g/L):
//     ‖x − x*‖ ≤ (1 + L/L)/(μ/L) ‖r(x)‖ = 2 (L/μ) ‖r(x)‖ ≤ 2 κ_bound ‖r(x)‖.
// MPRGP, GPCG and BLMVM stop on a projected gradient ‖g^P‖ ≤ ε = rtol‖d‖, and ‖r‖ ≤ ‖g^P‖/L
// componentwise, so each solution is within 2κ ε/L of x* and two of them within 4κ ε/L of
// each other (BQPIP stops on its own measure; its bound on ‖r‖ is derived below). The test
// asserts the sharper a-posteriori form with the measured residuals, which
// fails if either solver stops away from the solution whatever its own stopping measure says.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "support/qp_problems.hpp"
#include "support/tao_qp.hpp"
#include "tc/qp/mpgp.hpp"

namespace tc::test {
namespace {

/// The KKT measures of x, computed from F, d and the bounds only (not from any solver).
struct Kkt {
  double violation = 0;        // largest distance outside [l, u]
  double residual = 0;         // ‖x − P(x − g/L)‖₂
  double complementarity = 0;  // Σ_i (x_i − l_i) g_i⁺ + (u_i − x_i) g_i⁻ over finite bounds
  double complementarity_bound = 0;  // what the residual allows for it (see below)
  double error = 0;                  // ‖x − x*‖∞
};

Kkt kkt(const QpProblem& p, const core::Vector& lower, const core::Vector& upper, double lip,
        const core::Vector& x) {
  core::Vector g = x.duplicate();
  TC_PETSC(MatMult(p.f.get(), x.get(), g.get()));
  g.axpy(-1.0, p.d);
  Kkt k;
  const auto xs = x.to_std(), gs = g.to_std(), ls = lower.to_std(), us = upper.to_std(),
             xstar = p.x_star.to_std();
  double r2 = 0, r1 = 0, scale = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    const bool has_l = ls[i] > PETSC_NINFINITY, has_u = us[i] < PETSC_INFINITY;
    const double lo = has_l ? ls[i] : -qp::infinity, hi = has_u ? us[i] : qp::infinity;
    k.violation = std::max({k.violation, lo - xs[i], xs[i] - hi});
    const double r = xs[i] - std::clamp(xs[i] - gs[i] / lip, lo, hi);
    r2 += r * r;
    // |r_i| = min(x_i − l_i, g_i/L) when g_i > 0 (and symmetrically at u), so each product
    // (x_i − l_i)·g_i ≤ max(x_i − l_i, g_i/L)·L|r_i|: complementarity ≤ L·D·‖r‖₁ with D the
    // largest of those distances and scaled gradients.
    if (gs[i] > 0 && has_l) {
      k.complementarity += (xs[i] - lo) * gs[i];
      scale = std::max({scale, xs[i] - lo, gs[i] / lip});
    }
    if (gs[i] < 0 && has_u) {
      k.complementarity += (hi - xs[i]) * -gs[i];
      scale = std::max({scale, hi - xs[i], -gs[i] / lip});
    }
    r1 += std::abs(r);
    k.error = std::max(k.error, std::abs(xs[i] - xstar[i]));
  }
  k.residual = std::sqrt(r2);
  // r_i is computed as x_i − clamp(x_i − g_i/L): a g_i/L below half an ulp of x_i rounds r_i to
  // 0 while (x_i − l_i)·g_i > 0 (GPCG, n = 10: 3.9e-16 against a bound of 0), so each |r_i|
  // counts for at least the ulp it hides in.
  double xmax = 0;
  for (const double xi : xs) xmax = std::max(xmax, std::abs(xi));
  const double hidden =
      static_cast<double>(xs.size()) * std::numeric_limits<double>::epsilon() * xmax;
  k.complementarity_bound = lip * scale * (r1 + hidden);
  return k;
}

struct Case {
  PetscInt n;
  QpKind kind;
  double kappa;
  double active;
};

struct Param {
  Case c;
  const char* solver;
};

class AgreesWithTao : public ::testing::TestWithParam<Param> {};

TEST_P(AgreesWithTao, SameSolutionBothKkt) {
  const auto [c, solver] = GetParam();
  auto p = random_qp(PETSC_COMM_SELF, c.n, c.kind, c.kappa, c.active, 0.1, 4242 + c.n);
  double f_inf = 0;
  TC_PETSC(MatNorm(p.f.get(), NORM_INFINITY, &f_inf));
  const double lip = f_inf;            // ≥ λ_max(F)
  const double kappa = p.kappa_bound;  // ≥ L/μ with L = ‖F‖_∞, μ = shift
  core::Vector lower = p.d.duplicate(), upper = p.d.duplicate();
  interval_bounds(p.set, lower, upper);

  // 1e-9 relative: well inside what double precision resolves for κ ≤ 1e4 (‖x − x*‖ ≲ 4κε/L
  // leaves ~1e-5‖d‖/L), and loose enough that TAO's line searches, which compare values of
  // f, still make progress.
  const double rtol = 1e-9;
  const double eps = rtol * p.d.norm();

  qp::MatrixOperator f(p.f.get());
  qp::QpOptions opt;
  opt.rtol = rtol;
  opt.max_iterations = 20000;
  core::Vector x_m = p.d.duplicate();
  const auto rm = qp::Mprgp(f, p.set, opt).solve(p.d, x_m);
  ASSERT_TRUE(rm.converged()) << rm.message;

  // BQPIP gets the assembled F (ILU in its inner CG: unpreconditioned, its barrier systems
  // become too ill-conditioned to reach this accuracy); GPCG and BLMVM the matrix-free shell
  // around the same matrix, as in bench/qp.
  core::Vector x_t = p.d.duplicate();  // 0 is feasible for λ ≥ 0 and for boxes around 0
  core::Vector tao_lower = lower.clone(), tao_upper = upper.clone();
  const bool bqpip = std::string(solver) == TAOBQPIP;
  // μ ≥ ‖F‖_∞/κ_bound; twice the bound ‖x*‖ ≤ 2‖d‖/μ keeps the cap inactive.
  if (bqpip) cap_infinite_bounds(tao_lower, tao_upper, 4 * p.d.norm() * kappa / f_inf);
  CountingShell shell(f);
  const bool assembled = bqpip;
  const auto rt =
      run_tao(solver, assembled ? p.f.get() : shell.get(), assembled ? nullptr : &shell, p.d,
              tao_lower, tao_upper, x_t, bqpip ? bqpip_gatol(eps, p.d.norm()) : eps, 20000);
  const Kkt km = kkt(p, lower, upper, lip, x_m), kt = kkt(p, lower, upper, lip, x_t);
  // The residual each solver's stop guarantees. ‖r‖ ≤ ‖g^P‖/L ≤ ε/L for the projected-
  // gradient stops (MPRGP, GPCG, BLMVM). BQPIP stops on √(gap + ‖dual infeasibility‖) ≤ τ
  // (τ = bqpip_gatol): per component min(x_i − l_i, z_i)² ≤ (x_i − l_i) z_i with Σ = gap ≤ τ²,
  // and g − z is the dual infeasibility (≤ τ²), so ‖r‖ ≤ ‖r with step 1‖ ≤ τ + τ² (L ≥ 1).
  // Factor 2 for both: the gradient recomputed here differs from the solvers' own by
  // round-off, and BQPIP's z from g by the multipliers of its (inactive) upper caps.
  const double tau = bqpip_gatol(eps, p.d.norm());
  const double tao_residual = bqpip ? 2 * (tau + tau * tau) : 2 * eps / lip;
  ASSERT_GE(lip, 1.0);  // used for BQPIP's bound
  for (const auto& [who, k, bound, x] :
       {std::tuple{"MPRGP", km, 2 * eps / lip, &x_m}, std::tuple{solver, kt, tao_residual, &x_t}}) {
    SCOPED_TRACE(who);
    // Feasibility: MPRGP snaps to the bounds, BLMVM and GPCG project; BQPIP's interior
    // iterate x = l + slack lands outside by the round-off of that sum only.
    EXPECT_LE(k.violation,
              16 * std::numeric_limits<double>::epsilon() * std::max(1.0, x->max_abs()));
    EXPECT_LE(k.residual, bound);
    EXPECT_LE(k.complementarity, k.complementarity_bound * (1 + 1e-12) + 1e-300);
    // Distance to the solution built in: the error bound of the header.
    EXPECT_LE(k.error, 2 * kappa * k.residual + 1e-14 * p.x_star.max_abs());
  }
  core::Vector diff = x_m.clone();
  diff.axpy(-1.0, x_t);
  // ‖x_m − x_t‖ ≤ ‖x_m − x*‖ + ‖x_t − x*‖ ≤ 2κ(‖r(x_m)‖ + ‖r(x_t)‖).
  EXPECT_LE(diff.norm(), 2 * kappa * (km.residual + kt.residual) + 1e-14 * p.x_star.norm())
      << "MPRGP " << rm.iterations << " iterations, " << solver << " " << rt.iterations;
  RecordProperty("mprgp_applications", rm.operator_applications);
  RecordProperty("tao_iterations", static_cast<int>(rt.iterations));
  RecordProperty("tao_applications", static_cast<int>(rt.applications));  // −1: assembled F
}

/// Every instance with each TAO solver.
inline std::vector<Param> with_every_solver(const std::vector<Case>& cases) {
  std::vector<Param> out;
  for (const auto& c : cases)
    for (const char* s : {TAOBQPIP, TAOGPCG, TAOBLMVM}) out.push_back({c, s});
  return out;
}

inline std::string instance_name(const ::testing::TestParamInfo<Param>& info) {
  const auto& c = info.param.c;
  return std::string(info.param.solver) + "_" + (c.kind == QpKind::box ? "box" : "lower") + "_n" +
         std::to_string(c.n) + "_kappa1e" + std::to_string(std::lround(std::log10(c.kappa))) +
         "_active" + std::to_string(std::lround(100 * c.active));
}

}  // namespace
}  // namespace tc::test
