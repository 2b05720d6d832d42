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

void ContactCoupling::add_pairs() {
  group_ = ContactGroup(problem_);
  pairs_.clear();
  pairs_.resize(problem_.contacts.size());
  for (size_t q = 0; q < pairs_.size(); ++q) {
    auto& pr = pairs_[q];
    const auto& c = problem_.contacts[q];
    pr.settings = &c;
    pr.bodies = group_.pairs[q];
    pr.laws = InterfaceLaws(c);
    // Crosspoints: a node on the slave surfaces of two pairs would carry two multipliers on the
    // same dofs (F singular along their difference, docs/choices.md): the first pair keeps it.
    const auto& mesh = problem_.bodies[c.slave_body].mesh;
    pr.crosspoint.assign(static_cast<size_t>(mesh.n_nodes()), 0);
    for (size_t e = 0; e < q; ++e) {
      const auto& earlier = problem_.contacts[e];
      if (earlier.slave_body != c.slave_body) continue;
      std::vector<char> on(static_cast<size_t>(mesh.n_nodes()), 0);
      for (const int a : mesh.boundary_nodes(earlier.slave_where)) on[a] = 1;
      for (const int a : mesh.boundary_nodes(c.slave_where))
        if (on[a]) pr.crosspoint[a] = 1;
    }
  }
  heat_.set_pairs(pairs_.size());
  heat_.set_treatment(problem_.solver.conductance_treatment);
}

void ContactCoupling::enable(ContactRowsBuilder builder, DualContactSettings settings,
                             const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_contact: the problem has no [contact]");
  if (problem_.contacts.size() != 1)
    throw Error("enable_contact: rows from a builder are for one contact pair");
  pairs_.front().rows = finite_rows(std::move(builder), step);
  method_ = choose_contact_method(problem_, bodies_, std::move(settings), timers_);
}

void ContactCoupling::enable_mortar(DualContactSettings settings, contact::MortarOptions options,
                                    const int& step) {
  if (problem_.contacts.empty()) throw Error("enable_mortar_contact: the problem has no [contact]");
  for (auto& pr : pairs_) {
    const auto& c = *pr.settings;
    {
      auto t = timers_.scope("mortar");
      pr.mortar = std::make_unique<contact::MortarPair>(
          problem_.bodies[c.slave_body].mesh, c.slave_where, problem_.bodies[c.master_body].mesh,
          c.master_where, options);
    }
    auto* mortar = pr.mortar.get();
    pr.rows = finite_rows(
        [mortar](const core::Vector& u_slave, const core::Vector& u_master) {
          mortar->update(u_slave.to_std(), u_master.to_std());
          return mortar->rows();
        },
        step);
  }
  method_ = choose_contact_method(problem_, bodies_, std::move(settings), timers_);
}

BodyGroup ContactCoupling::group() {
  return bodies_.group(group_.members);
}

bool ContactCoupling::any_pair(bool (InterfaceLaws::*law)() const) const {
  return std::any_of(pairs_.begin(), pairs_.end(),
                     [&](const auto& pr) { return (pr.laws.*law)(); });
}

double ContactCoupling::traction_per_multiplier() const {
  return method_.scheme ? method_.scheme->traction_per_multiplier()
                        : physics::traction_per_multiplier(false);
}

std::vector<double> ContactCoupling::multipliers() const {
  return lambda_.get() ? lambda_.to_std() : std::vector<double>{};
}

namespace {

/// Entries [dim·from, dim·to) of a node-major vector.
std::vector<double> nodes_of(std::span<const double> v, int dim, PetscInt from, PetscInt to) {
  if (static_cast<PetscInt>(v.size()) < dim * to) return {};
  return {v.begin() + dim * from, v.begin() + dim * to};
}

}  // namespace

std::vector<double> ContactCoupling::multipliers(int q) const {
  if (lambda_at_.size() < pairs_.size() + 1) return {};
  return nodes_of(multipliers(), problem_.dimension, lambda_at_[q], lambda_at_[q + 1]);
}

