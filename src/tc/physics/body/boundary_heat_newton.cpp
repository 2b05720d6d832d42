#include "tc/physics/body/boundary_heat_newton.hpp"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"

namespace tc::physics {

namespace {

/// Relative tolerance of the conjugate gradients of one Newton correction: Newton's
/// convergence then stays quadratic until ‖r‖ is 1e-8 of where the correction started.
constexpr double kInnerTolerance = 1e-8;
constexpr int kMaxInnerIterations = 500;
constexpr int kMaxHalvings = 30;

/// Vectors of one size per block, and the block-wise operations Newton and CG need.
struct Blocks {
  std::vector<core::Vector> v;
  explicit Blocks(const std::vector<const BodySystem*>& systems) {
    for (const auto* s : systems) v.emplace_back(s->n_theta());
  }
  [[nodiscard]] std::vector<core::Vector*> out() {
    std::vector<core::Vector*> p;
    for (auto& x : v) p.push_back(&x);
    return p;
  }
  [[nodiscard]] std::vector<const core::Vector*> in() const {
    std::vector<const core::Vector*> p;
    for (const auto& x : v) p.push_back(&x);
    return p;
  }
};

/// θ + sδ, s halved while the residual grows (far from the solution θ⁴ overshoots, and so
/// can κ(θ)); θ and r take the accepted step's values. Returns the new residual norm.
template <class Residual>
double damped_step(const std::vector<core::Vector*>& theta, const Blocks& delta, double current,
                   Residual& residual, Blocks& trial, Blocks& r_trial, Blocks& r) {
  const size_t n = theta.size();
  double s = 1.0, next = 0;
  for (int h = 0; h <= kMaxHalvings; ++h, s *= 0.5) {
    for (size_t i = 0; i < n; ++i) {
      trial.v[i].copy_from(*theta[i]);
      trial.v[i].axpy(s, delta.v[i]);
    }
    next = residual(trial.in(), r_trial);
    if (next < current || h == kMaxHalvings) break;
  }
  for (size_t i = 0; i < n; ++i) {
    theta[i]->copy_from(trial.v[i]);
    r.v[i].copy_from(r_trial.v[i]);
  }
  return next;
}

double dot(const std::vector<const core::Vector*>& x, const std::vector<const core::Vector*>& y) {
  double s = 0;
  for (size_t i = 0; i < x.size(); ++i) s += x[i]->dot(*y[i]);
  return s;
}

double norm(const std::vector<const core::Vector*>& x) {
  return std::sqrt(dot(x, x));
}

void zero_constrained(const BodySystem& sys, core::Vector& x) {
  const auto& dofs = sys.theta_dirichlet_dofs();
  if (dofs.empty()) return;
  auto v = x.view();
  for (const PetscInt d : dofs) v[d] = 0.0;
}

/// Restart length of the GMRES of one correction: the preconditioned operator is
/// I + N'A⁻¹ with N' the change of the properties from their reference values, so a few
/// iterations reach kInnerTolerance unless the properties spread over orders of magnitude.
constexpr int kRestart = 30;

/// y += the nonlinear terms' derivative at θ applied to x (boundary and material), with y
/// zero on the constrained dofs.
void add_derivatives(const HeatOperator& a, double t, const std::vector<core::Vector*>& theta,
                     const std::vector<const core::Vector*>& x,
                     const std::vector<core::Vector*>& y) {
  for (size_t i = 0; i < a.systems.size(); ++i) {
    a.systems[i]->add_boundary_derivative(t, *theta[i], *x[i], *y[i]);
    if (const auto* m = a.systems[i]->nonlinear_heat())
      m->add_nonlinear_derivative(*theta[i], *x[i], a.inv_tau, *y[i]);
    zero_constrained(*a.systems[i], *y[i]);
  }
}

/// δ of (A + N'(θ)) δ = rhs by restarted GMRES right-preconditioned with A⁻¹, the
/// preconditioned directions kept (δ = Σ y_j A⁻¹v_j, no second solve per direction). Stops
/// at ‖rhs − (A + N')δ‖ ≤ kInnerTolerance‖rhs‖, at kMaxInnerIterations, or when a restart
/// cycle gains nothing (Newton's line search then takes the δ there is). Returns the
/// iterations (one solve with A and one product each).
int gmres(const HeatOperator& a, double t, const std::vector<core::Vector*>& theta,
          const Blocks& rhs, Blocks& delta) {
  const auto& systems = a.systems;
  const size_t n = systems.size();
  // The Krylov vectors made as the iteration reaches them, not kRestart of each up front: a
  // correction takes a few iterations (docs/choices.md), and the 61 blocks of vectors made per
  // correction were a visible part of the tabulated heat step.
  std::vector<Blocks> v, z;
  v.emplace_back(systems);
  Blocks w(systems);
  for (auto& d : delta.v) d.zero();
  for (size_t i = 0; i < n; ++i) v[0].v[i].copy_from(rhs.v[i]);
  const double r0 = norm(rhs.in());
  double beta = r0;
  int iterations = 0;
  while (beta > kInnerTolerance * r0 && iterations < kMaxInnerIterations) {
    for (auto& x : v[0].v) x.scale(1.0 / beta);  // v[0] holds the residual of δ
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(kRestart + 1, kRestart);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(kRestart + 1), cs(kRestart), sn(kRestart);
    g[0] = beta;
    int k = 0;
    while (k < kRestart && iterations < kMaxInnerIterations) {
      ++iterations;
      if (static_cast<int>(z.size()) <= k) z.emplace_back(systems);
      if (static_cast<int>(v.size()) <= k + 1) v.emplace_back(systems);
      for (auto& x : z[k].v) x.zero();
      a.solve(v[k].in(), z[k].out());
      for (size_t i = 0; i < n; ++i) zero_constrained(*systems[i], z[k].v[i]);
      a.apply(z[k].in(), w.out());
      add_derivatives(a, t, theta, z[k].in(), w.out());
      for (int j = 0; j <= k; ++j) {  // modified Gram–Schmidt
        h(j, k) = dot(w.in(), v[j].in());
        for (size_t i = 0; i < n; ++i) w.v[i].axpy(-h(j, k), v[j].v[i]);
      }
      h(k + 1, k) = norm(w.in());
      const bool breakdown = !(h(k + 1, k) > 0);  // the Krylov space holds the solution
      if (!breakdown)
        for (size_t i = 0; i < n; ++i) {
          v[k + 1].v[i].copy_from(w.v[i]);
          v[k + 1].v[i].scale(1.0 / h(k + 1, k));
        }
      for (int j = 0; j < k; ++j) {  // the previous Givens rotations on the new column
        const double x = cs[j] * h(j, k) + sn[j] * h(j + 1, k);
        h(j + 1, k) = -sn[j] * h(j, k) + cs[j] * h(j + 1, k);
        h(j, k) = x;
      }
      const double rho = std::hypot(h(k, k), h(k + 1, k));
      if (!(rho > 0)) break;  // a zero column: nothing more to gain
      cs[k] = h(k, k) / rho;
      sn[k] = h(k + 1, k) / rho;
      h(k, k) = rho;
      h(k + 1, k) = 0;
      g[k + 1] = -sn[k] * g[k];
      g[k] = cs[k] * g[k];
      ++k;
      if (breakdown || std::abs(g[k]) <= kInnerTolerance * r0) break;
    }
    if (k == 0) break;
    const Eigen::VectorXd y = h.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
    for (int j = 0; j < k; ++j)
      for (size_t i = 0; i < n; ++i) delta.v[i].axpy(y[j], z[j].v[i]);
    // The true residual rhs − (A + N')δ: the next cycle's start and the exit test.
    a.apply(delta.in(), w.out());
    add_derivatives(a, t, theta, delta.in(), w.out());
    for (size_t i = 0; i < n; ++i) {
      v[0].v[i].copy_from(rhs.v[i]);
      v[0].v[i].axpy(-1.0, w.v[i]);
      zero_constrained(*systems[i], v[0].v[i]);
    }
    const double next = norm(v[0].in());
    if (!(next < beta)) break;
    beta = next;
  }
  return iterations;
}

}  // namespace

NewtonOutcome solve_boundary_heat(const HeatOperator& a, double t,
                                  const std::vector<const core::Vector*>& b,
                                  const std::vector<core::Vector*>& theta, double tolerance,
                                  int max_iterations) {
  const auto& systems = a.systems;
  const size_t n = systems.size();
  Blocks r(systems), at(systems), delta(systems), res(systems), z(systems), p(systems), q(systems),
      trial(systems), r_trial(systems), b_free(systems);
  for (size_t i = 0; i < n; ++i) {
    b_free.v[i].copy_from(*b[i]);
    zero_constrained(*systems[i], b_free.v[i]);
  }
  const double b_norm = norm(b_free.in());
  Blocks zero(systems), n_zero(systems), n_part(systems);
  for (size_t i = 0; i < n; ++i) systems[i]->add_boundary_term(t, zero.v[i], n_zero.v[i]);
  // ‖N(t, 0)‖: the surroundings' side of the boundary terms (εσθ∞⁴), which cancels the body's
  // side at equilibrium: part of the scale that the residual is measured against.
  for (size_t i = 0; i < n; ++i) zero_constrained(*systems[i], n_zero.v[i]);
  const double absorbed = norm(n_zero.in());
  // ‖r(x)‖ with r = A x + N(t, x) − b on the free dofs; `scale` the size of the equation's
  // terms at x: max(‖b‖, ‖A x‖, ‖N(t, x) − N(t, 0)‖, ‖N(t, 0)‖).
  double scale = 0;
  auto residual = [&](const std::vector<const core::Vector*>& x, Blocks& out) {
    a.apply(x, at.out());
    for (size_t i = 0; i < n; ++i) zero_constrained(*systems[i], at.v[i]);
    for (size_t i = 0; i < n; ++i) {
      n_part.v[i].zero();
      systems[i]->add_boundary_term(t, *x[i], n_part.v[i]);
      zero_constrained(*systems[i], n_part.v[i]);
      out.v[i].copy_from(at.v[i]);
      out.v[i].axpy(1.0, n_part.v[i]);
      out.v[i].axpy(-1.0, *b[i]);
      zero_constrained(*systems[i], out.v[i]);
      n_part.v[i].axpy(-1.0, n_zero.v[i]);
    }
    scale = std::max({b_norm, norm(at.in()), norm(n_part.in()), absorbed});
    return norm(out.in());
  };
  auto precondition = [&]() {  // z = A⁻¹ res
    for (auto& x : z.v) x.zero();
    a.solve(res.in(), z.out());
    for (size_t i = 0; i < n; ++i) zero_constrained(*systems[i], z.v[i]);
  };
  std::vector<const core::Vector*> theta_in(theta.begin(), theta.end());
  NewtonOutcome o;
  double current = residual(theta_in, r);  // ‖r‖
  auto relative = [&](double value) { return scale > 0 ? value / scale : value; };
  o.residual = relative(current);
  while (!(o.residual <= tolerance)) {
    if (o.iterations >= max_iterations || !std::isfinite(o.residual)) return o;
    ++o.iterations;
    // (A + N'(θ)) δ = −r by preconditioned CG, δ = 0 on the constrained dofs.
    for (size_t i = 0; i < n; ++i) {
      delta.v[i].zero();
      res.v[i].copy_from(r.v[i]);
      res.v[i].scale(-1.0);
    }
    const double r0 = norm(res.in());
    precondition();
    for (size_t i = 0; i < n; ++i) p.v[i].copy_from(z.v[i]);
    double rz = dot(res.in(), z.in());
    for (int k = 0; k < kMaxInnerIterations && r0 > 0; ++k) {
      ++o.inner_iterations;
      a.apply(p.in(), q.out());
      for (size_t i = 0; i < n; ++i) {
        systems[i]->add_boundary_derivative(t, *theta[i], p.v[i], q.v[i]);
        zero_constrained(*systems[i], q.v[i]);
      }
      const double pq = dot(p.in(), q.in());
      if (!(pq > 0)) break;  // no descent left (round-off at the solution)
      const double alpha = rz / pq;
      for (size_t i = 0; i < n; ++i) {
        delta.v[i].axpy(alpha, p.v[i]);
        res.v[i].axpy(-alpha, q.v[i]);
      }
      // Converged before the preconditioner, a solve with A: its z would only make the next
      // direction (one interface solve of three per heat step of the pin-on-plate).
      if (norm(res.in()) <= kInnerTolerance * r0) break;
      precondition();
      const double rz_new = dot(res.in(), z.in());
      for (size_t i = 0; i < n; ++i) {
        p.v[i].scale(rz_new / rz);
        p.v[i].axpy(1.0, z.v[i]);
      }
      rz = rz_new;
    }
    current = damped_step(theta, delta, current, residual, trial, r_trial, r);
    o.residual = relative(current);
  }
  o.converged = true;
  return o;
}

NewtonOutcome solve_boundary_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                  const ConstrainedSolver& solver, double t, const core::Vector& b,
                                  core::Vector& theta, double tolerance, int max_iterations) {
  HeatOperator op;
  op.systems = {&sys};
  op.apply = [&](const auto& x, const auto& y) { a.mult(*x[0], *y[0]); };
  op.solve = [&](const auto& r, const auto& z) { solver.solve(*r[0], *z[0]); };
  return solve_boundary_heat(op, t, {&b}, {&theta}, tolerance, max_iterations);
}

