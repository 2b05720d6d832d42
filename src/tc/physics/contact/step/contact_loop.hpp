#pragma once
// The variants of the contact bodies' staggered loop (6.3, ContactCoupling::couple), each a
// named policy chosen once per step from the settings and the physics: the order of the
// halves, where the Tresca → Coulomb updates sit and how they are relaxed, how the mechanical
// half's displacements are fed back, and the rules the loop stops by (staggered_loop.hpp).
#include "tc/model/problem.hpp"
#include "tc/physics/body/step/staggered_loop.hpp"
#include "tc/physics/contact/friction_fixed_point.hpp"

namespace tc::physics {

/// Where the Tresca → Coulomb updates γ = λ_n sit ([solver] friction_loop; docs/choices.md,
/// "friction loop").
enum class FrictionPlacement {
  nested,     // to convergence in every mechanical half, Aitken restarted (θ changed the map)
  staggered,  // one update per sweep, the relaxation carried over the sweeps
};

/// How the mechanical half's displacements u = u_free − A⁻¹Bᵀλ are fed back into the loop.
enum class DisplacementFeedback {
  from_qp,      // the combined dual's QP returns u with λ
  deferred,     // B u only (the frictional heat's slip, B u_free − Fλ); u once, after the loop
  per_iterate,  // u of every iterate: the thermoelastic term wants u̇ of the whole body
};

/// What the physics of the step says about the loop.
struct ContactLoopPhysics {
  bool qp_gives_displacements = false;  // the enforcement's QP returns u (combined TFETI)
  bool heating = false;          // a contact body has the thermoelastic term θ₀K_uθᵀu̇
  bool expansion = false;        // a contact body has thermal expansion (θ → u_free)
  bool frictional = false;       // 𝔉 > 0 somewhere (else γ plays no part)
  bool friction_varies = false;  // 𝔉 depends on θ somewhere
  bool theta_iterates = false;   // lagged conductance, or γ_C(θ): θ iterates itself
};

struct ContactLoopPolicy {
  SweepOrder order = SweepOrder::heat_first;
  FrictionPlacement friction = FrictionPlacement::staggered;
  FrictionRelaxation relaxation = FrictionRelaxation::plain;  // of the Tresca → Coulomb updates
  DisplacementFeedback feedback = DisplacementFeedback::per_iterate;
  // Nested, with thermal expansion: each inner loop stops after a 1/loop_forcing-fold fall
  // (θ and u_free move in the next sweep anyway).
  bool cut_short = false;
  // No thermal expansion and 𝔉 independent of θ: λ at the Coulomb solution stays exact, and
  // the heat step with it is the last needed (FinalHeat).
  bool lambda_final = false;
  bool theta_iterates = false;

  /// Fixed-point updates per mechanical half.
  [[nodiscard]] int max_updates(const SolverSettings& s) const {
    return friction == FrictionPlacement::nested ? s.friction.max_updates : 1;
  }
  /// The loop with its stopping rules: u and θ within ε with the friction met, always; the
  /// last heat step when λ is final; the contraction estimate when the friction is nested.
  [[nodiscard]] StaggeredLoop loop(const SolverSettings& s) const;
};

/// The policy of the settings `s` for the physics `p` of the contact bodies.
[[nodiscard]] ContactLoopPolicy choose_contact_loop(const SolverSettings& s,
                                                    const ContactLoopPhysics& p);

}  // namespace tc::physics
