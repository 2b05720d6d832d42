#include "tc/physics/contact/step/contact_time_scheme.hpp"

#include <fmt/format.h>

#include "tc/core/error.hpp"
#include "tc/physics/body/time_scheme.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"

namespace tc::physics {

double ContactTimeScheme::traction_per_multiplier() const {
  return physics::traction_per_multiplier(false);
}

void QuasistaticContact::slip_reference(const BodyGroup& group) const {
  for (int i = 0; i < group.size(); ++i) group.fields[i]->work_u.copy_from(group.states[i]->u);
}

void PlainNewmarkContact::slip_reference(const BodyGroup& group) const {
  // u_pred − τ/2 u̇^k (= u^k + τ/2 u̇^k unless the predictor was projected), so that
  // B_τu − c_τ = τ/2 B_τu̇^{k+1} (5.4).
  for (int i = 0; i < group.size(); ++i) {
    auto& f = *group.fields[i];
    f.work_u.copy_from(f.u_pred);
    f.work_u.axpy(-0.5 * tau_, group.states[i]->v);
  }
}

void ModifiedMassContact::slip_reference(const BodyGroup& group) const {
  // The contact nodes have no inertia (massless_rates): B_τu − c_τ = τ B_τu̇^{k+1}.
  for (int i = 0; i < group.size(); ++i) group.fields[i]->work_u.copy_from(group.states[i]->u);
}

StabilisedNewmarkContact::StabilisedNewmarkContact(const Problem& p, Bodies& bodies,
                                                   const std::vector<int>& members,
                                                   const DualContactSettings& settings,
                                                   core::PhaseTimers& timers)
    : PlainNewmarkContact(p.time.step), timers_(timers) {
  auto t = timers_.scope("factorization");
  std::vector<const ConstrainedSolver*> mass;
  std::vector<PetscInt> n_u;
  for (const int b : members) {
    auto& sv = *bodies.fields[b];
    sv.mass = body_solver(p, *bodies.systems[b], bodies.systems[b]->matrices().mass_u,
                          BodyOperator::mass);
    mass.push_back(sv.mass.get());
    n_u.push_back(bodies.systems[b]->n_u());
  }
  projection_ = std::make_unique<DualContactSolver>(std::move(mass), std::move(n_u), settings);
}

void StabilisedNewmarkContact::prepare(const BodyGroup& group, DualContactSolver& dual,
                                       const core::Vector&, ContactStatistics& stats, int step) {
  // Deuflhard–Krause–Ertel: u_pred ← argmin ½‖v − (u^k + τu̇^k)‖²_M over B_n(v − u^k) ≤ g
  // (frictionless: the projection only removes the normal approach), then the position update
  // M(u^{k+1} − u_pred) = τ²/4 (g^k + f^{k+1} − K u^{k+1} − … − Bᵀλ^{k+1}) drops the contact
  // force of step k, which is what made plain Newmark gain energy at the impact.
  auto scope = timers_.scope("qp");
  const auto u_k = group.state(&BodyState::u);
  const auto normal_targets = dual.targets(u_k, u_k);
  std::vector<ContactRows> rows;
  for (int q = 0; q < dual.n_pairs(); ++q) rows.push_back(dual.pair_rows(q).shared());
  projection_->set_rows(std::move(rows), dual.pair_bodies());
  projection_->hold_at_zero(dual.held());  // the crosspoints of the contact QP here too
  core::Vector multipliers(dual.n_rows());
  const std::vector<double> no_friction(static_cast<size_t>(dual.n_nodes()), 0.0);
  for (auto* f : group.fields) f->u_prev.copy_from(f->u_pred);
  const auto r = projection_->solve(group.field_in(&BodyField::u_prev), normal_targets, no_friction,
                                    multipliers, group.field(&BodyField::u_pred));
  stats.qp_iterations += r.iterations;
  stats.operator_applications +=
      r.operator_applications + projection_->setup_solves() / group.size();
  if (!r.converged())
    throw NumericalError(
        fmt::format("the contact-stabilised predictor (mass projection) did not converge: {}",
                    r.message),
        step, 0, r.projected_gradient);
  const double tau = tau_;
  for (int i = 0; i < group.size(); ++i) {
    auto* s = group.fields[i];
    s->rhs_u_base.copy_from(s->f_u);
    s->rhs_u_base.axpy(1.0, s->g_free);
    group.systems[i]->matrices().mass_u.mult(s->u_pred, s->work_u);
    s->rhs_u_base.axpy(newmark_mass_factor(tau), s->work_u);
    s->u_new.copy_from(s->u_pred);
  }
}

double StabilisedNewmarkContact::traction_per_multiplier() const {
  return physics::traction_per_multiplier(true);
}

void StabilisedNewmarkContact::save(Checkpoint& c) const {
  c.stabiliser_compliance.clear();
  projection_->save_compliance(c.stabiliser_compliance);
}

void StabilisedNewmarkContact::restore(const Checkpoint& c) {
  projection_->replay_compliance(c.stabiliser_compliance);
}

}  // namespace tc::physics