NewtonOutcome solve_nonlinear_heat(const HeatOperator& a, double t,
                                   const std::vector<const core::Vector*>& b,
                                   const std::vector<core::Vector*>& theta, double tolerance,
                                   int max_iterations) {
  const auto& systems = a.systems;
  const size_t n = systems.size();
  Blocks r(systems), at(systems), delta(systems), res(systems), trial(systems), r_trial(systems),
      b_free(systems);
  for (size_t i = 0; i < n; ++i) {
    b_free.v[i].copy_from(*b[i]);
    zero_constrained(*systems[i], b_free.v[i]);
  }
  const double b_norm = norm(b_free.in());
  Blocks zero(systems), n_zero(systems), n_part(systems);
  for (size_t i = 0; i < n; ++i) {
    systems[i]->add_boundary_term(t, zero.v[i], n_zero.v[i]);
    zero_constrained(*systems[i], n_zero.v[i]);
  }
  const double absorbed = norm(n_zero.in());
  // r = A x + N(t, x) + N_m(x) − b on the free dofs; the scale as in solve_boundary_heat with
  // ‖A x‖ (of the absolute temperature, as the constant-property steps have it) and
  // ‖A x + N_m(x)‖ = ‖H(x)/τ + C(x)‖: a body resting at θ₀ has b = 0 and H(x) = 0, whose
  // residual is round-off of ‖A x‖ and must pass.
  double scale = 0, linear = 0;
  auto residual = [&](const std::vector<const core::Vector*>& x, Blocks& out) {
    a.apply(x, at.out());
    for (size_t i = 0; i < n; ++i) zero_constrained(*systems[i], at.v[i]);
    linear = norm(at.in());
    for (size_t i = 0; i < n; ++i) {
      if (const auto* m = systems[i]->nonlinear_heat())
        m->add_nonlinear_part(*x[i], a.inv_tau, at.v[i]);
      zero_constrained(*systems[i], at.v[i]);
      n_part.v[i].zero();
      systems[i]->add_boundary_term(t, *x[i], n_part.v[i]);
      zero_constrained(*systems[i], n_part.v[i]);
      out.v[i].copy_from(at.v[i]);
      out.v[i].axpy(1.0, n_part.v[i]);
      out.v[i].axpy(-1.0, *b[i]);
      zero_constrained(*systems[i], out.v[i]);
      n_part.v[i].axpy(-1.0, n_zero.v[i]);
    }
    scale = std::max({b_norm, linear, norm(at.in()), norm(n_part.in()), absorbed});
    return norm(out.in());
  };
  std::vector<const core::Vector*> theta_in(theta.begin(), theta.end());
  NewtonOutcome o;
  double current = residual(theta_in, r);
  auto relative = [&](double value) { return scale > 0 ? value / scale : value; };
  o.residual = relative(current);
  while (!(o.residual <= tolerance)) {
    if (o.iterations >= max_iterations || !std::isfinite(o.residual)) return o;
    ++o.iterations;
    for (size_t i = 0; i < n; ++i) {
      res.v[i].copy_from(r.v[i]);
      res.v[i].scale(-1.0);
    }
    o.inner_iterations += gmres(a, t, theta, res, delta);
    current = damped_step(theta, delta, current, residual, trial, r_trial, r);
    o.residual = relative(current);
  }
  o.converged = true;
  return o;
}

NewtonOutcome solve_nonlinear_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                   const ConstrainedSolver& solver, double tau, double t,
                                   const core::Vector& b, core::Vector& theta, double tolerance,
                                   int max_iterations) {
  HeatOperator op;
  op.systems = {&sys};
  op.apply = [&](const auto& x, const auto& y) { a.mult(*x[0], *y[0]); };
  op.solve = [&](const auto& r, const auto& z) { solver.solve(*r[0], *z[0]); };
  op.inv_tau = 1.0 / tau;
  return solve_nonlinear_heat(op, t, {&b}, {&theta}, tolerance, max_iterations);
}

void require_converged(const NewtonOutcome& o, const std::string& what, double tolerance, int step,
                       int iteration, std::string_view terms) {
  if (!o.converged)
    throw NumericalError(
        fmt::format("heat step (5.6): Newton's method for {} of "
                    "{} did not converge to {:.1e} in {} iterations (staggered iteration {})",
                    terms, what, tolerance, o.iterations, iteration),
        step, o.iterations, o.residual);
}

}  // namespace tc::physics
