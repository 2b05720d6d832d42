#include "tc/physics/body/time_scheme.hpp"

namespace tc::physics {

namespace {

/// rate = (u − u_old)/τ on the given dofs (the massless ones: massless_rates).
void step_mean_rate(const std::vector<PetscInt>& dofs, const core::Vector& u,
                    const core::Vector& u_old, double tau, core::Vector& rate) {
  if (dofs.empty()) return;
  const auto un = u.read();
  const auto uo = u_old.read();
  auto v = rate.view();
  for (const PetscInt d : dofs) v[d] = (un[d] - uo[d]) / tau;
}

void massless_rates(const Problem& p, const BodySystem& sys, BodyState& st, const BodyField& s) {
  // Dofs without inertia (modified mass) follow the equilibrium of each t^k: Newmark's
  // u̇^{k+1} = 2/τ Δu − u̇^k would carry the step-to-step oscillation of a quasistatic
  // variable (2v, 0, 2v, … after a sudden start) into the slip and the thermoelastic heat.
  // Their rate is the step's mean Δu/τ, their acceleration zero (M ü has no entry there).
  const auto& dofs = sys.massless_dofs();
  step_mean_rate(dofs, s.u_new, st.u, p.time.step, st.v);
  auto a = st.a.view();
  for (const PetscInt d : dofs) a[d] = 0.0;
}

}  // namespace

int BodyTimeScheme::step(const Problem& p, Bodies& bodies, const std::vector<int>& members,
                         double t, const std::function<int()>& iterate) const {
  for (const int b : members)
    begin_step(p, *bodies.systems[b], bodies.states[b], *bodies.fields[b], t);
  const int iterations = iterate();
  for (const int b : members) end_step(p, *bodies.systems[b], bodies.states[b], *bodies.fields[b]);
  return iterations;
}

void BodyTimeScheme::begin_step(const Problem& p, const BodySystem& sys, const BodyState& st,
                                BodyField& s, double t) const {
  const double tau = p.time.step;
  const auto& m = sys.matrices();
  // Right-hand sides that do not change within the fixed point: f_u^{k+1} of (5.3) (with the
  // inertia's part, predict), f_θ^{k+1} of (5.6) + M_θ θ/τ
  // (+ H(θ)/τ, the enthalpy, when κ or c_p depends on θ).
  sys.mechanical_load(t, s.f_u);
  s.rhs_u_base.copy_from(s.f_u);
  sys.thermal_load(t, s.f_theta);
  s.rhs_theta_base.copy_from(s.f_theta);
  if (const auto* heat = sys.nonlinear_heat()) {
    heat->add_enthalpy(st.theta, 1.0 / tau, s.rhs_theta_base);  // H(θ^k)/τ (nonlinear_heat.hpp)
  } else {
    s.work_theta.copy_from(st.theta);
    s.work_theta.scale(1.0 / tau);
    m.mass_theta.mult_add(s.work_theta, s.rhs_theta_base);
  }
  predict(p, sys, st, s);
  s.theta_new.copy_from(st.theta);
}

void BodyTimeScheme::end_step(const Problem& p, const BodySystem& sys, BodyState& st,
                              BodyField& s) const {
  update_rates(p, sys, st, s);
  st.u.copy_from(s.u_new);
  st.theta.copy_from(s.theta_new);
  if (s.mass) {  // g^{k+1} = f^{k+1} − K u^{k+1} − K_uθ(θ^{k+1} − θ₀) (f_u still holds f^{k+1})
    const auto& m = sys.matrices();
    s.g_free.copy_from(s.f_u);
    m.stiffness_u.mult(st.u, s.work_u);
    s.g_free.axpy(-1.0, s.work_u);
    if (p.physics.thermal_expansion) subtract_thermal_force(p, sys, s, st.theta, s.g_free);
  }
}

void NewmarkScheme::predict(const Problem& p, const BodySystem& sys, const BodyState& st,
                            BodyField& s) const {
  const double tau = p.time.step;
  // f_u^{k+1} of (5.3): + M(4/τ² u + 4/τ u̇ + ü) = M(4/τ² u_pred + ü).
  s.u_pred.copy_from(st.u);
  s.u_pred.axpy(tau, st.v);
  s.work_u.copy_from(st.a);
  s.work_u.axpy(newmark_mass_factor(tau), s.u_pred);
  sys.matrices().mass_u.mult_add(s.work_u, s.rhs_u_base);
  // Predictor: Newmark with ü^{k+1} = ü^k (the thesis starts from u^k; this is closer).
  s.u_new.copy_from(st.u);
  s.u_new.axpy(tau, st.v);
  s.u_new.axpy(0.5 * tau * tau, st.a);
}

void NewmarkScheme::iterate_velocity(const Problem& p, const BodySystem& sys, const BodyState& st,
                                     BodyField& s) const {
  // The rate of the current iterate in the thermoelastic term θ₀K_uθᵀu̇ of (5.6): backward
  // Euler's (u − u^k)/τ by default, the discrete d/dt of the strain as (5.5) has θ̇, so the
  // term's heat sums over the steps to θ₀K_uθᵀ(u^n − u⁰), whatever the velocities did, and
  // cancels Newmark's coupling work in the energy. Newmark's u̇ = u̇^k + 2/τ(u − u_pred) (u_pred
  // projected when contact-stabilised), as (5.6) writes it, on request: after a jump of
  // velocity it alternates ±Δv from step to step (no numerical damping), and where
  // neighbouring nodes ring differently (the massless contact faces of the modified mass take
  // the mean rate) the ringing is a strain rate of Δv/h that heats and cools the first layer of
  // cells by turns (docs/choices.md, "The thermoelastic term at the step's mean rate").
  const double tau = p.time.step;
  s.velocity.copy_from(s.u_new);
  if (p.physics.thermoelastic_rate == ThermoelasticRate::newmark) {
    s.velocity.axpy(-1.0, s.u_pred);
    s.velocity.scale(2.0 / tau);
    s.velocity.axpy(1.0, st.v);
    step_mean_rate(sys.massless_dofs(), s.u_new, st.u, tau, s.velocity);
  } else {
    s.velocity.axpy(-1.0, st.u);
    s.velocity.scale(1.0 / tau);
  }
}

void NewmarkScheme::update_rates(const Problem& p, const BodySystem& sys, BodyState& st,
                                 BodyField& s) const {
  const double tau = p.time.step;
  s.work_u.copy_from(s.u_new);
  s.work_u.axpy(-1.0, s.u_pred);  // u^{k+1} − u_pred = τ²/4 (ü^k + ü^{k+1})
  st.a.scale(-1.0);               // ü^{k+1} = 4/τ²(u^{k+1} − u_pred) − ü^k
  st.a.axpy(newmark_mass_factor(tau), s.work_u);
  st.v.axpy(2.0 / tau, s.work_u);  // u̇^{k+1} = u̇^k + 2/τ(u^{k+1} − u_pred)
  massless_rates(p, sys, st, s);
}

void QuasistaticScheme::predict(const Problem& p, const BodySystem&, const BodyState& st,
                                BodyField& s) const {
  // Predictor u^k + τu̇^k (the last step's rate); the velocity is taken from u_pred = u^k.
  s.u_new.copy_from(st.u);
  s.u_new.axpy(p.time.step, st.v);
  s.u_pred.copy_from(st.u);
}

void QuasistaticScheme::iterate_velocity(const Problem& p, const BodySystem&, const BodyState&,
                                         BodyField& s) const {
  // (u − u^k)/τ, with u_pred = u^k.
  s.velocity.copy_from(s.u_new);
  s.velocity.axpy(-1.0, s.u_pred);
  s.velocity.scale(1.0 / p.time.step);
}

void QuasistaticScheme::update_rates(const Problem& p, const BodySystem&, BodyState& st,
                                     BodyField& s) const {
  s.work_u.copy_from(s.u_new);
  s.work_u.axpy(-1.0, st.u);
  st.v.copy_from(s.work_u);
  st.v.scale(1.0 / p.time.step);
}

const BodyTimeScheme& body_time_scheme(const Problem& p) {
  static const NewmarkScheme newmark{};
  static const QuasistaticScheme quasistatic{};
  if (p.time.scheme == Scheme::dynamic) return newmark;
  return quasistatic;
}

}  // namespace tc::physics
