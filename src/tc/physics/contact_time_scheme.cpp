#include "tc/physics/contact_time_scheme.hpp"

#include <fmt/format.h>

#include "tc/core/error.hpp"
#include "tc/physics/contact_heat.hpp"
#include "tc/physics/multiplier_transfer.hpp"
#include "tc/physics/time_scheme.hpp"

namespace tc::physics {

double ContactTimeScheme::traction_per_multiplier() const {
  return physics::traction_per_multiplier(false);
}

void QuasistaticContact::slip_reference(const BodyPair& pair) const {
  pair.slave.work_u.copy_from(pair.slave_state.u);
  pair.master.work_u.copy_from(pair.master_state.u);
}

void PlainNewmarkContact::slip_reference(const BodyPair& pair) const {
  // u_pred − τ/2 u̇^k (= u^k + τ/2 u̇^k unless the predictor was projected), so that
  // B_τu − c_τ = τ/2 B_τu̇^{k+1} (5.4).
  pair.slave.work_u.copy_from(pair.slave.u_pred);
  pair.master.work_u.copy_from(pair.master.u_pred);
  pair.slave.work_u.axpy(-0.5 * tau_, pair.slave_state.v);
  pair.master.work_u.axpy(-0.5 * tau_, pair.master_state.v);
}

void ModifiedMassContact::prepare(const BodyPair&, DualContactSolver& dual,
                                  const core::Vector& lambda, ContactStatistics&, int) {
  dual.set_normal_floor(release_floor(lambda, dual.rows().dim));
}

void ModifiedMassContact::slip_reference(const BodyPair& pair) const {
  // The contact nodes have no inertia (massless_rates): B_τu − c_τ = τ B_τu̇^{k+1}.
  pair.slave.work_u.copy_from(pair.slave_state.u);
  pair.master.work_u.copy_from(pair.master_state.u);
}

StabilisedNewmarkContact::StabilisedNewmarkContact(const Problem& p, Bodies& bodies, int slave,
                                                   int master, const DualContactSettings& settings,
                                                   core::PhaseTimers& timers)
    : PlainNewmarkContact(p.time.step), timers_(timers) {
  auto t = timers_.scope("factorization");
  for (const int b : {slave, master}) {
    auto& sv = *bodies.fields[b];
    sv.mass = sv.initial_mass
                  ? std::move(sv.initial_mass)
                  : body_solver(p, *bodies.systems[b], bodies.systems[b]->matrices().mass_u,
                                BodyOperator::mass);
  }
  projection_ = std::make_unique<DualContactSolver>(
      *bodies.fields[slave]->mass, *bodies.fields[master]->mass, bodies.systems[slave]->n_u(),
      bodies.systems[master]->n_u(), settings);
}

void StabilisedNewmarkContact::prepare(const BodyPair& pair, DualContactSolver& dual,
                                       const core::Vector&, ContactStatistics& stats, int step) {
  // Deuflhard–Krause–Ertel: u_pred ← argmin ½‖v − (u^k + τu̇^k)‖²_M over B_n(v − u^k) ≤ g
  // (frictionless: the projection only removes the normal approach), then the position update
  // M(u^{k+1} − u_pred) = τ²/4 (g^k + f^{k+1} − K u^{k+1} − … − Bᵀλ^{k+1}) drops the contact
  // force of step k, which is what made plain Newmark gain energy at the impact.
  auto scope = timers_.scope("qp");
  const auto normal_targets = dual.targets(pair.slave_state.u, pair.master_state.u,
                                           pair.slave_state.u, pair.master_state.u);
  auto& ss = pair.slave;
  auto& sm = pair.master;
  const auto& rows = dual.rows();
  projection_->set_rows(
      {rows.dim, rows.slave.share(), rows.master.share(), rows.gap, rows.weights, rows.nodes});
  core::Vector multipliers(rows.n_rows());
  const std::vector<double> no_friction(static_cast<size_t>(rows.n_nodes()), 0.0);
  ss.u_prev.copy_from(ss.u_pred);
  sm.u_prev.copy_from(sm.u_pred);
  const auto r = projection_->solve(ss.u_prev, sm.u_prev, normal_targets, no_friction, multipliers,
                                    ss.u_pred, sm.u_pred);
  stats.qp_iterations += r.iterations;
  stats.operator_applications += r.operator_applications + projection_->setup_solves() / 2;
  if (!r.converged())
    throw NumericalError(
        fmt::format("the contact-stabilised predictor (mass projection) did not converge: {}",
                    r.message),
        step, 0, r.projected_gradient);
  const double tau = tau_;
  for (auto [s, sys] : {std::pair{&ss, &pair.slave_system}, {&sm, &pair.master_system}}) {
    s->rhs_u_base.copy_from(s->f_u);
    s->rhs_u_base.axpy(1.0, s->g_free);
    sys->matrices().mass_u.mult(s->u_pred, s->work_u);
    s->rhs_u_base.axpy(newmark_mass_factor(tau), s->work_u);
    s->u_new.copy_from(s->u_pred);
  }
}

double StabilisedNewmarkContact::traction_per_multiplier() const {
  return physics::traction_per_multiplier(true);
}

void StabilisedNewmarkContact::save(Checkpoint& c) const {
  projection_->save_compliance(std::span<std::vector<int>, 4>(&c.compliance[4], 4));
}

void StabilisedNewmarkContact::restore(const Checkpoint& c) {
  projection_->replay_compliance(std::span<const std::vector<int>, 4>(&c.compliance[4], 4));
}

}  // namespace tc::physics
