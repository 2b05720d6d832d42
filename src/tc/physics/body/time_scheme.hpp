#pragma once
// The time schemes of chapter 5 for one body: Newmark's average acceleration (5.1–5.3,
// β = 1/4, γ = 1/2) or the quasistatic scheme for u, backward Euler (5.5–5.6) for θ — the
// right-hand sides and the predictor of a step, the velocity of an iterate, the updates at its
// end, M_u's coefficient in A_u. One class per scheme, chosen in one place (body_time_scheme), as
// the contact's schemes are (contact_time_scheme.hpp); Newmark's coefficient 4/τ² is written
// here only. A step enters the scheme once (BodyTimeScheme::step), which brackets whatever the
// step does between its beginning and its end.
#include <functional>
#include <vector>

#include "tc/model/problem.hpp"
#include "tc/physics/body/bodies.hpp"
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
/// physics read from the problem. Contract: step() is the one entry of a time step; inside it,
/// any number of iterate_velocity on iterates u_new.
class BodyTimeScheme {
 public:
  virtual ~BodyTimeScheme() = default;
  /// M_u's coefficient in A_u = c M_u + K_u: 4/τ² (Newmark) or 0 (quasistatic, A_u = K_u).
  [[nodiscard]] virtual double mass_factor(double tau) const = 0;
  /// Whether the bodies have inertia: a kinetic energy, M_u ü in their balance, ü⁰ to start.
  [[nodiscard]] virtual bool inertia() const = 0;
  /// Whether the contact faces carry no inertia (the modified mass, Hager, Hüeber & Wohlmuth:
  /// M_u without their dofs, BodySystem::massless_dofs).
  [[nodiscard]] virtual bool massless_contact_faces(const Problem& p) const = 0;
  /// The step of the bodies `members` (Problem::bodies indices) to t^{k+1} = t: begin_step of
  /// each (right-hand sides, predictor), then `iterate` (the step's fixed point, from the
  /// predictor; returns its iterations, which step returns), then end_step of each. If
  /// `iterate` throws, the states stay at t^k.
  int step(const Problem& p, Bodies& bodies, const std::vector<int>& members, double t,
           const std::function<int()>& iterate) const;
  /// The rate of the current displacement iterate u_new for the thermoelastic term of (5.6)
  /// into s.velocity: (u_new − u^k)/τ, or Newmark's (5.2) with [physics] thermoelastic_rate =
  /// "newmark".
  virtual void iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st,
                                BodyField& s) const = 0;

 protected:
  /// The right-hand sides of (5.3) and (5.6) that do not change within the fixed point of the
  /// step to t, and the predictor (u = u^k + τu̇^k + τ²/2 ü^k dynamic, θ = θ^k).
  void begin_step(const Problem& p, const BodySystem& sys, const BodyState& st, BodyField& s,
                  double t) const;
  /// The state moves to t^{k+1}: the scheme's updates of u̇ and ü, u and θ from the iterate,
  /// and g^{k+1} of the contact-stabilised scheme.
  void end_step(const Problem& p, const BodySystem& sys, BodyState& st, BodyField& s) const;
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
  [[nodiscard]] bool inertia() const override { return true; }
  [[nodiscard]] bool massless_contact_faces(const Problem& p) const override {
    return p.time.contact_scheme == ContactScheme::modified_mass;
  }
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
  [[nodiscard]] bool inertia() const override { return false; }
  [[nodiscard]] bool massless_contact_faces(const Problem&) const override { return false; }
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
