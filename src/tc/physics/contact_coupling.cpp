#include "tc/physics/contact_coupling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/physics/contact_heat.hpp"
#include "tc/physics/time_scheme.hpp"

namespace tc::physics {

namespace {

// The heat–mechanics sweep λ → θ(λ) → λ(θ) of the nested loop contracts (measured on the ch. 7
// examples: by 1e-3 per sweep), so the distance to its fixed point is known before the next
// sweep: with ρ = ‖λ^p − λ^{p−1}‖/‖λ^{p−1} − λ^{p−2}‖, ‖λ* − λ^p‖ ≤ ρ/(1 − ρ)‖λ^p − λ^{p−1}‖
// (contraction mapping), and θ answers λ as in the last sweep, θ^{p+1} − θ^p ≈
// (‖θ^p − θ^{p−1}‖/‖λ^{p−1} − λ^{p−2}‖)(λ^p − λ^{p−1}). Stopping when both are within the
// tolerance saves the sweep that would only confirm it (3.1 → 2.4 sweeps per step on example
// 05). All arguments are relative to ‖λ‖ and ‖θ‖.
bool fixed_point_reached(double lambda_change, double theta_change, double previous_lambda_change,
                         double tol) {
  const double rho = lambda_change / previous_lambda_change;
  if (!(rho <= 0.5)) return false;  // no clear contraction: confirm by another sweep
  const double lambda_left = rho / (1 - rho) * lambda_change;
  const double theta_left = theta_change / previous_lambda_change * lambda_change / (1 - rho);
  return lambda_left <= tol && theta_left <= tol;
}

}  // namespace

void ContactCoupling::enable(ContactRowsBuilder builder, DualContactSettings settings,
                             const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_contact: the problem has no [contact]");
  const auto& c = problem_.contacts.at(0);
  rows_ = finite_rows(std::move(builder), step);
  laws_ = InterfaceLaws(c);
  heat_.set_treatment(problem_.solver.conductance_treatment);
  method_ = choose_contact_method(problem_, bodies_, std::move(settings), timers_);
}

void ContactCoupling::enable_mortar(DualContactSettings settings, contact::MortarOptions options,
                                    const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_mortar_contact: the problem has no [contact]");
  const auto& c = problem_.contacts.at(0);
  {
    auto t = timers_.scope("mortar");
    mortar_ = std::make_unique<contact::MortarPair>(
        problem_.bodies[c.slave_body].mesh, c.slave_where, problem_.bodies[c.master_body].mesh,
        c.master_where, options);
  }
  enable(
      [this](const core::Vector& u_slave, const core::Vector& u_master) {
        mortar_->update(u_slave.to_std(), u_master.to_std());
        return mortar_->rows();
      },
      std::move(settings), step);
}

BodyPair ContactCoupling::pair() {
  return bodies_.pair(problem_.contacts.at(0).slave_body, problem_.contacts.at(0).master_body);
}

double ContactCoupling::traction_per_multiplier() const {
  return method_.scheme ? method_.scheme->traction_per_multiplier()
                        : physics::traction_per_multiplier(false);
}

std::vector<double> ContactCoupling::multipliers() const {
  return lambda_.get() ? lambda_.to_std() : std::vector<double>{};
}

void ContactCoupling::heat_step(int step, int iteration) {
  // (4.3) for the two bodies of the contact pair, backward Euler:
  //   (M_θ/τ + K_θ) θ + L_θγ θ = rhs + d_θγ(u̇)   (ContactHeatCoupling::heat_step),
  // rhs with the thermoelastic term of each body.
  auto scope = timers_.scope("heat_solve");
  const auto& c = problem_.contacts.at(0);
  const auto p = pair();
  const auto& rows = method_.enforcement->dual().rows();
  // 𝔉, β_C, δ_C at the interface temperature of the last iterate (θ^k at the first): fixed
  // for this heat step and the Tresca QPs after it (interface_laws.hpp).
  nodal_laws_ = laws_.at_interface(mortar_.get(), rows, p.slave.theta_new, p.master.theta_new);
  steps_.heat_rhs(c.slave_body);
  steps_.heat_rhs(c.master_body);
  heat_.heat_step(
      problem_, p,
      {mortar_.get(), rows, lambda_, traction_per_multiplier(), iterate_slip_, nodal_laws_},
      step * problem_.time.step, step, iteration);
  require_finite(p.slave.theta_new, "temperature", step, iteration);
  require_finite(p.master.theta_new, "temperature", step, iteration);
}

double ContactCoupling::mech_step(TrescaIteration& t, std::span<const double> targets, int step,
                                  int outer, int max_updates) {
  // The mechanical half of (6.3) at the θ of this iteration: u_free is fixed, so each update
  // of γ costs one QP with the same F and no solve. Nested, the heat–mechanics iterations
  // are left with the thermal coupling alone (docs/choices.md, "friction loop").
  auto scope = timers_.scope("qp");
  const auto& s = problem_.solver;
  const auto p = pair();
  auto& enforcement = *method_.enforcement;
  p.slave.u_prev.copy_from(p.slave.u_new);  // u_free, the QP's data
  p.master.u_prev.copy_from(p.master.u_new);
  const CoulombFixedPoint fp{.dim = enforcement.dual().rows().dim,
                             .friction = nodal_laws_.friction,
                             .frictional = nodal_laws_.frictional,
                             .tolerance = s.coupling_tolerance,
                             .qp_tolerance = s.qp_tolerance,
                             .qp_forcing = s.friction.qp_forcing,
                             .qp_forcing_cap = s.friction.qp_forcing_cap,
                             .loop_forcing = s.friction.loop_forcing,
                             .max_updates = max_updates,
                             .step = step,
                             .outer = outer};
  const double residual = coulomb_fixed_point(t, lambda_, fp, [&](double rtol) {
    enforcement.solve_qp(p, {targets, t.bound, rtol, step, outer}, lambda_, stats_);
    require_finite(lambda_, "contact multiplier", step, outer);
  });
  enforcement.finish_qps(p, lambda_, t, iterate_slip_, step, outer);
  return residual;
}

int ContactCoupling::couple(int step) {
  const auto& c = problem_.contacts.at(0);
  const auto p = pair();
  auto& ss = p.slave;
  auto& sm = p.master;
  const auto& sts = p.slave_state;
  const auto& stm = p.master_state;
  auto& enforcement = *method_.enforcement;
  for (const int b : {c.slave_body, c.master_body})
    begin_step(problem_, *bodies_.systems[b], bodies_.states[b], *bodies_.fields[b],
               step * problem_.time.step);
  stats_.qp_iterations = 0;
  stats_.operator_applications = 0;
  stats_.friction_iterations = 0;
  {
    ContactRows rows;
    {
      auto scope = timers_.scope("mortar");
      rows = rows_(sts.u, stm.u);
    }
    auto scope = timers_.scope("dual_setup");  // F formed explicitly here when it is small
    enforcement.set_rows(std::move(rows));
  }
  auto& dual = enforcement.dual();
  const auto& rows = dual.rows();
  const int dim = rows.dim;
  transfer_.warm_start(rows, mortar_.get(), lambda_);  // λ of the last step on these rows
  method_.scheme->prepare(p, dual, lambda_, stats_, step);
  method_.scheme->slip_reference(p);  // into work_u
  const auto targets = dual.targets(sts.u, stm.u, ss.work_u, sm.work_u);

  TrescaIteration tresca;
  tresca.relax = problem_.solver.friction.acceleration && laws_.frictional();
  // u = u_free − A⁻¹Bᵀλ costs two solves; inside the fixed point only B u is needed (the
  // frictional heat's slip, = B u_free − Fλ) unless the thermoelastic term wants u̇ of the
  // whole body. Then u is formed once, after convergence. Combined, u comes with every QP.
  tresca.defer = !enforcement.qp_gives_displacements() && !(ss.heating || sm.heating);
  iterate_slip_.clear();
  if (tresca.defer) tresca.bu_old = step_slip(rows, sts.u, stm.u);
  stats_.operator_applications += dual.setup_solves() / 2;
  core::Vector lambda_prev = lambda_.clone();
  const bool nested = problem_.solver.friction_loop == FrictionLoop::nested;
  const bool one_way = !(ss.expansion || sm.expansion);
  tresca.cut_short = nested && !one_way;
  const double tol = problem_.solver.coupling_tolerance;
  int iteration = 1;
  double change = 0;
  double sweep_change = -1;  // ‖λ^p − λ^{p−1}‖/‖λ‖ of the previous iteration
  for (; iteration <= problem_.solver.max_coupling_iterations; ++iteration) {
    lambda_prev.copy_from(lambda_);
    ss.theta_prev.copy_from(ss.theta_new);
    sm.theta_prev.copy_from(sm.theta_new);
    heat_step(step, iteration);
    ss.theta_prev.axpy(-1.0, ss.theta_new);
    sm.theta_prev.axpy(-1.0, sm.theta_new);
    const double dth = std::hypot(ss.theta_prev.norm(), sm.theta_prev.norm());
    const double thn = std::hypot(ss.theta_new.norm(), sm.theta_new.norm());
    // Without thermal expansion u_free does not depend on θ: λ of the last iteration (the
    // Coulomb solution to the tolerance) stays exact, and so is this heat step with it, unless
    // the conductance is lagged or depends on θ (then θ itself iterates); not when 𝔉 depends
    // on θ (then λ does).
    const bool theta_iterates =
        heat_.treatment() == ConductanceTreatment::lagged || laws_.conductance_varies();
    if (one_way && tresca.converged && !laws_.friction_varies() &&
        (!theta_iterates || dth <= tol * thn)) {
      change = thn > 0 ? dth / thn : dth;
      break;
    }
    if (enforcement.qp_gives_displacements()) {  // the loads only: the QP solves for u itself
      auto scope = timers_.scope("mechanical_solve");
      steps_.mech_load(c.slave_body, step);
      steps_.mech_load(c.master_body, step);
    } else {
      steps_.mech_step(c.slave_body, step, iteration);  // u_free = A⁻¹f with the Dirichlet data
      steps_.mech_step(c.master_body, step, iteration);
    }
    // Nested: γ = λ_n(γ) to convergence at this θ, Aitken restarted (the map changed with θ);
    // staggered: one update, the relaxation carried over the heat–mechanics iterations.
    if (nested || tresca.gamma.empty()) tresca.restart(lambda_, dim, nodal_laws_.friction);
    const double fixed_residual = mech_step(tresca, targets, step, iteration,
                                            nested ? problem_.solver.friction.max_updates : 1);
    lambda_prev.axpy(-1.0, lambda_);
    const double dl = lambda_prev.norm(), ln = lambda_.norm();
    const double rl = ln > 0 ? dl / ln : dl, rth = thn > 0 ? dth / thn : dth;
    change = std::max({rl, rth, ln > 0 ? fixed_residual / ln : fixed_residual});
    const bool friction_met = fixed_residual <= tol * ln && tresca.converged;
    if (dl <= tol * ln && dth <= tol * thn && friction_met) break;
    if (nested && friction_met && sweep_change > 0 &&
        fixed_point_reached(rl, rth, sweep_change, tol))
      break;
    sweep_change = rl;
  }
  if (iteration > problem_.solver.max_coupling_iterations)
    throw NumericalError(
        fmt::format("the staggered fixed point (6.3) with contact did not converge to {:.1e}", tol),
        step, iteration - 1, change);
  iterate_slip_.clear();
  qp_bound_ = std::move(tresca.qp_bound);  // empty without friction
  if (tresca.defer) {                      // u_new holds u_free of the last iteration
    auto scope = timers_.scope("qp");
    dual.recover(lambda_, ss.u_new, sm.u_new);
  }
  require_finite(ss.u_new, "displacement", step, iteration);
  require_finite(sm.u_new, "displacement", step, iteration);

  // The slip increment B_τ(u^{k+1} − u^k) for the dissipation, before the state moves on.
  ss.work_u.copy_from(ss.u_new);
  ss.work_u.axpy(-1.0, sts.u);
  sm.work_u.copy_from(sm.u_new);
  sm.work_u.axpy(-1.0, stm.u);
  slip_ = step_slip(rows, ss.work_u, sm.work_u);
  // Heat through the interface in this step, with the L and d of the last heat step (those
  // that produced θ^{k+1}): then the thermal energy balance of the pair closes to round-off.
  heat_.account_step(p, problem_.time.step);
  for (const int b : {c.slave_body, c.master_body})
    end_step(problem_, *bodies_.systems[b], bodies_.states[b], *bodies_.fields[b]);
  return iteration;
}

void ContactCoupling::bookkeeping() {
  const auto& rows = method_.enforcement->dual().rows();
  const auto l = lambda_.to_std();
  const double unit = traction_per_multiplier();
  stats_.record_step(rows, l, slip_, unit, qp_bound_, mortar_.get());
  if (mortar_) {  // q = β_C λ_n [θ] per contact node (contact_heat.hpp)
    const auto& c = problem_.contacts.at(0);
    heat_flux_.assign(static_cast<size_t>(rows.n_nodes()), 0.0);
    if (c.heat_conduction && nodal_laws_.conducting &&
        mortar_->contact_nodes().size() == static_cast<size_t>(rows.n_nodes())) {
      std::vector<double> scale(nodal_laws_.beta_c);
      for (double& s : scale) s *= unit;
      heat_flux_ = conduction_flux(*mortar_, rows, l, scale, bodies_.states[c.slave_body].theta,
                                   bodies_.states[c.master_body].theta);
    }
  }
  total_qp_ += stats_.qp_iterations;
  total_applications_ += stats_.operator_applications;
}

void ContactCoupling::save(Checkpoint& c) const {
  c.lambda = multipliers();
  transfer_.save(c);
  if (enabled()) {
    method_.enforcement->save(c);
    method_.scheme->save(c);
  }
  c.slip = slip_;
  c.heat_flux = heat_flux_;
  c.total_qp = total_qp_;
  c.total_applications = total_applications_;
  c.contact = stats_;
  c.heat = heat_.heat();
}

void ContactCoupling::restore(const Checkpoint& c) {
  if (c.lambda.size() != c.lambda_nodes.size() * static_cast<size_t>(problem_.dimension) &&
      !c.lambda_nodes.empty())
    throw Error("checkpoint: the multipliers do not match their contact nodes");
  lambda_ = c.lambda.empty() ? core::Vector() : core::Vector::from(c.lambda);
  transfer_.restore(c);
  if (enabled()) {
    method_.enforcement->restore(c);
    method_.scheme->restore(c);
  }
  slip_ = c.slip;
  heat_flux_ = c.heat_flux;
  total_qp_ = c.total_qp;
  total_applications_ = c.total_applications;
  stats_ = c.contact;
  heat_.heat() = c.heat;
}

}  // namespace tc::physics
