#pragma once
// The heat step of bodies with radiation (or a film whose h changes in time):
//
//   A θ + N(t, θ) = b,   A = M_θ/τ + K_θ + H (factorised once, Dirichlet data eliminated;
//                        for a contact pair also the interface conductance L_θγ),
//   N(t, θ) = Σ_{h(t) films} h(t) H θ + Σ_radiation w_a εσ(θ_a|θ_a|³ − θ∞⁴),
//
// solved by Newton's method inside the heat step (docs/choices.md, "Film and radiation"):
// (A + N'(θ)) δ = −r(θ), r = A θ + N(t, θ) − b on the free dofs, θ ← θ + sδ with s halved
// while ‖r‖ grows. N' is on the boundary only, so the correction is solved by conjugate
// gradients on A + N' preconditioned by the solve with A (its eigenvalues are 1 + those of
// A⁻¹N' ≥ 0: a few iterations), never refactorising. Converged when
// ‖r‖ ≤ tolerance · max(‖b‖, ‖Aθ‖, ‖N(t, θ) − N(t, 0)‖, ‖N(t, 0)‖) over the free dofs: the
// size of the equation's terms (radiation can dominate all others, in a body whose heat
// capacity per step is small; the emitted and the absorbed parts are counted apart because
// they cancel at equilibrium).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "tc/dual/constrained_solver.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::physics {

struct NewtonOutcome {
  bool converged = false;
  int iterations = 0;        // Newton corrections
  int inner_iterations = 0;  // conjugate-gradient iterations over all corrections
  double residual = 0;       // ‖r‖ / scale at exit (below)
};

/// Throws NumericalError when the Newton of a heat step did not converge; `what` names the
/// body or the contact pair, `step` and `iteration` (of the staggered loop) place it, `terms`
/// the nonlinear terms the Newton was for.
void require_converged(const NewtonOutcome& o, const std::string& what, double tolerance, int step,
                       int iteration, std::string_view terms = "the radiation and film boundaries");
/// The words of require_converged for a step with κ(θ) or c_p(θ).
inline constexpr std::string_view kMaterialLawTerms =
    "the temperature-dependent conductivity or specific heat (and the radiation and film "
    "boundaries, if any)";

/// The linear part A of one or more bodies' heat step (one block per body, numbered like
/// `systems`): `apply` sets y = A x with every row (as assembled), `solve` sets z = A⁻¹ r with
/// z = 0 on the constrained dofs (r is zero there).
struct HeatOperator {
  std::vector<const BodySystem*> systems;
  std::function<void(const std::vector<const core::Vector*>& x,
                     const std::vector<core::Vector*>& y)>
      apply;
  std::function<void(const std::vector<const core::Vector*>& r,
                     const std::vector<core::Vector*>& z)>
      solve;
  /// 1/τ of the step: the scale of the enthalpy in the material term (solve_nonlinear_heat).
  double inv_tau = 0;
};

/// Solves A θ + N(t, θ) = b for the blocks θ. On entry θ holds the starting guess and the
/// prescribed values at the constrained dofs (kept).
NewtonOutcome solve_boundary_heat(const HeatOperator& a, double t,
                                  const std::vector<const core::Vector*>& b,
                                  const std::vector<core::Vector*>& theta, double tolerance,
                                  int max_iterations);

/// One body: `a` is its heat operator with all rows, `solver` its factorisation (or FETI).
NewtonOutcome solve_boundary_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                  const ConstrainedSolver& solver, double t, const core::Vector& b,
                                  core::Vector& theta, double tolerance, int max_iterations);

/// The heat step of bodies with κ(θ) or c_p(θ) (BodySystem::nonlinear_heat), with their
/// boundary terms N(t, θ) if any: A θ + N(t, θ) + Σ N_m(θ) = b, N_m the material part
/// (fem::NonlinearHeat, b holding H(θ^k)/τ), solved by Newton's method as above but each
/// correction by GMRES (the Jacobian A + N' + N_m' is not symmetric when κ' ≠ 0), right-
/// preconditioned by the solve with A: the factorised operator of the reference properties,
/// so that the iteration count depends on the properties' spread, not on the mesh. Same
/// convergence test, same contract.
NewtonOutcome solve_nonlinear_heat(const HeatOperator& a, double t,
                                   const std::vector<const core::Vector*>& b,
                                   const std::vector<core::Vector*>& theta, double tolerance,
                                   int max_iterations);
NewtonOutcome solve_nonlinear_heat(const BodySystem& sys, const core::SparseMatrix& a,
                                   const ConstrainedSolver& solver, double tau, double t,
                                   const core::Vector& b, core::Vector& theta, double tolerance,
                                   int max_iterations);

}  // namespace tc::physics
