#pragma once
// The heat and mechanical steps of one body within a time step (6.1, 6.3), and the staggered
// fixed point of 6.3 for a body outside contact. The contact pairs' loop (ContactCoupling)
// takes the body steps from here and adds the interface.
#include "tc/core/timer.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/body/bodies.hpp"

namespace tc::physics {

class BodySteps {
 public:
  BodySteps(const Problem& problem, Bodies& bodies, core::PhaseTimers& timers)
      : problem_(problem), bodies_(bodies), timers_(timers) {}

  /// The right-hand side of (6.1) without contact terms into rhs_theta: the step's fixed part
  /// and the thermoelastic term of the current displacement iterate.
  void heat_rhs(int b);
  /// (6.1)/(5.6) of body b with the current u iterate into theta_new; `step` is k + 1.
  void heat_step(int b, int step, int iteration);
  /// The loads of (5.3) at θ^{k+1,p+1} into rhs_u, the prescribed values into u_new: what the
  /// body's solver (mech_step) or the combined contact dual solves with.
  void mech_load(int b, int step);
  /// (6.3) with θ^{k+1,p+1}, without contact forces: u_new = A_u⁻¹ rhs_u.
  void mech_step(int b, int step, int iteration);
  /// The fixed point of the step k → `step` of body b without contact, from the scheme's
  /// predictor (inside BodyTimeScheme::step): the staggered loop of 6.3, one pass when the
  /// coupling is one-way; returns its iterations.
  int couple(int b, int step);

  /// Newton corrections and their CG iterations so far (radiation, h(t) films).
  [[nodiscard]] long newton_iterations() const { return newton_; }
  [[nodiscard]] long newton_inner_iterations() const { return newton_inner_; }

 private:
  const Problem& problem_;
  Bodies& bodies_;
  core::PhaseTimers& timers_;
  long newton_ = 0, newton_inner_ = 0;
};

}  // namespace tc::physics