std::vector<double> ContactCoupling::heat_flux() const {
  std::vector<double> all;
  for (const auto& pr : pairs_) all.insert(all.end(), pr.heat_flux.begin(), pr.heat_flux.end());
  return all;
}

std::vector<double> ContactCoupling::slip(int q) const {
  if (lambda_at_.size() < pairs_.size() + 1) return {};
  return nodes_of(slip_, problem_.dimension, lambda_at_[q], lambda_at_[q + 1]);
}

void ContactCoupling::register_history(History& h) const {
  stats_.register_history(h);
  heat_.heat().register_history(h);
  if (pairs_.size() < 2) return;
  for (size_t q = 0; q < pairs_.size(); ++q) {
    const std::string suffix = "_" + pairs_[q].settings->name;
    pairs_[q].stats.register_pair_history(h, suffix);
    heat_.pair_heat()[q].register_history(h, suffix);
  }
}

void ContactCoupling::interface_laws() {
  // 𝔉, β_C, δ_C at the interface temperature of the last iterate (θ^k at the first): fixed
  // for this coupling iteration's heat step and Tresca QPs (interface_laws.hpp).
  auto g = group();
  const auto& dual = method_.enforcement->dual();
  nodal_laws_ = {};
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    pr.nodal = pr.laws.at_interface(pr.mortar.get(), dual.pair_rows(q),
                                    g.fields[pr.bodies.slave]->theta_new,
                                    g.fields[pr.bodies.master]->theta_new);
    auto& all = nodal_laws_;
    for (auto [to, from] : {std::pair{&all.friction, &pr.nodal.friction},
                            {&all.beta_c, &pr.nodal.beta_c},
                            {&all.delta_c, &pr.nodal.delta_c}})
      to->insert(to->end(), from->begin(), from->end());
    all.frictional = all.frictional || pr.nodal.frictional;
    all.conducting = all.conducting || pr.nodal.conducting;
  }
}

void ContactCoupling::heat_step(int step, int iteration) {
  // (4.3) for the bodies of the contact pairs, backward Euler:
  //   (M_θ/τ + K_θ) θ + Σ L_θγ θ = rhs + Σ d_θγ(u̇)   (ContactHeatCoupling::heat_step),
  // rhs with the thermoelastic term of each body.
  auto scope = timers_.scope("heat_solve");
  auto g = group();
  const auto& dual = method_.enforcement->dual();
  for (const int b : group_.members) steps_.heat_rhs(b);
  const auto lambda = lambda_.to_std();
  const double unit = traction_per_multiplier();
  const int dim = dual.dim();
  std::vector<ContactIterate> iterates;
  for (int q = 0; q < n_pairs(); ++q) {
    const auto& pr = pairs_[q];
    const auto from = static_cast<size_t>(dim * dual.pair_offset(q));
    const auto to = static_cast<size_t>(dim * dual.pair_offset(q + 1));
    iterates.push_back({*pr.settings, pr.bodies, pr.mortar.get(), dual.pair_rows(q),
                        std::span(lambda).subspan(from, to - from), unit,
                        iterate_slip_.empty()
                            ? std::span<const double>()
                            : std::span<const double>(iterate_slip_).subspan(from, to - from),
                        pr.nodal});
  }
  heat_.heat_step(problem_, g, iterates, step * problem_.time.step, step, iteration);
  for (const auto* f : g.fields) require_finite(f->theta_new, "temperature", step, iteration);
}

double ContactCoupling::mech_step(TrescaIteration& t, std::span<const double> targets, int step,
                                  int outer, int max_updates) {
  // The mechanical half of (6.3) at the θ of this iteration: u_free is fixed, so each update
  // of γ costs one QP with the same F and no solve. Nested, the heat–mechanics iterations
  // are left with the thermal coupling alone (docs/choices.md, "friction loop").
  auto scope = timers_.scope("qp");
  const auto& s = problem_.solver;
  const auto g = group();
  auto& enforcement = *method_.enforcement;
  for (auto* f : g.fields) f->u_prev.copy_from(f->u_new);  // u_free, the QP's data
  const CoulombFixedPoint fp{.dim = enforcement.dual().dim(),
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
    enforcement.solve_qp(g, {targets, t.bound, rtol, step, outer}, lambda_, stats_);
    require_finite(lambda_, "contact multiplier", step, outer);
  });
  enforcement.finish_qps(g, lambda_, t, iterate_slip_, step, outer);
  return residual;
}

