#include "tc/physics/contact_heat_coupling.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/physics/boundary_heat.hpp"
#include "tc/physics/contact_heat.hpp"

namespace tc::physics {

void ContactHeatCoupling::heat_step(const Problem& p, const HeatPair& pair,
                                    const ContactIterate& it, double t, int step, int iteration) {
  // γ = λ_n of the current multiplier iterate (nodal pressures, ≥ 0), u̇ of the current
  // displacement iterate; β_C and δ_C per contact node at the interface temperature of the last
  // coupling iterate (it.laws). L on the left through the interface (InterfaceHeatSolver), or
  // lagged.
  const auto& c = p.contacts.at(0);
  auto& ss = pair.slave;
  auto& sm = pair.master;
  frictional_heat_ = {};
  conductance_.reset();
  std::vector<double> gamma;
  if (it.mortar) {
    const auto& rows = it.rows;
    const auto lv = it.lambda.read();
    gamma.resize(static_cast<size_t>(rows.n_nodes()));
    const double unit = it.unit;
    for (PetscInt k = 0; k < rows.n_nodes(); ++k) gamma[k] = unit * std::max(lv[rows.dim * k], 0.0);
    if (static_cast<size_t>(rows.n_nodes()) != it.mortar->contact_nodes().size())
      throw Error("thermal contact: the multipliers do not match the mortar pair's nodes");
  }
  if (it.mortar && c.frictional_heating && it.laws.frictional) {
    // d_θγ from the multipliers: the friction work of the step λ_τ,k·(B_τ(u − u^k))_k per
    // contact node over τ, δ_C of it to the slave through D, 1 − δ_C to the master through M;
    // ContactCoupling::bookkeeping sums the same work at u^{k+1}: heat = dissipation by
    // construction.
    const double tau = p.time.step;
    for (auto [s, st] : {std::pair{&ss, &pair.slave_state}, {&sm, &pair.master_state}}) {
      s->velocity.copy_from(s->u_new);  // (the thermoelastic term of heat_rhs used it above)
      s->velocity.axpy(-1.0, st->u);
    }
    std::vector<double> power = nonnegative_heat(
        friction_work(it.rows, it.lambda.to_std(),
                      it.slip.empty() ? step_slip(it.rows, ss.velocity, sm.velocity)
                                      : std::vector<double>(it.slip.begin(), it.slip.end())));
    for (double& q : power) q *= it.unit / tau;
    for (const double q : power) frictional_heat_.total += q;
    std::vector<double> master_share(it.laws.delta_c.size());
    for (size_t k = 0; k < master_share.size(); ++k) master_share[k] = 1.0 - it.laws.delta_c[k];
    frictional_heat_.slave = distribute(power, it.laws.delta_c, it.mortar->d_matrix());
    frictional_heat_.master = distribute(power, master_share, it.mortar->m_matrix());
    for (auto [s, d] : {std::pair{&ss, &frictional_heat_.slave}, {&sm, &frictional_heat_.master}}) {
      auto rv = s->rhs_theta.view();
      for (size_t a = 0; a < d->size(); ++a) rv[static_cast<PetscInt>(a)] += (*d)[a];
    }
  }
  const bool conduct = it.mortar && c.heat_conduction && it.laws.conducting;
  if (conduct) {
    // L_θγ = ∫β_Cγ[θ][χ] with β_Cγ = Σ_k β_C,k γ_k φ_k (the nodal product interpolated, as γ
    // is); β_C,kγ_k × 1 is the β_C × γ_k of a constant β_C to the bit.
    for (size_t k = 0; k < gamma.size(); ++k) gamma[k] = it.laws.beta_c[k] * gamma[k];
    conductance_ = it.mortar->thermal_conductance(gamma, 1.0);
  }
  if (conduct && treatment_ == ConductanceTreatment::lagged) {
    // (6.2): L θ^p of the previous iterate to the right-hand side.
    const auto& l = *conductance_;
    l.ss.mult(ss.theta_new, ss.work_theta);
    l.sm.mult_add(sm.theta_new, ss.work_theta);
    l.ms.mult(ss.theta_new, sm.work_theta);
    l.mm.mult_add(sm.theta_new, sm.work_theta);
    ss.rhs_theta.axpy(-1.0, ss.work_theta);
    sm.rhs_theta.axpy(-1.0, sm.work_theta);
  }
  pair.slave_system.prescribe_theta(t, ss.theta_new);
  pair.master_system.prescribe_theta(t, sm.theta_new);
  const bool implicit = conduct && treatment_ == ConductanceTreatment::implicit;
  if (implicit) {
    if (!interface_heat_) {
      interface_heat_ = std::make_unique<InterfaceHeatSolver>(
          *ss.heat, pair.slave_system.n_theta(),
          p.bodies[c.slave_body].mesh.boundary_nodes(c.slave_where), *sm.heat,
          pair.master_system.n_theta(),
          p.bodies[c.master_body].mesh.boundary_nodes(c.master_where));
    }
    interface_heat_->set_conductance(*conductance_);
  }
  if (pair.slave_system.has_boundary_term() || pair.master_system.has_boundary_term()) {
    pair_boundary_heat(p, pair, implicit, t, step, iteration);
  } else if (implicit) {
    interface_heat_->solve(ss.rhs_theta, sm.rhs_theta, ss.theta_new, sm.theta_new);
  } else {
    ss.heat->solve(ss.rhs_theta, ss.theta_new);
    sm.heat->solve(sm.rhs_theta, sm.theta_new);
  }
}

void ContactHeatCoupling::pair_boundary_heat(const Problem& p, const HeatPair& pair, bool implicit,
                                             double t, int step, int iteration) {
  // The contact pair's heat step with radiation or an h(t) film on either body: Newton over
  // both bodies (boundary_heat.hpp) on A = diag(A_s, A_m) (+ L_θγ when implicit), each
  // correction preconditioned by the pair's exact linear solve.
  auto& ss = pair.slave;
  auto& sm = pair.master;
  HeatOperator op;
  op.systems = {&pair.slave_system, &pair.master_system};
  op.apply = [&](const auto& x, const auto& y) {
    ss.a_theta.mult(*x[0], *y[0]);
    sm.a_theta.mult(*x[1], *y[1]);
    if (implicit) {
      const auto& l = *conductance_;
      l.ss.mult_add(*x[0], *y[0]);
      l.sm.mult_add(*x[1], *y[0]);
      l.ms.mult_add(*x[0], *y[1]);
      l.mm.mult_add(*x[1], *y[1]);
    }
  };
  op.solve = [&](const auto& r, const auto& z) {
    if (implicit) {
      interface_heat_->solve(*r[0], *r[1], *z[0], *z[1]);
    } else {
      ss.heat->solve(*r[0], *z[0]);
      sm.heat->solve(*r[1], *z[1]);
    }
  };
  const auto& settings = p.solver;
  const auto o =
      solve_boundary_heat(op, t, {&ss.rhs_theta, &sm.rhs_theta}, {&ss.theta_new, &sm.theta_new},
                          settings.newton_tolerance, settings.max_newton_iterations);
  newton_ += o.iterations;
  newton_inner_ += o.inner_iterations;
  require_converged(o,
                    fmt::format("the contact pair '{}'–'{}'", p.bodies[p.contacts.at(0).slave_body].name,
                                p.bodies[p.contacts.at(0).master_body].name),
                    settings.newton_tolerance, step, iteration);
}

void ContactHeatCoupling::account_step(const HeatPair& pair, double tau) {
  auto& ss = pair.slave;
  const auto& sm = pair.master;
  heat_.generated += tau * frictional_heat_.total;
  for (const double q : frictional_heat_.slave) heat_.to_slave += tau * q;
  for (const double q : frictional_heat_.master) heat_.to_master += tau * q;
  if (conductance_) {  // 1ᵀ(L_ss θ_s + L_sm θ_m) = β_C ∫ γ (θ_s − θ_m) dS, slave → master
    conductance_->ss.mult(ss.theta_new, ss.work_theta);
    conductance_->sm.mult_add(sm.theta_new, ss.work_theta);
    heat_.conducted += tau * ss.work_theta.sum();
  }
}

}  // namespace tc::physics
