#pragma once
// The time schemes of chapter 5 for one body: Newmark's average acceleration (5.1–5.3,
// β = 1/4, γ = 1/2) or the quasistatic scheme for u, backward Euler (5.5–5.6) for θ — the
// right-hand sides and the predictor of a step, the velocity of an iterate, the updates at its
// end, M_u's coefficient in A_u. One class per scheme, chosen in one place (body_time_scheme), as
// the contact's schemes are (contact_time_scheme.hpp); Newmark's coefficient 4/τ² is written
// here only.
#include "tc/model/problem.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::physics {

/// 4/τ²: M_u's coefficient in Newmark's step (5.3), (4/τ² M_u + K_u) u^{k+1} = f^{k+1} +
/// M_u(4/τ² u_pred + ü^k) with u_pred = u^k + τu̇^k, and in its update (5.1)
/// ü^{k+1} = 4/τ²(u^{k+1} − u_pred) − ü^k.
[[nodiscard]] constexpr double newmark_mass_factor(double tau) {
  return 4.0 / (tau * tau);
}

/// The scheme of one body's u (θ is backward Euler in both); stateless, the step τ and the
/// physics read from the problem. Contract: begin_step(t^{k+1}), then any number of
/// iterate_velocity on iterates u_new, then end_step, which moves the state to t^{k+1}.
class BodyTimeScheme {
 public:
  virtual ~BodyTimeScheme() = default;
  /// M_u's coefficient in A_u = c M_u + K_u: 4/τ² (Newmark) or 0 (quasistatic, A_u = K_u).
  [[nodiscard]] virtual double mass_factor(double tau) const = 0;
  /// The right-hand sides of (5.3) and (5.6) that do not change within the fixed point of the
  /// step to t, and the predictor (u = u^k + τu̇^k + τ²/2 ü^k dynamic, θ = θ^k).
  void begin_step(const Problem& p, const BodySystem& sys, const BodyState& st, BodyField& s,
                  double t) const;
  /// The rate of the current displacement iterate u_new for the thermoelastic term of (5.6)
  /// into s.velocity: (u_new − u^k)/τ, or Newmark's (5.2) with [physics] thermoelastic_rate =
  /// "newmark".
  virtual void iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st,
                                BodyField& s) const = 0;
  /// The state moves to t^{k+1}: the scheme's updates of u̇ and ü, u and θ from the iterate,
  /// and g^{k+1} of the contact-stabilised scheme.
  void end_step(const Problem& p, const BodySystem& sys, BodyState& st, BodyField& s) const;

 protected:
  /// The inertia's part of rhs_u_base (none quasistatic), u_pred and the predictor u_new.
  virtual void predict(const Problem& p, const BodySystem& sys, const BodyState& st,
                       BodyField& s) const = 0;
  /// u̇ and ü at t^{k+1} from u_new.
  virtual void update_rates(const Problem& p, const BodySystem& sys, BodyState& st,
                            BodyField& s) const = 0;
};

/// Newmark's average acceleration: inertia 4/τ² M_u, u̇ and ü updated by (5.1)–(5.2); the
/// massless dofs (modified mass) take the step's mean rate.
class NewmarkScheme final : public BodyTimeScheme {
 public:
  [[nodiscard]] double mass_factor(double tau) const override { return newmark_mass_factor(tau); }
  void iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st,
                        BodyField& s) const override;

 private:
  void predict(const Problem& p, const BodySystem& sys, const BodyState& st,
               BodyField& s) const override;
  void update_rates(const Problem& p, const BodySystem& sys, BodyState& st,
                    BodyField& s) const override;
};

/// The quasistatic scheme: no inertia, u̇ = (u − u^k)/τ (backward difference), ü unused.
class QuasistaticScheme final : public BodyTimeScheme {
 public:
  [[nodiscard]] double mass_factor(double) const override { return 0.0; }
  void iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st,
                        BodyField& s) const override;

 private:
  void predict(const Problem& p, const BodySystem& sys, const BodyState& st,
               BodyField& s) const override;
  void update_rates(const Problem& p, const BodySystem& sys, BodyState& st,
                    BodyField& s) const override;
};

/// The scheme of p.time.scheme: the one place a body's steps choose it.
[[nodiscard]] const BodyTimeScheme& body_time_scheme(const Problem& p);

}  // namespace tc::physics
