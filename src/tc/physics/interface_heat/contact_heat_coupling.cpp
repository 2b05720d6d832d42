#include "tc/physics/interface_heat/contact_heat_coupling.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"
#include "tc/physics/body/boundary_heat_newton.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"
#include "tc/physics/interface_heat/gap_conductance.hpp"

namespace tc::physics {

void ContactHeatCoupling::heat_step(const Problem& p, const BodyGroup& group,
                                    std::span<const ContactIterate> pairs, double t, int step,
                                    int iteration) {
  // Per pair: γ = λ_n of the current multiplier iterate (nodal pressures, ≥ 0), u̇ of the
  // current displacement iterate; β_C and δ_C per contact node at the interface temperature of
  // the last coupling iterate (it.laws). L on the left through the interface
  // (InterfaceHeatSolver), or lagged.
  const auto n_pairs = pairs.size();
  frictional_heat_.assign(n_pairs, {});
  conductance_.clear();
  conductance_.resize(n_pairs);
  gap_weights_.clear();
  gap_weights_.resize(n_pairs);
  gap_open_.assign(n_pairs, {});
  bodies_.clear();
  for (const auto& it : pairs) bodies_.push_back(it.bodies);
  TC_VERIFY(heat_.size() == n_pairs, "set_pairs sized the pairs' heat");
  std::vector<std::vector<double>> gamma(n_pairs);
  bool any_frictional = false;
  for (size_t q = 0; q < n_pairs; ++q) {
    const auto& it = pairs[q];
    any_frictional =
        any_frictional || (it.mortar && it.settings.frictional_heating && it.laws.frictional);
    if (!it.mortar) continue;
    const auto& rows = it.rows;
    gamma[q].resize(static_cast<size_t>(rows.n_nodes()));
    for (PetscInt k = 0; k < rows.n_nodes(); ++k)
      gamma[q][k] = it.unit * std::max(it.lambda[rows.dim * k], 0.0);
    if (static_cast<size_t>(rows.n_nodes()) != it.mortar->contact_nodes().size())
      throw Error("thermal contact: the multipliers do not match the mortar pair's nodes");
  }
  if (any_frictional)
    for (int i = 0; i < group.size(); ++i) {
      auto& f = *group.fields[i];
      f.velocity.copy_from(f.u_new);  // (the thermoelastic term of heat_rhs used it above)
      f.velocity.axpy(-1.0, group.states[i]->u);
    }
  for (size_t q = 0; q < n_pairs; ++q) {
    const auto& it = pairs[q];
    if (!(it.mortar && it.settings.frictional_heating && it.laws.frictional)) continue;
    // d_θγ from the multipliers: the friction work of the step λ_τ,k·(B_τ(u − u^k))_k per
    // contact node over τ, δ_C of it to the slave through D, 1 − δ_C to the master through M;
    // ContactCoupling::bookkeeping sums the same work at u^{k+1}: heat = dissipation by
    // construction.
    auto& ss = *group.fields[it.bodies.slave];
    auto& sm = *group.fields[it.bodies.master];
    const double tau = p.time.step;
    std::vector<double> power = nonnegative_heat(
        friction_work(it.rows, it.lambda,
                      it.slip.empty() ? step_slip(it.rows, ss.velocity, sm.velocity)
                                      : std::vector<double>(it.slip.begin(), it.slip.end())));
    for (double& w : power) w *= it.unit / tau;
    auto& fh = frictional_heat_[q];
    for (const double w : power) fh.total += w;
    std::vector<double> master_share(it.laws.delta_c.size());
    for (size_t k = 0; k < master_share.size(); ++k) master_share[k] = 1.0 - it.laws.delta_c[k];
    fh.slave = distribute(power, it.laws.delta_c, it.mortar->d_matrix());
    fh.master = distribute(power, master_share, it.mortar->m_matrix());
    for (auto [s, d] : {std::pair{&ss, &fh.slave}, {&sm, &fh.master}}) {
      auto rv = s->rhs_theta.view();
      for (size_t a = 0; a < d->size(); ++a) rv[static_cast<PetscInt>(a)] += (*d)[a];
    }
  }
  std::vector<PairConductance> conducting;
  for (size_t q = 0; q < n_pairs; ++q) {
    const auto& it = pairs[q];
    const auto& gap = it.settings.gap_conductance;
    if (!(it.mortar && it.settings.heat_conduction && (it.laws.conducting || gap))) continue;
    // L_θγ = ∫β_Cγ[θ][χ] with β_Cγ = Σ_k β_C,k γ_k φ_k (the nodal product interpolated, as γ
    // is); β_C,kγ_k × 1 is the β_C × γ_k of a constant β_C to the bit. The gap conductance
    // h(g_k) is added at every node (gap_conductance.hpp); its own L, first (the mortar pair
    // reuses its matrices), gives the ledger its share: 1ᵀL_gap θ = (L_ss1)·θ_s + (L_ms1)·θ_m.
    auto& g = gamma[q];
    std::vector<double> open(g.size(), 0.0);
    if (gap) {
      // Radiation at the faces' θ of the last iterate: the fixed point iterates θ with it
      // (InterfaceLaws::gap_radiates), so the secant h_rad[θ] converges to σε(θ_s⁴ − θ_m⁴).
      const auto faces =
          gap->effective_emissivity() > 0
              ? std::optional(gap_faces(*it.mortar, group.fields[it.bodies.slave]->theta_new,
                                        group.fields[it.bodies.master]->theta_new))
              : std::nullopt;
      open = nodal_gap_conductance(*gap, it.rows, faces ? &*faces : nullptr);
      gap_open_[q] = open;
      const auto l = it.mortar->thermal_conductance(open, 1.0);
      auto& w = gap_weights_[q].emplace(core::Vector(l.ss.rows()), core::Vector(l.ms.rows()));
      core::Vector ones(l.ss.cols());  // L_ms = L_smᵀ: both row sums over the slave's nodes
      ones.fill(1.0);
      l.ss.mult(ones, w.first);
      l.ms.mult(ones, w.second);
    }
    for (size_t k = 0; k < g.size(); ++k) g[k] = it.laws.beta_c[k] * g[k] + open[k];
    conductance_[q] = it.mortar->thermal_conductance(g, 1.0);
    conducting.push_back({&*conductance_[q], it.bodies.slave, it.bodies.master});
  }
  if (treatment_ == ConductanceTreatment::lagged)
    for (const auto& c : conducting) {  // (6.2): L θ^p of the previous iterate to the right
      auto& ss = *group.fields[c.slave];
      auto& sm = *group.fields[c.master];
      const auto& l = *c.l;
      l.ss.mult(ss.theta_new, ss.work_theta);
      l.sm.mult_add(sm.theta_new, ss.work_theta);
      l.ms.mult(ss.theta_new, sm.work_theta);
      l.mm.mult_add(sm.theta_new, sm.work_theta);
      ss.rhs_theta.axpy(-1.0, ss.work_theta);
      sm.rhs_theta.axpy(-1.0, sm.work_theta);
    }
  for (int i = 0; i < group.size(); ++i)
    group.systems[i]->prescribe_theta(t, group.fields[i]->theta_new);
  const bool implicit = !conducting.empty() && treatment_ == ConductanceTreatment::implicit;
  if (implicit) {
    if (!interface_heat_) make_interface_solver(p, group);
    // within a time step L changes by the fixed point's residual: refinement with the last LU
    interface_heat_->set_conductance(conducting, iteration > 1);
  }
  bool boundary_term = false;
  bool material_laws = false;
  for (const auto* sys : group.systems) {
    boundary_term = boundary_term || sys->has_boundary_term();
    material_laws = material_laws || sys->nonlinear_heat();
  }
  if (boundary_term || material_laws) {
    group_boundary_heat(p, group, implicit, material_laws, t, step, iteration);
  } else {
    // Linear: for θ − θ₀ where every body's heat is factorised (heat_to_deviation). L_Γ adds
    // nothing to θ₀A1: L_Γ1 = 0, each segment's integrand holding both sides' partitions of
    // unity (the jump of a constant is zero at every point).
    const double theta0 = p.physics.reference_temperature;
    const bool deviation = std::all_of(group.fields.begin(), group.fields.end(),
                                       [](const BodyField* f) { return deviation_applies(*f); });
    if (deviation)
      for (auto* f : group.fields) heat_to_deviation(theta0, *f);
    if (implicit)
      interface_heat_->solve(group.field_in(&BodyField::rhs_theta),
                             group.field(&BodyField::theta_new));
    else
      for (auto* f : group.fields) f->heat->solve(f->rhs_theta, f->theta_new);
    if (deviation)
      for (int i = 0; i < group.size(); ++i)
        heat_from_deviation(theta0, *group.systems[i], t, *group.fields[i]);
  }
}

void ContactHeatCoupling::make_interface_solver(const Problem& p, const BodyGroup& group) {
  // Γ of each body: the nodes of its contact surfaces in every pair.
  std::vector<std::set<int>> nodes(static_cast<size_t>(group.size()));
  for (const auto& c : p.contacts) {
    const auto& members = group.index;
    for (const auto& [b, where] :
         {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
      const auto at = std::find(members.begin(), members.end(), b) - members.begin();
      for (const int a : p.bodies[b].mesh.boundary_nodes(*where)) nodes[at].insert(a);
    }
  }
  std::vector<const ConstrainedSolver*> solvers;
  std::vector<PetscInt> n;
  std::vector<std::vector<int>> gamma_nodes;
  for (int i = 0; i < group.size(); ++i) {
    solvers.push_back(group.fields[i]->heat.get());
    n.push_back(group.systems[i]->n_theta());
    gamma_nodes.emplace_back(nodes[i].begin(), nodes[i].end());
  }
  interface_heat_ = std::make_unique<InterfaceHeatSolver>(std::move(solvers), std::move(n),
                                                          std::move(gamma_nodes));
}

void ContactHeatCoupling::save(Checkpoint& c) const {
  c.heat_compliance.clear();
  if (interface_heat_) interface_heat_->save_compliance(c.heat_compliance);
}

void ContactHeatCoupling::restore(const Checkpoint& c, const Problem& p, const BodyGroup& group) {
  // The run's S only where its run had one (a checkpoint before the first conducting heat
  // step has none: the next heat step makes it, as the run did).
  if (c.heat_compliance.empty()) {
    interface_heat_.reset();
    return;
  }
  make_interface_solver(p, group);
  interface_heat_->replay_compliance(c.heat_compliance);
}

void ContactHeatCoupling::group_boundary_heat(const Problem& p, const BodyGroup& group,
                                              bool implicit, bool material_laws, double t, int step,
                                              int iteration) {
  // The heat step with radiation or an h(t) film on any body of the group: Newton over its
  // bodies (boundary_heat_newton.hpp) on A = diag(A_i) (+ Σ_pairs L_θγ when implicit), each
  // correction preconditioned by the group's exact linear solve.
  HeatOperator op;
  op.systems = group.systems;
  op.apply = [&](const auto& x, const auto& y) {
    for (int i = 0; i < group.size(); ++i) group.fields[i]->a_theta.mult(*x[i], *y[i]);
    if (implicit)
      for (size_t q = 0; q < conductance_.size(); ++q) {
        if (!conductance_[q]) continue;
        const auto& l = *conductance_[q];
        const int s = bodies_[q].slave, m = bodies_[q].master;
        l.ss.mult_add(*x[s], *y[s]);
        l.sm.mult_add(*x[m], *y[s]);
        l.ms.mult_add(*x[s], *y[m]);
        l.mm.mult_add(*x[m], *y[m]);
      }
  };
  op.solve = [&](const auto& r, const auto& z) {
    if (implicit) {
      interface_heat_->solve(r, z);
    } else {
      for (int i = 0; i < group.size(); ++i) group.fields[i]->heat->solve(*r[i], *z[i]);
    }
  };
  const auto& settings = p.solver;
  op.inv_tau = 1.0 / p.time.step;
  const auto o =
      material_laws
          ? solve_nonlinear_heat(op, t, group.field_in(&BodyField::rhs_theta),
                                 group.field(&BodyField::theta_new), settings.newton_tolerance,
                                 settings.max_newton_iterations)
          : solve_boundary_heat(op, t, group.field_in(&BodyField::rhs_theta),
                                group.field(&BodyField::theta_new), settings.newton_tolerance,
                                settings.max_newton_iterations);
  newton_ += o.iterations;
  newton_inner_ += o.inner_iterations;
  std::string names;
  for (const int b : group.index)
    names += fmt::format("{}'{}'", names.empty() ? "" : "–", p.bodies[b].name);
  if (material_laws)
    require_converged(o, "the contact bodies " + names, settings.newton_tolerance, step, iteration,
                      kMaterialLawTerms);
  else
    require_converged(o, "the contact bodies " + names, settings.newton_tolerance, step, iteration);
}

void ContactHeatCoupling::account_step(const BodyGroup& group, double tau) {
  for (size_t q = 0; q < frictional_heat_.size(); ++q) {
    auto& h = heat_[q];
    const auto& fh = frictional_heat_[q];
    h.generated += tau * fh.total;
    for (const double w : fh.slave) h.to_slave += tau * w;
    for (const double w : fh.master) h.to_master += tau * w;
    if (conductance_[q]) {  // 1ᵀ(L_ss θ_s + L_sm θ_m) = β_C ∫ γ (θ_s − θ_m) dS, slave → master
      auto& ss = *group.fields[bodies_[q].slave];
      const auto& sm = *group.fields[bodies_[q].master];
      conductance_[q]->ss.mult(ss.theta_new, ss.work_theta);
      conductance_[q]->sm.mult_add(sm.theta_new, ss.work_theta);
      h.conducted += tau * ss.work_theta.sum();
    }
    if (const auto& w = gap_weights_[q]) {
      const auto& ss = *group.fields[bodies_[q].slave];
      const auto& sm = *group.fields[bodies_[q].master];
      h.gap_conducted += tau * (w->first.dot(ss.theta_new) + w->second.dot(sm.theta_new));
    }
  }
  sum_heat();
}

void ContactHeatCoupling::set_pair_heat(std::span<const ContactHeat> heat) {
  TC_VERIFY(heat.size() == heat_.size(), "one interface heat per contact pair");
  std::copy(heat.begin(), heat.end(), heat_.begin());
  sum_heat();
}

void ContactHeatCoupling::sum_heat() {
  total_ = {};
  for (const auto& h : heat_) {
    total_.generated += h.generated;
    total_.to_slave += h.to_slave;
    total_.to_master += h.to_master;
    total_.conducted += h.conducted;
    total_.gap_conducted += h.gap_conducted;
  }
}

}  // namespace tc::physics
