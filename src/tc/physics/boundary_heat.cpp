#include "tc/physics/boundary_heat.hpp"

#include <algorithm>
#include <cmath>

namespace tc::physics {

namespace {

void zero_constrained(const std::vector<PetscInt>& dofs, core::Vector& x) {
  if (dofs.empty()) return;
  auto v = x.view();
  for (const PetscInt d : dofs) v[d] = 0.0;
}

/// Relative tolerance of the conjugate gradients of one Newton correction: Newton's
/// convergence then stays quadratic until ‖r‖ is 1e-8 of where the correction started.
constexpr double kInnerTolerance = 1e-8;
constexpr int kMaxInnerIterations = 500;
constexpr int kMaxHalvings = 30;

}  // namespace

NewtonOutcome solve_boundary_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                  const ConstrainedSolver& solver, double t, const core::Vector& b,
                                  core::Vector& theta, double tolerance, int max_iterations) {
  const auto& fixed = sys.theta_dirichlet_dofs();
  const PetscInt n = sys.n_theta();
  core::Vector r(n), at(n), delta(n), res(n), z(n), p(n), q(n), trial(n), r_trial(n);
  core::Vector b_free = b.clone();
  zero_constrained(fixed, b_free);
  const double b_norm = b_free.norm();
  // r(x) = A x + N(t, x) − b on the free dofs; returns ‖r‖ / max(‖b‖, ‖A x‖).
  auto residual = [&](const core::Vector& x, core::Vector& out) {
    a.mult(x, at);
    zero_constrained(fixed, at);
    const double scale = std::max(b_norm, at.norm());
    out.copy_from(at);
    sys.add_boundary_term(t, x, out);
    out.axpy(-1.0, b);
    zero_constrained(fixed, out);
    const double norm = out.norm();
    return scale > 0 ? norm / scale : norm;
  };
  NewtonOutcome o;
  o.residual = residual(theta, r);
  while (!(o.residual <= tolerance)) {
    if (o.iterations >= max_iterations || !std::isfinite(o.residual)) return o;
    ++o.iterations;
    // (A + N'(θ)) δ = −r by preconditioned CG, δ = 0 on the constrained dofs.
    delta.zero();
    res.copy_from(r);
    res.scale(-1.0);
    const double r0 = res.norm();
    z.zero();
    solver.solve(res, z);
    zero_constrained(fixed, z);
    p.copy_from(z);
    double rz = res.dot(z);
    for (int k = 0; k < kMaxInnerIterations && res.norm() > kInnerTolerance * r0; ++k) {
      ++o.inner_iterations;
      a.mult(p, q);
      sys.add_boundary_derivative(t, theta, p, q);
      zero_constrained(fixed, q);
      const double pq = p.dot(q);
      if (!(pq > 0)) break;  // no descent left (round-off at the solution)
      const double alpha = rz / pq;
      delta.axpy(alpha, p);
      res.axpy(-alpha, q);
      z.zero();
      solver.solve(res, z);
      zero_constrained(fixed, z);
      const double rz_new = res.dot(z);
      p.scale(rz_new / rz);
      p.axpy(1.0, z);
      rz = rz_new;
    }
    // θ + sδ, s halved while the residual grows (far from the solution θ⁴ overshoots).
    double s = 1.0, next = 0;
    for (int h = 0; h <= kMaxHalvings; ++h, s *= 0.5) {
      trial.copy_from(theta);
      trial.axpy(s, delta);
      next = residual(trial, r_trial);
      if (next < o.residual || h == kMaxHalvings) break;
    }
    theta.copy_from(trial);
    r.copy_from(r_trial);
    o.residual = next;
  }
  o.converged = true;
  return o;
}

}  // namespace tc::physics