void ContactCoupling::set_rows(BodyGroup& g) {
  auto& enforcement = *method_.enforcement;
  {
    std::vector<ContactRows> rows;
    {
      auto scope = timers_.scope("mortar");
      for (const auto& pr : pairs_)
        rows.push_back(pr.rows(g.states[pr.bodies.slave]->u, g.states[pr.bodies.master]->u));
    }
    auto scope = timers_.scope("dual_setup");  // F formed explicitly here when it is small
    enforcement.set_rows(std::move(rows), group_.pairs);
  }
  auto& dual = enforcement.dual();
  const int dim = dual.dim();
  // λ of the last step on these rows, pair by pair (each pair's nodes where they were; one pair
  // without the last step's node counts, from a test's rows: all of λ, by position).
  const auto previous = multipliers();
  const bool known = lambda_at_.size() == pairs_.size() + 1;
  std::vector<double> next;
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    core::Vector lq;
    if (known)
      lq = core::Vector::from(nodes_of(previous, dim, lambda_at_[q], lambda_at_[q + 1]));
    else if (n_pairs() == 1 && !previous.empty())
      lq = core::Vector::from(previous);
    pr.transfer.warm_start(dual.pair_rows(q), pr.mortar.get(), lq);
    const auto v = lq.to_std();
    next.insert(next.end(), v.begin(), v.end());
  }
  lambda_ = core::Vector::from(next);
  lambda_at_.clear();
  for (int q = 0; q <= n_pairs(); ++q) lambda_at_.push_back(dual.pair_offset(q));
  // Crosspoints: a later pair's multipliers held at 0 (λ_n ∈ [0, 0], no friction) where an
  // earlier pair with the same slave body has the node too and their normals there are less than
  // 60° apart (docs/choices.md, "Crosspoints"): the two rows would be (nearly) dependent.
  std::vector<char> held(static_cast<size_t>(dual.n_nodes()), 0);
  bool any = false;
  for (int q = 1; q < n_pairs(); ++q) {
    const auto& pr = pairs_[q];
    const auto& nodes = dual.pair_rows(q).nodes;
    for (size_t k = 0; k < nodes.size(); ++k) {
      if (!pr.crosspoint[nodes[k]]) continue;
      bool hold = !pr.mortar;  // a test's rows: no normals to compare
      for (int e = 0; e < q && !hold; ++e) {
        const auto& earlier = pairs_[e];
        if (earlier.settings->slave_body != pr.settings->slave_body || !earlier.mortar) continue;
        const int at = earlier.mortar->contact_index(nodes[k]);
        if (at < 0) continue;
        const auto& a = earlier.mortar->normals()[at];
        const auto& b = pr.mortar->normals()[k];
        hold = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] >= 0.5;
      }
      if (hold) {
        held[static_cast<size_t>(dual.pair_offset(q)) + k] = 1;
        any = true;
      }
    }
  }
  if (any) {
    dual.hold_at_zero(std::move(held));
    auto lv = lambda_.view();
    for (PetscInt k = 0; k < dual.n_nodes(); ++k)
      if (dual.held_at_zero(k))
        for (int i = 0; i < dim; ++i) lv[dim * k + i] = 0;
  }
}

