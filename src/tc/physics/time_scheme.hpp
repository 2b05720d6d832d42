#pragma once
// The time schemes of chapter 5: Newmark's average acceleration (5.1–5.3, β = 1/4, γ = 1/2)
// or the quasistatic scheme for u, backward Euler (5.5–5.6) for θ: the right-hand sides and
// the predictor of a step, the velocity of an iterate, the updates at its end. Newmark's
// coefficient of M_u is written here only.
#include "tc/physics/body_field.hpp"
#include "tc/physics/body_system.hpp"
#include "tc/physics/problem.hpp"

namespace tc::physics {

/// 4/τ²: M_u's coefficient in Newmark's step (5.3), (4/τ² M_u + K_u) u^{k+1} = f^{k+1} +
/// M_u(4/τ² u_pred + ü^k) with u_pred = u^k + τu̇^k, and in its update (5.1)
/// ü^{k+1} = 4/τ²(u^{k+1} − u_pred) − ü^k.
[[nodiscard]] constexpr double newmark_mass_factor(double tau) {
  return 4.0 / (tau * tau);
}

/// The right-hand sides of (5.3) and (5.6) that do not change within the fixed point of the
/// step to t, and the predictor u = u^k + τu̇^k + τ²/2 ü^k (dynamic), θ = θ^k.
void begin_step(const Problem& p, const BodySystem& sys, const BodyState& st, BodyField& s,
                double t);
/// The rate of the current displacement iterate u_new for the thermoelastic term of (5.6) into
/// s.velocity: (u_new − u^k)/τ, or Newmark's (5.2) with [physics] thermoelastic_rate = "newmark".
void iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st, BodyField& s);
/// The state moves to t^{k+1}: Newmark (or backward-difference) updates of u̇ and ü, u and θ
/// from the iterate, and g^{k+1} of the contact-stabilised scheme.
void end_step(const Problem& p, const BodySystem& sys, BodyState& st, BodyField& s);

}  // namespace tc::physics
