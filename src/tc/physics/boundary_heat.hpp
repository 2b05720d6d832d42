#pragma once
// The heat step of a body with radiation (or a film whose h changes in time):
//
//   A θ + N(t, θ) = b,   A = M_θ/τ + K_θ + H (factorised once, Dirichlet data eliminated),
//   N(t, θ) = Σ_{h(t) films} h(t) H θ + Σ_radiation w_a εσ(θ_a|θ_a|³ − θ∞⁴),
//
// solved by Newton's method inside the heat step (docs/choices.md, "Film and radiation"):
// (A + N'(θ)) δ = −r(θ), r = A θ + N(t, θ) − b on the free dofs, θ ← θ + sδ with s halved
// while ‖r‖ grows. N' is A's boundary part only, so the correction is solved by conjugate
// gradients on A + N' preconditioned by the factorised A (its eigenvalues are 1 + those of
// A⁻¹N' ≥ 0: a few iterations), never refactorising. Converged when
// ‖r‖ ≤ tolerance · max(‖b‖, ‖Aθ‖) over the free dofs.
#include "tc/physics/body_system.hpp"
#include "tc/physics/constrained_solver.hpp"

namespace tc::physics {

struct NewtonOutcome {
  bool converged = false;
  int iterations = 0;        // Newton corrections
  int inner_iterations = 0;  // conjugate-gradient iterations over all corrections
  double residual = 0;       // ‖r‖ / max(‖b‖, ‖Aθ‖) at exit
};

/// Solves A θ + N(t, θ) = b for θ. On entry θ holds the starting guess and the prescribed
/// values at the constrained dofs (kept). `a` is A with all rows (as assembled), `solver` its
/// factorisation with the body's Dirichlet dofs.
NewtonOutcome solve_boundary_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                  const ConstrainedSolver& solver, double t, const core::Vector& b,
                                  core::Vector& theta, double tolerance, int max_iterations);

}  // namespace tc::physics