int ContactCoupling::couple(int step) {
  auto g = group();
  auto& enforcement = *method_.enforcement;
  for (int i = 0; i < g.size(); ++i)
    begin_step(problem_, *g.systems[i], bodies_.states[g.index[i]], *g.fields[i],
               step * problem_.time.step);
  stats_.qp_iterations = 0;
  stats_.operator_applications = 0;
  stats_.friction_iterations = 0;
  set_rows(g);
  auto& dual = enforcement.dual();
  const int dim = dual.dim();
  method_.scheme->prepare(g, dual, lambda_, stats_, step);
  method_.scheme->slip_reference(g);  // into work_u
  const auto targets = dual.targets(g.state(&BodyState::u), g.field_in(&BodyField::work_u));

  bool heating = false, expansion = false;
  for (const auto* f : g.fields) {
    heating = heating || f->heating;
    expansion = expansion || f->expansion;
  }
  TrescaIteration tresca;
  tresca.relax = problem_.solver.friction.acceleration && any_pair(&InterfaceLaws::frictional);
  // u = u_free − A⁻¹Bᵀλ costs a solve per body; inside the fixed point only B u is needed (the
  // frictional heat's slip, = B u_free − Fλ) unless the thermoelastic term wants u̇ of the
  // whole body. Then u is formed once, after convergence. Combined, u comes with every QP.
  tresca.defer = !enforcement.qp_gives_displacements() && !heating;
  iterate_slip_.clear();
  if (tresca.defer) tresca.bu_old = dual.row_values(g.state(&BodyState::u));
  // An application of F is a solve per body: the set-up's solves in those units.
  stats_.operator_applications += dual.setup_solves() / g.size();
  core::Vector lambda_prev = lambda_.clone();
  const bool nested = problem_.solver.friction_loop == FrictionLoop::nested;
  const bool one_way = !expansion;
  tresca.cut_short = nested && !one_way;
  const double tol = problem_.solver.coupling_tolerance;
  const auto norm = [&](core::Vector BodyField::*v) {  // ‖·‖ over the group, as one vector
    double sq = 0;
    for (const auto* f : g.fields) sq = std::hypot(sq, (f->*v).norm());
    return sq;
  };
  // Without thermal expansion u_free does not depend on θ: λ at the Coulomb solution (to the
  // tolerance) stays exact, and so is the heat step with it, unless the conductance is lagged
  // or depends on θ (then θ itself iterates); not when 𝔉 depends on θ (then λ does).
  const bool theta_iterates = heat_.treatment() == ConductanceTreatment::lagged ||
                              any_pair(&InterfaceLaws::conductance_varies);
  const bool lambda_final = one_way && !any_pair(&InterfaceLaws::friction_varies);
  const bool heat_first = heat_before_mechanics(problem_.solver.coupling_order, heating);
  double dth = 0, thn = 0;
  // The heat step just taken was the last one needed: it had the final λ (λ_converged).
  const auto heat_was_last = [&](bool lambda_converged) {
    return lambda_final && lambda_converged && (!theta_iterates || dth <= tol * thn);
  };
  const auto heat_half = [&](int iteration) {  // θ^{p+1} and ‖θ^{p+1} − θ^p‖
    for (auto* f : g.fields) f->theta_prev.copy_from(f->theta_new);
    heat_step(step, iteration);
    for (auto* f : g.fields) f->theta_prev.axpy(-1.0, f->theta_new);
    dth = norm(&BodyField::theta_prev);
    thn = norm(&BodyField::theta_new);
  };
  const auto mechanical_half = [&](int iteration) {  // u_free, then the Coulomb QPs: residual
    if (enforcement.qp_gives_displacements()) {      // the loads only: the QP solves for u itself
      auto scope = timers_.scope("mechanical_solve");
      for (const int b : group_.members) steps_.mech_load(b, step);
    } else if (tresca.defer) {  // u_free = A⁻¹f with the Dirichlet data
      for (const int b : group_.members) steps_.mech_step(b, step, iteration);
    } else {
      // The same, by halves where that saves a backward solve: finish_qps recovers u at once.
      auto scope = timers_.scope("mechanical_solve");
      for (int i = 0; i < g.size(); ++i) {
        steps_.mech_load(group_.members[static_cast<size_t>(i)], step);
        auto& f = *g.fields[i];
        enforcement.dual().solve_free(i, f.rhs_u, f.u_new, lambda_);
        require_finite(f.u_new, "displacement", step, iteration);
      }
    }
    // Nested: γ = λ_n(γ) to convergence at this θ, Aitken restarted (the map changed with θ);
    // staggered: one update, the relaxation carried over the heat–mechanics iterations.
    if (nested || tresca.gamma.empty()) tresca.restart(lambda_, dim, nodal_laws_.friction);
    return mech_step(tresca, targets, step, iteration,
                     nested ? problem_.solver.friction.max_updates : 1);
  };
  int iteration = 1;
  double change = 0;
  double sweep_change = -1;  // ‖λ^p − λ^{p−1}‖/‖λ‖ of the previous iteration
  for (; iteration <= problem_.solver.max_coupling_iterations; ++iteration) {
    lambda_prev.copy_from(lambda_);
    interface_laws();
    double fixed_residual = 0;
    if (heat_first) {
      heat_half(iteration);
      if (heat_was_last(tresca.converged)) {  // λ of the last iteration
        change = thn > 0 ? dth / thn : dth;
        break;
      }
      fixed_residual = mechanical_half(iteration);
    } else {
      fixed_residual = mechanical_half(iteration);
      heat_half(iteration);
    }
    lambda_prev.axpy(-1.0, lambda_);
    const double dl = lambda_prev.norm(), ln = lambda_.norm();
    const double rl = ln > 0 ? dl / ln : dl, rth = thn > 0 ? dth / thn : dth;
    change = std::max({rl, rth, ln > 0 ? fixed_residual / ln : fixed_residual});
    const bool friction_met = fixed_residual <= tol * ln && tresca.converged;
    if (!heat_first && heat_was_last(friction_met)) break;  // λ of this iteration
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
    dual.recover(lambda_, g.field(&BodyField::u_new));
  }
  for (const auto* f : g.fields) require_finite(f->u_new, "displacement", step, iteration);

  // The slip increment B_τ(u^{k+1} − u^k) for the dissipation, before the state moves on.
  for (int i = 0; i < g.size(); ++i) {
    g.fields[i]->work_u.copy_from(g.fields[i]->u_new);
    g.fields[i]->work_u.axpy(-1.0, g.states[i]->u);
  }
  slip_ = dual.row_values(g.field_in(&BodyField::work_u));
  // Heat through the interface in this step, with the L and d of the last heat step (those
  // that produced θ^{k+1}): then the thermal energy balance of the bodies closes to round-off.
  heat_.account_step(g, problem_.time.step);
  for (int i = 0; i < g.size(); ++i)
    end_step(problem_, *g.systems[i], bodies_.states[g.index[i]], *g.fields[i]);
  return iteration;
}

