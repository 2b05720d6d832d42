// What a coupled contact step leaves behind (ContactCoupling, contact_coupling.hpp): the
// tangential multipliers scaled into their cones after a loose fixed point, the contact laws
// checked at every node, the step's statistics, its history columns and values (the resultant
// force on the slave), and the checkpoint part: everything of the step after its staggered loop.
// contact_coupling.cpp holds the pairs, the rows and the staggered loop (6.3).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "tc/core/error.hpp"
#include "tc/physics/body/time_scheme.hpp"
#include "tc/physics/contact/step/contact_coupling.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"
#include "tc/physics/interface_heat/gap_conductance.hpp"

namespace tc::physics {

std::array<double, 3> ContactCoupling::slave_force(int q, std::span<const double> lq) const {
  // Σ_d (B_sᵀλ)_d over the dofs of one axis is the resultant of the nodal forces the rows
  // put on the slave body, normal and tangential parts and the normals' tilt included: it is
  // what the slave's equilibrium balances, where Σ_k w_kλ_n,k is not (docs/case-format.md).
  std::array<double, 3> f{0, 0, 0};
  if (lq.empty()) return f;
  const auto& rows = method_.enforcement->dual().pair_rows(q);
  const int dim = problem_.dimension;
  const auto& mesh = problem_.bodies[pairs_[q].settings->slave_body].mesh;
  core::Vector bl(dim * static_cast<PetscInt>(mesh.n_nodes()));
  rows.slave.mult_transpose_add(core::Vector::from(lq), bl);
  const auto v = bl.read();
  const double unit = traction_per_multiplier();
  for (PetscInt d = 0; d < bl.size(); ++d) f[static_cast<size_t>(d % dim)] -= unit * v[d];
  return f;
}

void ContactCoupling::register_history(History& h) const {
  stats_.register_history(h);
  const auto gap = [&](const ContactPairState& pr) {
    return pr.settings->gap_conductance.has_value();
  };
  heat_.heat().register_history(h, "", std::any_of(pairs_.begin(), pairs_.end(), gap));
  // The resultant contact force on the slave bodies (added after the standard columns and the
  // reactions, so that a case without contact keeps its columns).
  const char* axes = "xyz";
  const auto force_columns = [&](const std::array<double, 3>& f, const std::string& suffix) {
    if (pairs_.empty()) return;
    for (int k = 0; k < problem_.dimension; ++k)
      h.add(std::string("contact_force_") + axes[k] + suffix, History::value_of(f[k]));
  };
  force_columns(slave_force_, "");
  if (pairs_.size() < 2) return;
  for (size_t q = 0; q < pairs_.size(); ++q) {
    const std::string suffix = "_" + pairs_[q].settings->name;
    pairs_[q].stats.register_pair_history(h, suffix);
    heat_.pair_heat()[q].register_history(h, suffix, gap(pairs_[q]));
    force_columns(pairs_[q].slave_force, suffix);
  }
}

void ContactCoupling::scale_into_cones(const BodyGroup& g, bool u_formed) {
  auto& dual = method_.enforcement->dual();
  const int dim = dual.dim();
  const auto& friction = nodal_laws_.friction;
  auto l = lambda_.to_std();
  std::vector<double> delta(l.size(), 0.0);  // λ' − λ
  bool any = false;
  for (size_t k = 0; k < friction.size() && dim * (k + 1) <= l.size(); ++k) {
    const size_t r = dim * k;
    double lt2 = 0;
    for (int i = 1; i < dim; ++i) lt2 += l[r + i] * l[r + i];
    const double lt = std::sqrt(lt2), cap = friction[k] * std::max(l[r], 0.0);
    if (!(lt > cap)) continue;
    for (int i = 1; i < dim; ++i) {
      const double scaled = l[r + i] * (cap / lt);
      delta[r + i] = scaled - l[r + i];
      l[r + i] = scaled;
    }
    // On its Coulomb circle now: a slipping node (ContactStatistics' test against the bound).
    if (k < qp_bound_.size()) qp_bound_[k] = cap;
    any = true;
  }
  if (!any) return;
  lambda_ = core::Vector::from(l);
  // u = u_free − A⁻¹Bᵀλ' = u − A⁻¹Bᵀ(λ' − λ): the equilibrium with the scaled multipliers.
  if (u_formed) dual.recover(core::Vector::from(delta), g.field(&BodyField::u_new));
}

void ContactCoupling::check_laws(const BodyGroup& g, std::span<const double> targets, int step) {
  const auto& enforcement = *method_.enforcement;
  const auto& dual = enforcement.dual();
  const int dim = dual.dim();
  const auto bu = dual.row_values(g.field_in(&BodyField::u_new));
  const auto l = lambda_.to_std();
  const double ln = lambda_.norm();
  std::vector<double> gap_tolerance(static_cast<size_t>(dual.n_nodes()));
  for (PetscInt k = 0; k < dual.n_nodes(); ++k)
    gap_tolerance[static_cast<size_t>(k)] = enforcement.gap_tolerance(k);
  const auto& held = dual.held();
  const auto& friction = nodal_laws_.friction;
  for (int q = 0; q < n_pairs(); ++q) {
    const auto& rows = dual.pair_rows(q);
    const auto from = static_cast<size_t>(dual.pair_offset(q));
    const auto n = static_cast<size_t>(rows.n_nodes());
    const auto rows_of = [&](std::span<const double> v) {
      return v.size() >= dim * (from + n) ? v.subspan(dim * from, dim * n) : v.subspan(0, 0);
    };
    const auto nodes_of_pair = [&](std::span<const double> v) {
      return v.size() >= from + n ? v.subspan(from, n) : v.subspan(0, 0);
    };
    PairLaws p{.name = n_pairs() > 1 ? pairs_[q].settings->name : std::string(),
               .dim = dim,
               .nodes = rows.nodes,
               .weights = rows.weights,
               .targets = rows_of(targets),
               .constraint_values = rows_of(bu),
               .lambda = rows_of(l),
               .friction = nodes_of_pair(friction),
               .qp_bound = nodes_of_pair(qp_bound_),
               .gap_tolerance = nodes_of_pair(gap_tolerance),
               .held = held.size() >= from + n ? std::span<const char>(held).subspan(from, n)
                                               : std::span<const char>()};
    // u formed by FETI solves misses the glued, supported body by their misfit ‖B u − c‖,
    // which the QP's view of B u (its F formed by such solves) does not see.
    for (const int b : {pairs_[q].bodies.slave, pairs_[q].bodies.master}) {
      const auto* f = g.fields[static_cast<size_t>(b)];
      if (f->mech && f->mech->feti())
        p.solve_error +=
            ContactLaws::feti_misfit_factor * f->mech->feti()->statistics().peak_residual;
    }
    p.feti_tolerance = problem_.solver.feti_tolerance;
    laws_.check(p, traction_per_multiplier(), problem_.solver.coupling_tolerance, ln,
                problem_.solver.qp_tolerance, step);
  }
}

void ContactCoupling::finish_step(const BodyGroup& g, TrescaIteration& tresca,
                                  std::span<const double> targets, int step, int iteration) {
  auto& enforcement = *method_.enforcement;
  auto& dual = enforcement.dual();
  iterate_slip_.clear();
  qp_bound_ = std::move(tresca.qp_bound);  // empty without friction
  // A coupling tolerance looser than the cone's leaves nodes outside their Coulomb cone by up
  // to 𝔉 tol ‖λ‖ (history's T/N above 𝔉): scale them onto it, u to match (docs/choices.md).
  if (problem_.solver.coupling_tolerance > ContactLaws::cone_tolerance &&
      !enforcement.qp_gives_displacements())
    scale_into_cones(g, !tresca.defer);
  if (tresca.defer) {  // u_new holds u_free of the last iteration
    auto scope = timers_.scope("qp");
    dual.recover(lambda_, g.field(&BodyField::u_new));
    shift_loaded_face(g);
  }
  for (const auto* f : g.fields) require_finite(f->u_new, "displacement", step, iteration);
  check_laws(g, targets, step);

  // The slip increment B_τ(u^{k+1} − u^k) for the dissipation, before the state moves on.
  for (int i = 0; i < g.size(); ++i) {
    g.fields[i]->work_u.copy_from(g.fields[i]->u_new);
    g.fields[i]->work_u.axpy(-1.0, g.states[i]->u);
  }
  slip_ = dual.row_values(g.field_in(&BodyField::work_u));
  // Heat through the interface in this step, with the L and d of the last heat step (those
  // that produced θ^{k+1}): then the thermal energy balance of the bodies closes to round-off.
  heat_.account_step(g, problem_.time.step);
  bookkeeping();
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
    pr.stats.record_step(rows, lq, friction_work(rows, lq, nodes_of(slip_, dim, from, to)), unit,
                         bound, pr.mortar.get());
    pr.slave_force = slave_force(q, lq);
    if (pr.mortar) {  // q = β_C λ_n [θ] per contact node (contact_heat.hpp)
      const auto& c = *pr.settings;
      pr.heat_flux.assign(static_cast<size_t>(rows.n_nodes()), 0.0);
      if (c.heat_conduction && (pr.nodal.conducting || c.gap_conductance) &&
          pr.mortar->contact_nodes().size() == static_cast<size_t>(rows.n_nodes())) {
        std::vector<double> scale(pr.nodal.beta_c);
        for (double& s : scale) s *= unit;
        // h of the last heat step (its radiation at that iterate's θ), as the ledger has it.
        const auto last = heat_.gap_conductance(static_cast<size_t>(q));
        const auto open = !c.gap_conductance ? std::vector<double>{}
                          : last.empty()     ? nodal_gap_conductance(*c.gap_conductance, rows)
                                             : std::vector<double>(last.begin(), last.end());
        pr.heat_flux =
            conduction_flux(*pr.mortar, rows, lq, scale, bodies_.fields[c.slave_body]->theta_new,
                            bodies_.fields[c.master_body]->theta_new, open);
      }
    }
  }
  sum_pair_statistics();
  slave_force_ = {0, 0, 0};
  for (const auto& pr : pairs_)
    for (size_t x = 0; x < 3; ++x) slave_force_[x] += pr.slave_force[x];
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
