#pragma once
// The field of one body inside the time loop: its operators of (5.3) and (5.6), factorised once
// (directly, or by Total FETI over the body's subdomains), the right-hand sides and the work
// vectors of a step.
#include <memory>

#include "tc/core/numeric/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/body/body_system.hpp"
#include "tc/physics/body/rigid_coupling.hpp"

namespace tc::physics {

/// Which of a body's operators a solver is for (FETI assembles it per subdomain).
enum class BodyOperator { mechanics, heat, mass, statics };

/// a·X + b·Y as a new matrix (same nonzero pattern: both come from the same node graph).
[[nodiscard]] core::SparseMatrix combine(double a, const core::SparseMatrix& x, double b,
                                         const core::SparseMatrix& y);

/// The solver of A x = b for one body: a direct factorisation of A, or Total FETI over the
/// body's subdomains when it is decomposed (6.2), with a·M + b·K assembled per subdomain.
[[nodiscard]] std::unique_ptr<ConstrainedSolver> body_solver(const Problem& p,
                                                             const BodySystem& sys,
                                                             const core::SparseMatrix& a,
                                                             BodyOperator op);
/// The same consuming `a` when the body is solved directly (ConstrainedSolver's consuming
/// constructor): for an operator formed only to be factorised.
[[nodiscard]] std::unique_ptr<ConstrainedSolver> body_solver(const Problem& p,
                                                             const BodySystem& sys,
                                                             core::SparseMatrix&& a,
                                                             BodyOperator op);

/// Displacement, velocity, acceleration and temperature of one body at the current time.
struct BodyState {
  core::Vector u, v, a, theta;
};

/// Factorised operators and work vectors of one body.
struct BodyField {
  /// Forms and factorises A_u and A_θ of body `sys`, allocates the vectors.
  BodyField(const Problem& p, const BodySystem& sys);
  /// Refactorises A_u from the system's K_u, re-assembled by BodySystem::update_moduli (the
  /// contact's compliances of `mech` are then stale: ContactCoupling::refactorised).
  void refactorise_mechanics(const Problem& p, const BodySystem& sys);

  core::SparseMatrix a_theta;  // M_θ/τ + K_θ (5.6)
  std::unique_ptr<ConstrainedSolver> mech, heat;
  /// The faces under load control of the body ([[boundary]] force); null when it has none.
  std::unique_ptr<RigidCoupling> coupling;
  bool coupling_in_contact = false;  // its w is found with the contact QP (ContactCoupling)
  core::Vector f_u, f_theta, rhs_u_base, rhs_theta_base, rhs_u, rhs_theta;
  core::Vector u_new, theta_new, u_prev, theta_prev, velocity, dtheta, work_u, work_theta;
  core::Vector u_pred;  // Newmark's u^k + τu̇^k, projected onto the admissible set if stabilised
  // Contact-stabilised Newmark only: M_u factorised, and the force without inertia and contact
  // g^k = f^k − K_u u^k − K_uθ(θ^k − θ₀) that replaces M_u ü^k (which holds the contact force).
  std::unique_ptr<ConstrainedSolver> mass;
  core::Vector g_free;
  // θ₀(M_θ/τ + H_film)1, A_θ θ₀ without K_θ θ₀ (zero in exact arithmetic): the linear heat
  // solves are for ϑ = θ − θ₀ (heat_to_deviation).
  core::Vector theta0_load;
  bool expansion = false;  // θ drives u (thermal expansion on, α ≠ 0)
  bool heating = false;    // u̇ drives θ (thermoelastic heating on, α ≠ 0)
};

/// ü⁰ of M_u ü⁰ = r (2.1 at t = 0) with ü⁰ = 0 on the supports and on the massless dofs of the
/// modified mass, by Jacobi-preconditioned CG: no factorisation of M_u, whose fill is that of
/// A_u's and which would coexist with it at the run's memory peak. Throws NumericalError
/// (step 0) when CG does not converge.
void solve_initial_acceleration(const BodySystem& sys, const core::Vector& r, core::Vector& a);

/// The heat step (5.6) solved for ϑ = θ − θ₀ (docs/choices.md, "The heat step solved for
/// θ − θ₀"): A_θ ϑ = b − θ₀ A_θ1 with K_θ1 = 0 taken exactly, so that a body at θ₀ with no
/// heat coming in has a right-hand side of exact zeros, and so a temperature of exactly θ₀
/// and no thermal load on its mechanics (whose solves are then skipped: CholeskySolver::solve).
/// heat_to_deviation: rhs_theta −= theta0_load, theta_new −= θ₀ (its prescribed values with
/// it); heat_from_deviation: theta_new += θ₀, the prescribed values of time t set again. Only
/// for factorised heat operators (deviation_applies): FETI's stopping test is relative to the
/// right-hand side, which the shift would shrink. Not in the Newton loop of radiation and h(t)
/// films (solve_boundary_heat works on θ).
[[nodiscard]] bool deviation_applies(const BodyField& s);
void heat_to_deviation(double theta0, BodyField& s);
void heat_from_deviation(double theta0, const BodySystem& sys, double t, BodyField& s);

/// out = θ − θ₀ per node, or with α(θ) a table ϑ_α(θ_a) = ∫_{θ₀}^{θ_a} α dθ / α
/// (fem::Material::expansion_deviation): what K_uθ multiplies in the thermal force.
void thermal_deviation(const Problem& p, const BodySystem& sys, const core::Vector& theta,
                       core::Vector& out);
/// f ← f − K_uθ ϑ_α(θ) (ϑ_α = θ − θ₀ for a constant α), the thermal stress's load of (2.5),
/// with s's scratch vectors.
void subtract_thermal_force(const Problem& p, const BodySystem& sys, BodyField& s,
                            const core::Vector& theta, core::Vector& f);

}  // namespace tc::physics