void ContactCoupling::bookkeeping() {
  const auto& dual = method_.enforcement->dual();
  const auto l = lambda_.to_std();
  const double unit = traction_per_multiplier();
  const int dim = dual.dim();
  for (int q = 0; q < n_pairs(); ++q) {
    auto& pr = pairs_[q];
    const PetscInt from = dual.pair_offset(q), to = dual.pair_offset(q + 1);
    const auto& rows = dual.pair_rows(q);
    const auto lq = nodes_of(l, dim, from, to);
    const auto bound = qp_bound_.empty()
                           ? std::vector<double>{}
                           : std::vector<double>(qp_bound_.begin() + from, qp_bound_.begin() + to);
    pr.stats.record_step(rows, lq, nodes_of(slip_, dim, from, to), unit, bound, pr.mortar.get());
    if (pr.mortar) {  // q = β_C λ_n [θ] per contact node (contact_heat.hpp)
      const auto& c = *pr.settings;
      pr.heat_flux.assign(static_cast<size_t>(rows.n_nodes()), 0.0);
      if (c.heat_conduction && pr.nodal.conducting &&
          pr.mortar->contact_nodes().size() == static_cast<size_t>(rows.n_nodes())) {
        std::vector<double> scale(pr.nodal.beta_c);
        for (double& s : scale) s *= unit;
        pr.heat_flux =
            conduction_flux(*pr.mortar, rows, lq, scale, bodies_.states[c.slave_body].theta,
                            bodies_.states[c.master_body].theta);
      }
    }
  }
  sum_pair_statistics();
  total_qp_ += stats_.qp_iterations;
  total_applications_ += stats_.operator_applications;
}

void ContactCoupling::save(Checkpoint& c) const {
  c.lambda = multipliers();
  c.pairs.clear();
  for (size_t q = 0; q < pairs_.size(); ++q) {
    Checkpoint::Pair record;
    pairs_[q].transfer.save(record);
    record.contact = pairs_[q].stats;
    if (q < heat_.pair_heat().size()) record.heat = heat_.pair_heat()[q];
    c.pairs.push_back(std::move(record));
  }
  if (enabled()) {
    method_.enforcement->save(c);
    method_.scheme->save(c);
  }
  heat_.save(c);
  c.slip = slip_;
  c.heat_flux = heat_flux();
  c.total_qp = total_qp_;
  c.total_applications = total_applications_;
}

void ContactCoupling::restore(const Checkpoint& c) {
  if (c.pairs.size() != pairs_.size())
    throw Error("checkpoint: the contact pairs do not match the case's");
  size_t nodes = 0;
  bool named = true;
  for (const auto& pr : c.pairs) {
    nodes += pr.lambda_nodes.size();
    named = named && !pr.lambda_nodes.empty();
  }
  if (named && c.lambda.size() != nodes * static_cast<size_t>(problem_.dimension))
    throw Error("checkpoint: the multipliers do not match their contact nodes");
  lambda_ = c.lambda.empty() ? core::Vector() : core::Vector::from(c.lambda);
  lambda_at_.assign(1, 0);
  for (const auto& pr : c.pairs)
    lambda_at_.push_back(lambda_at_.back() + static_cast<PetscInt>(pr.lambda_nodes.size()));
  if (!named) lambda_at_.clear();  // a test's rows without nodes: by position, one pair
  std::vector<ContactHeat> heat;
  for (size_t q = 0; q < pairs_.size(); ++q) {
    auto& pr = pairs_[q];
    pr.transfer.restore(c.pairs[q]);
    pr.stats = c.pairs[q].contact;
    heat.push_back(c.pairs[q].heat);
    // The flux is written per contact node of the pairs with a mortar pair, pair after pair.
    pr.heat_flux.clear();
    if (named && pr.mortar && c.heat_flux.size() >= static_cast<size_t>(lambda_at_.back()))
      pr.heat_flux.assign(c.heat_flux.begin() + lambda_at_[q],
                          c.heat_flux.begin() + lambda_at_[q + 1]);
    else if (pr.mortar && pairs_.size() == 1)
      pr.heat_flux = c.heat_flux;
  }
  heat_.set_pair_heat(heat);
  if (enabled()) {
    method_.enforcement->restore(c);
    method_.scheme->restore(c);
  }
  heat_.restore(c, problem_, group());
  slip_ = c.slip;
  total_qp_ = c.total_qp;
  total_applications_ = c.total_applications;
  stats_ = {};
  sum_pair_statistics();
}

void ContactCoupling::sum_pair_statistics() {
  // The tangential force is the sum of the pairs' resultants' magnitudes (docs/choices.md).
  stats_.normal_force = stats_.tangential_force = stats_.tangential_force_sum = 0;
  stats_.dissipation = 0;
  stats_.active_nodes = stats_.slip_nodes = 0;
  for (const auto& pr : pairs_) {
    stats_.normal_force += pr.stats.normal_force;
    stats_.tangential_force += pr.stats.tangential_force;
    stats_.tangential_force_sum += pr.stats.tangential_force_sum;
    stats_.dissipation += pr.stats.dissipation;
    stats_.active_nodes += pr.stats.active_nodes;
    stats_.slip_nodes += pr.stats.slip_nodes;
  }
}

}  // namespace tc::physics
