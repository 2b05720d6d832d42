#include "tc/physics/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/physics/body_field.hpp"
#include "tc/physics/boundary_heat.hpp"
#include "tc/physics/contact_heat.hpp"
#include "tc/physics/time_scheme.hpp"

namespace tc::physics {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The largest (or smallest) temperature of all bodies.
double extreme_temperature(const std::vector<BodyState>& states, bool largest) {
  double e = largest ? -INFINITY : INFINITY;
  for (const auto& st : states) {
    PetscReal v = 0;
    if (largest) {
      TC_PETSC(VecMax(st.theta.get(), nullptr, &v));
      e = std::max(e, static_cast<double>(v));
    } else {
      TC_PETSC(VecMin(st.theta.get(), nullptr, &v));
      e = std::min(e, static_cast<double>(v));
    }
  }
  return e;
}

}  // namespace

Simulation::Simulation(const Problem& problem)
    : problem_(problem), friction_loop_(problem.solver.friction_loop) {
  for (int b = 0; b < static_cast<int>(problem_.bodies.size()); ++b) {
    {
      auto t = timers_.scope("assembly");
      systems_.push_back(std::make_unique<BodySystem>(problem_, b));
    }
    const auto& sys = *systems_.back();
    std::unique_ptr<BodyField> s;
    {
      auto t = timers_.scope("factorization");
      s = std::make_unique<BodyField>(problem_, sys);
    }
    factorization_ = s->mech->package();
    solvers_.push_back(std::move(s));
  }
  initialise();
  check_setup_finite(systems_, states_);
}

Simulation::~Simulation() = default;

PetscInt Simulation::n_dofs() const {
  PetscInt n = 0;
  for (const auto& s : systems_) n += s->n_u() + s->n_theta();
  return n;
}

feti::FetiStatistics Simulation::feti_statistics() const {
  feti::FetiStatistics total;
  for (const auto& s : solvers_)
    for (const auto* solver : {s->mech.get(), s->heat.get(), s->mass.get()})
      if (solver && solver->feti()) total += solver->feti()->statistics();
  return total;
}

void Simulation::initialise() {
  for (int b = 0; b < n_bodies(); ++b) {
    const auto& sys = *systems_[b];
    auto& s = *solvers_[b];
    BodyState st{core::Vector(sys.n_u()), core::Vector(sys.n_u()), core::Vector(sys.n_u()),
                 core::Vector(sys.n_theta())};
    sys.prescribe_u(0.0, st.u);
    {
      auto v = st.v.view();
      for (PetscInt i = 0; i < sys.n_u(); ++i) v[i] = sys.body().initial_velocity[i % sys.dim()];
    }
    sys.prescribe_u_rate(0.0, st.v);  // supports move as their tables say, not with the body
    st.theta.fill(sys.body().initial_temperature);
    sys.prescribe_theta(0.0, st.theta);

    if (problem_.time.scheme == Scheme::dynamic && sys.body().start_in_equilibrium)
      static_initial_state(b, st);
    if (problem_.time.scheme == Scheme::dynamic) {
      // Consistent initial acceleration (2.1 at t = 0): M ü⁰ = f(0) − K u⁰ − K_uθ(θ⁰ − θ₀),
      // with ü = 0 on the supports. M is factorised for this one solve and dropped.
      auto t = timers_.scope("factorization");
      const auto& m = sys.matrices();
      sys.mechanical_load(0.0, s.rhs_u);
      m.stiffness_u.mult(st.u, s.work_u);
      s.rhs_u.axpy(-1.0, s.work_u);
      if (problem_.physics.thermal_expansion)
        subtract_thermal_force(problem_, sys, s, st.theta, s.rhs_u);
      s.g_free = s.rhs_u.clone();  // g⁰ = M ü⁰ (no contact force at t = 0)
      s.initial_mass = body_solver(problem_, sys, m.mass_u, BodyOperator::mass);
      st.a.zero();
      s.initial_mass->solve(s.rhs_u, st.a);
    }
    states_.push_back(std::move(st));
    forces_.emplace_back(sys.n_u());
  }

  for (int b = 0; b < n_bodies(); ++b) support_forces(b, forces_[b]);
  register_history();
  history_.record();
}

void Simulation::static_initial_state(int b, BodyState& st) {
  // K u⁰ = f(0) − K_uθ(θ⁰ − θ₀) with u⁰ = u_D(0) on the supports: the body starts expanded
  // by its initial temperature and loaded, so ü⁰ = 0 off the supports. Released from u⁰ = 0
  // instead, a body 80 K above θ₀ rings with ~2e4 J (example 05's cube), at frequencies that
  // Newmark's τ aliases to the step-to-step oscillation without damping it.
  auto t = timers_.scope("factorization");
  const auto& sys = *systems_[b];
  const auto& m = sys.matrices();
  auto& s = *solvers_[b];
  sys.mechanical_load(0.0, s.rhs_u);
  if (problem_.physics.thermal_expansion)
    subtract_thermal_force(problem_, sys, s, st.theta, s.rhs_u);
  body_solver(problem_, sys, m.stiffness_u, BodyOperator::statics)->solve(s.rhs_u, st.u);
  require_finite(st.u, "displacement", 0, 0);
}

void Simulation::support_forces(int b, core::Vector& r) const {
  // F = f_ext + R with R = M ü + K u + K_uθ(θ − θ₀) − f_ext on the constrained dofs: the
  // force the supports exert on the body. F is what does external work.
  const auto& sys = *systems_[b];
  const auto& m = sys.matrices();
  const auto& st = states_[b];
  auto& s = *solvers_[b];
  core::Vector& f = s.f_u;
  sys.mechanical_load(time(), f);
  m.stiffness_u.mult(st.u, r);
  if (problem_.time.scheme == Scheme::dynamic) m.mass_u.mult_add(st.a, r);
  if (problem_.physics.thermal_expansion) {
    s.dtheta.copy_from(st.theta);
    s.dtheta.shift(-problem_.physics.reference_temperature);
    m.coupling_u_theta.mult_add(s.dtheta, r);
  }
  {  // f is scratch: overwrite its constrained entries with the support forces, keep the rest
    auto rv = r.view();
    auto fv = f.view();
    for (const PetscInt d : sys.u_dirichlet_dofs()) fv[d] = rv[d];
  }
  r.copy_from(f);
}

void Simulation::heat_rhs(int b) {
  const auto& sys = *systems_[b];
  auto& s = *solvers_[b];
  s.rhs_theta.copy_from(s.rhs_theta_base);
  if (s.heating) {  // −K_θu u̇ = θ₀ K_uθᵀ u̇ (docs/choices.md)
    iterate_velocity(problem_, sys, states_[b], s);
    s.work_theta.zero();
    sys.matrices().coupling_u_theta.mult_transpose(s.velocity, s.work_theta);
    s.rhs_theta.axpy(problem_.physics.reference_temperature, s.work_theta);
  }
}

void Simulation::heat_step(int b, int iteration) {
  // (6.1) with the velocity of the current displacement iterate.
  auto scope = timers_.scope("heat_solve");
  const auto& sys = *systems_[b];
  auto& s = *solvers_[b];
  heat_rhs(b);
  const double t = (step_ + 1) * problem_.time.step;
  sys.prescribe_theta(t, s.theta_new);
  if (!sys.has_boundary_term()) {
    s.heat->solve(s.rhs_theta, s.theta_new);
  } else {  // radiation or a film with h(t): Newton (boundary_heat.hpp)
    const auto& settings = problem_.solver;
    const auto o = solve_boundary_heat(sys, s.a_theta, *s.heat, t, s.rhs_theta, s.theta_new,
                                       settings.newton_tolerance, settings.max_newton_iterations);
    total_newton_ += o.iterations;
    total_newton_inner_ += o.inner_iterations;
    require_converged(o, fmt::format("body '{}'", sys.body().name), settings.newton_tolerance,
                      step_ + 1, iteration);
  }
  require_finite(s.theta_new, "temperature", step_ + 1, iteration);
}

void Simulation::contact_heat_step(int iteration) {
  // (4.3) for the two bodies of the contact pair, backward Euler:
  //   (M_θ/τ + K_θ) θ + L_θγ θ = rhs + d_θγ(u̇)   (ContactHeatCoupling::heat_step),
  // rhs with the thermoelastic term of each body.
  auto scope = timers_.scope("heat_solve");
  const auto& c = *problem_.contact;
  const auto pair = heat_pair();
  // 𝔉, β_C, δ_C at the interface temperature of the last iterate (θ^k at the first): fixed
  // for this heat step and the Tresca QPs after it (interface_laws.hpp).
  nodal_laws_ =
      laws_.at_interface(mortar_.get(), dual_->rows(), pair.slave.theta_new, pair.master.theta_new);
  heat_rhs(c.slave_body);
  heat_rhs(c.master_body);
  heat_coupling_.heat_step(problem_, pair,
                           {mortar_.get(), dual_->rows(), lambda_, traction_per_multiplier(),
                            iterate_slip_, nodal_laws_},
                           (step_ + 1) * problem_.time.step, step_ + 1, iteration);
  require_finite(pair.slave.theta_new, "temperature", step_ + 1, iteration);
  require_finite(pair.master.theta_new, "temperature", step_ + 1, iteration);
}

HeatPair Simulation::heat_pair() {
  const auto& c = *problem_.contact;
  const int sb = c.slave_body, mb = c.master_body;
  return {*solvers_[sb], *solvers_[mb], *systems_[sb], *systems_[mb], states_[sb], states_[mb]};
}

void Simulation::mech_load(int b) {
  // The loads of (5.3) at θ^{k+1,p+1} in rhs_u, the prescribed values in u_new: what the
  // body's solver (mech_step) or the combined contact dual (contact_mech_step) solves with.
  const auto& sys = *systems_[b];
  auto& s = *solvers_[b];
  s.rhs_u.copy_from(s.rhs_u_base);
  if (s.expansion) subtract_thermal_force(problem_, sys, s, s.theta_new, s.rhs_u);
  sys.prescribe_u((step_ + 1) * problem_.time.step, s.u_new);
}

void Simulation::mech_step(int b, int iteration) {
  // (6.3) with θ^{k+1,p+1}, without contact forces.
  auto scope = timers_.scope("mechanical_solve");
  auto& s = *solvers_[b];
  mech_load(b);
  s.mech->solve(s.rhs_u, s.u_new);
  require_finite(s.u_new, "displacement", step_ + 1, iteration);
}

int Simulation::couple_body(int b) {
  const auto& sys = *systems_[b];
  auto& s = *solvers_[b];
  begin_step(problem_, sys, states_[b], s, (step_ + 1) * problem_.time.step);
  int iteration = 1;
  if (!(s.expansion && s.heating)) {
    // One-way coupling: one pass in the right order is the exact solution of the step.
    if (s.expansion) {
      heat_step(b, iteration);
      mech_step(b, iteration);
    } else {
      mech_step(b, iteration);
      heat_step(b, iteration);
    }
  } else {
    const double tol = problem_.solver.coupling_tolerance;
    double change = 0;
    for (iteration = 1; iteration <= problem_.solver.max_coupling_iterations; ++iteration) {
      s.u_prev.copy_from(s.u_new);
      s.theta_prev.copy_from(s.theta_new);
      heat_step(b, iteration);
      mech_step(b, iteration);
      s.u_prev.axpy(-1.0, s.u_new);
      s.theta_prev.axpy(-1.0, s.theta_new);
      const double du = s.u_prev.norm(), un = s.u_new.norm();
      const double dth = s.theta_prev.norm(), thn = s.theta_new.norm();
      change = std::max(un > 0 ? du / un : du, thn > 0 ? dth / thn : dth);
      if (du <= tol * un && dth <= tol * thn) break;
    }
    if (iteration > problem_.solver.max_coupling_iterations)
      throw NumericalError(
          fmt::format("the staggered fixed point (6.3) of body '{}' did not converge to {:.1e}",
                      sys.body().name, tol),
          step_ + 1, iteration - 1, change);
  }
  end_step(problem_, sys, states_[b], s);
  return iteration;
}

void Simulation::enable_contact(ContactRowsBuilder builder, DualContactSettings settings) {
  if (!problem_.contact) throw Error("enable_contact: the problem has no [contact]");
  const auto& c = *problem_.contact;
  settings.qp.rtol = problem_.solver.qp_tolerance;
  settings.qp.max_iterations = problem_.solver.max_qp_iterations;
  contact_rows_ = finite_rows(std::move(builder), step_);
  laws_ = InterfaceLaws(c);
  const int sb = c.slave_body, mb = c.master_body;
  const auto mode = problem_.solver.contact_dual;
  const auto why = combined_contact_dual_unavailable(problem_);
  combined_ = mode == ContactDual::combined || (mode == ContactDual::automatic && why.empty());
  if (combined_) {
    if (!why.empty()) throw Error("contact_dual = \"combined\": " + why);
    if (!solvers_[sb]->mech->feti() || !solvers_[mb]->mech->feti())
      throw Error("contact_dual = \"combined\": a contact body's mechanics is not solved by FETI");
    // The rows, targets and bookkeeping only: F is never applied nor formed.
    settings.explicit_limit = 0;
  }
  dual_ = std::make_unique<DualContactSolver>(*solvers_[sb]->mech, *solvers_[mb]->mech,
                                              systems_[sb]->n_u(), systems_[mb]->n_u(), settings);
  if (problem_.time.scheme == Scheme::dynamic &&
      problem_.time.contact_scheme == ContactScheme::stabilised) {
    auto t = timers_.scope("factorization");
    for (const int b : {sb, mb}) {
      auto& sv = *solvers_[b];
      sv.mass = sv.initial_mass ? std::move(sv.initial_mass)
                                : body_solver(problem_, *systems_[b],
                                              systems_[b]->matrices().mass_u, BodyOperator::mass);
    }
    stabiliser_ =
        std::make_unique<DualContactSolver>(*solvers_[sb]->mass, *solvers_[mb]->mass,
                                            systems_[sb]->n_u(), systems_[mb]->n_u(), settings);
  }
}

void Simulation::enable_mortar_contact(DualContactSettings settings,
                                       contact::MortarOptions options) {
  if (!problem_.contact) throw Error("enable_mortar_contact: the problem has no [contact]");
  const auto& c = *problem_.contact;
  {
    auto t = timers_.scope("mortar");
    mortar_ = std::make_unique<contact::MortarPair>(
        problem_.bodies[c.slave_body].mesh, c.slave_where, problem_.bodies[c.master_body].mesh,
        c.master_where, options);
  }
  enable_contact(
      [this](const core::Vector& u_slave, const core::Vector& u_master) {
        mortar_->update(u_slave.to_std(), u_master.to_std());
        return mortar_->rows();
      },
      std::move(settings));
}

void Simulation::stabilise_predictor(std::span<const double> normal_targets) {
  // Deuflhard–Krause–Ertel: u_pred ← argmin ½‖v − (u^k + τu̇^k)‖²_M over B_n(v − u^k) ≤ g
  // (frictionless: the projection only removes the normal approach), then the position update
  // M(u^{k+1} − u_pred) = τ²/4 (g^k + f^{k+1} − K u^{k+1} − … − Bᵀλ^{k+1}) drops the contact
  // force of step k, which is what made plain Newmark gain energy at the impact.
  const auto& c = *problem_.contact;
  const int sb = c.slave_body, mb = c.master_body;
  const double tau = problem_.time.step;
  auto& ss = *solvers_[sb];
  auto& sm = *solvers_[mb];
  const auto& rows = dual_->rows();
  stabiliser_->set_rows(
      {rows.dim, rows.slave.share(), rows.master.share(), rows.gap, rows.weights, rows.nodes});
  core::Vector multipliers(rows.n_rows());
  const std::vector<double> no_friction(static_cast<size_t>(rows.n_nodes()), 0.0);
  ss.u_prev.copy_from(ss.u_pred);
  sm.u_prev.copy_from(sm.u_pred);
  const auto r = stabiliser_->solve(ss.u_prev, sm.u_prev, normal_targets, no_friction, multipliers,
                                    ss.u_pred, sm.u_pred);
  contact_stats_.qp_iterations += r.iterations;
  contact_stats_.operator_applications += r.operator_applications + stabiliser_->setup_solves() / 2;
  if (!r.converged())
    throw NumericalError(
        fmt::format("the contact-stabilised predictor (mass projection) did not converge: {}",
                    r.message),
        step_ + 1, 0, r.projected_gradient);
  for (const int b : {sb, mb}) {
    auto& s = *solvers_[b];
    s.rhs_u_base.copy_from(s.f_u);
    s.rhs_u_base.axpy(1.0, s.g_free);
    systems_[b]->matrices().mass_u.mult(s.u_pred, s.work_u);
    s.rhs_u_base.axpy(newmark_mass_factor(tau), s.work_u);
    s.u_new.copy_from(s.u_pred);
  }
}

double Simulation::traction_per_multiplier() const {
  return physics::traction_per_multiplier(stabiliser_ != nullptr);
}

std::vector<double> Simulation::contact_multipliers() const {
  return lambda_.get() ? lambda_.to_std() : std::vector<double>{};
}

double Simulation::contact_mech_step(TrescaIteration& t, std::span<const double> targets, int outer,
                                     int max_updates) {
  // The mechanical half of (6.3) at the θ of this iteration: u_free is fixed, so each update
  // of γ costs one QP with the same F and no solve. Nested, the heat–mechanics iterations
  // are left with the thermal coupling alone (docs/choices.md, "friction loop").
  auto scope = timers_.scope("qp");
  const auto& c = *problem_.contact;
  auto& ss = *solvers_[c.slave_body];
  auto& sm = *solvers_[c.master_body];
  const int step = step_ + 1;
  ss.u_prev.copy_from(ss.u_new);  // u_free, the QP's data
  sm.u_prev.copy_from(sm.u_new);
  const CoulombFixedPoint p{.dim = dual_->rows().dim,
                            .friction = nodal_laws_.friction,
                            .frictional = nodal_laws_.frictional,
                            .tolerance = problem_.solver.coupling_tolerance,
                            .qp_tolerance = problem_.solver.qp_tolerance,
                            .max_updates = max_updates,
                            .step = step,
                            .outer = outer};
  // The QP at the Tresca bound t.bound: the contact enforcement.
  const double residual = coulomb_fixed_point(t, lambda_, p, [&](double rtol) {
    if (combined_) {
      // The whole mechanical step at this Tresca bound: one TFETI QP over the gluing, Dirichlet
      // and contact multipliers (6.4), SMALBE warm-started from the last one's λ and μ; u
      // comes with it. Its tolerance is that of the nested QP on both ‖g^P‖ and ‖Gλ − e‖.
      feti::ContactFetiOptions o;
      o.smalbe.rtol = rtol;
      o.smalbe.equality_rtol = rtol;
      o.smalbe.max_inner_iterations = problem_.solver.max_qp_iterations;
      const auto r = contact_feti_->solve(ss.rhs_u, sm.rhs_u, targets, t.bound, ss.u_new, sm.u_new,
                                          lambda_, o, &feti_state_);
      contact_stats_.qp_iterations += r.inner_iterations;
      contact_stats_.operator_applications += r.operator_applications;
      total_smalbe_outer_ += r.outer_iterations;
      ++contact_stats_.friction_iterations;
      if (!r.converged())
        throw NumericalError(
            fmt::format("the combined TFETI contact QP (6.4, SMALBE) did not converge: {}",
                        r.message),
            step, outer, r.projected_gradient);
    } else {
      const auto r = dual_->solve(ss.u_prev, sm.u_prev, targets, t.bound, lambda_, ss.u_new,
                                  sm.u_new, false, rtol);
      contact_stats_.qp_iterations += r.iterations;
      contact_stats_.operator_applications += r.operator_applications;
      ++contact_stats_.friction_iterations;
      if (!r.converged())
        throw NumericalError(fmt::format("the contact QP (6.9) did not converge: {}", r.message),
                             step, outer, r.projected_gradient);
    }
    require_finite(lambda_, "contact multiplier", step, outer);
  });
  if (combined_) {  // u came with λ
    require_finite(ss.u_new, "displacement", step, outer);
    require_finite(sm.u_new, "displacement", step, outer);
  } else if (t.defer) {
    core::Vector bu;
    dual_->constraint_values(ss.u_prev, sm.u_prev, lambda_, bu);
    iterate_slip_ = bu.to_std();
    for (size_t i = 0; i < iterate_slip_.size(); ++i) iterate_slip_[i] -= t.bu_old[i];
  } else {
    dual_->recover(lambda_, ss.u_new, sm.u_new);
    require_finite(ss.u_new, "u = u_free − A⁻¹Bᵀλ", step, outer);
    require_finite(sm.u_new, "u = u_free − A⁻¹Bᵀλ", step, outer);
  }
  return residual;
}

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

int Simulation::couple_contact() {
  const auto& c = *problem_.contact;
  const int sb = c.slave_body, mb = c.master_body;
  const double tau = problem_.time.step;
  const bool dynamic = problem_.time.scheme == Scheme::dynamic;
  auto& ss = *solvers_[sb];
  auto& sm = *solvers_[mb];
  const auto& sts = states_[sb];
  const auto& stm = states_[mb];
  for (const int b : {sb, mb})
    begin_step(problem_, *systems_[b], states_[b], *solvers_[b], (step_ + 1) * problem_.time.step);
  contact_stats_.qp_iterations = 0;
  contact_stats_.operator_applications = 0;
  contact_stats_.friction_iterations = 0;
  {
    ContactRows rows;
    {
      auto scope = timers_.scope("mortar");
      rows = contact_rows_(sts.u, stm.u);
    }
    auto scope = timers_.scope("dual_setup");  // F formed explicitly here when it is small
    dual_->set_rows(std::move(rows));
    if (combined_) {  // the combined B and G on this step's contact rows
      const auto& r = dual_->rows();
      contact_feti_ = std::make_unique<feti::ContactFeti>(*ss.mech->feti(), *sm.mech->feti(),
                                                          r.slave, r.master, r.dim);
    }
  }
  const auto& rows = dual_->rows();
  const int dim = rows.dim;
  transfer_.warm_start(rows, mortar_.get(), lambda_);  // λ of the last step on these rows
  if (dynamic && problem_.time.contact_scheme == ContactScheme::modified_mass)
    dual_->set_normal_floor(release_floor(lambda_, dim));
  if (stabiliser_) {
    auto scope = timers_.scope("qp");
    stabilise_predictor(dual_->targets(sts.u, stm.u, sts.u, stm.u));
  }
  // The slip is measured from u_pred − τ/2 u̇^k (= u^k + τ/2 u̇^k with plain Newmark), so that
  // B_τu − c_τ = τ/2 B_τu̇^{k+1} (5.4); quasistatic, and with the modified mass (whose contact
  // nodes have no inertia, massless_rates): from u^k, B_τu − c_τ = τ B_τu̇^{k+1}.
  const bool massless = problem_.time.contact_scheme == ContactScheme::modified_mass;
  ss.work_u.copy_from(massless ? sts.u : ss.u_pred);
  sm.work_u.copy_from(massless ? stm.u : sm.u_pred);
  if (dynamic && !massless) {
    ss.work_u.axpy(-0.5 * tau, sts.v);
    sm.work_u.axpy(-0.5 * tau, stm.v);
  }
  const auto targets = dual_->targets(sts.u, stm.u, ss.work_u, sm.work_u);

  TrescaIteration tresca;
  tresca.relax = accelerate_ && laws_.frictional();
  // u = u_free − A⁻¹Bᵀλ costs two solves; inside the fixed point only B u is needed (the
  // frictional heat's slip, = B u_free − Fλ) unless the thermoelastic term wants u̇ of the
  // whole body. Then u is formed once, after convergence.
  // Combined, u comes with every QP.
  tresca.defer = !combined_ && !(ss.heating || sm.heating);
  iterate_slip_.clear();
  if (tresca.defer) tresca.bu_old = step_slip(rows, sts.u, stm.u);
  contact_stats_.operator_applications += dual_->setup_solves() / 2;
  core::Vector lambda_prev = lambda_.clone();
  const bool nested = friction_loop_ == FrictionLoop::nested;
  const bool one_way = !(ss.expansion || sm.expansion);
  tresca.cut_short = nested && !one_way;
  const double tol = problem_.solver.coupling_tolerance;
  const int step = step_ + 1;
  int iteration = 1;
  double change = 0;
  double sweep_change = -1;  // ‖λ^p − λ^{p−1}‖/‖λ‖ of the previous iteration
  for (; iteration <= problem_.solver.max_coupling_iterations; ++iteration) {
    lambda_prev.copy_from(lambda_);
    ss.theta_prev.copy_from(ss.theta_new);
    sm.theta_prev.copy_from(sm.theta_new);
    contact_heat_step(iteration);
    ss.theta_prev.axpy(-1.0, ss.theta_new);
    sm.theta_prev.axpy(-1.0, sm.theta_new);
    const double dth = std::hypot(ss.theta_prev.norm(), sm.theta_prev.norm());
    const double thn = std::hypot(ss.theta_new.norm(), sm.theta_new.norm());
    // Without thermal expansion u_free does not depend on θ: λ of the last iteration (the
    // Coulomb solution to the tolerance) stays exact, and so is this heat step with it, unless
    // the conductance is lagged or depends on θ (then θ itself iterates); not when 𝔉 depends
    // on θ (then λ does).
    const bool theta_iterates =
        heat_coupling_.treatment() == ConductanceTreatment::Lagged || laws_.conductance_varies();
    if (one_way && tresca.converged && !laws_.friction_varies() &&
        (!theta_iterates || dth <= tol * thn)) {
      change = thn > 0 ? dth / thn : dth;
      break;
    }
    if (combined_) {  // the loads only: the combined QP solves for u itself
      auto scope = timers_.scope("mechanical_solve");
      mech_load(sb);
      mech_load(mb);
    } else {
      mech_step(sb, iteration);  // u_free = A⁻¹f with the Dirichlet data
      mech_step(mb, iteration);
    }
    // Nested: γ = λ_n(γ) to convergence at this θ, Aitken restarted (the map changed with θ);
    // staggered: one update, the relaxation carried over the heat–mechanics iterations.
    if (nested || tresca.gamma.empty()) tresca.restart(lambda_, dim, nodal_laws_.friction);
    const double fixed_residual = contact_mech_step(
        tresca, targets, iteration, nested ? problem_.solver.max_coupling_iterations : 1);
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
  if (tresca.defer) {  // u_new holds u_free of the last iteration
    auto scope = timers_.scope("qp");
    dual_->recover(lambda_, ss.u_new, sm.u_new);
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
  heat_coupling_.account_step(heat_pair(), tau);
  for (const int b : {sb, mb}) end_step(problem_, *systems_[b], states_[b], *solvers_[b]);
  for (int b = 0; b < n_bodies(); ++b)
    if (b != sb && b != mb) couple_body(b);
  return iteration;
}

void Simulation::contact_bookkeeping() {
  const auto& rows = dual_->rows();
  const auto l = lambda_.to_std();
  const double unit = traction_per_multiplier();
  contact_stats_.record_step(rows, l, slip_, unit, nodal_laws_.friction, mortar_.get());
  if (mortar_) {  // q = β_C λ_n [θ] per contact node (contact_heat.hpp)
    const auto& c = *problem_.contact;
    heat_flux_.assign(static_cast<size_t>(rows.n_nodes()), 0.0);
    if (c.heat_conduction && nodal_laws_.conducting &&
        mortar_->contact_nodes().size() == static_cast<size_t>(rows.n_nodes())) {
      std::vector<double> scale(nodal_laws_.beta_c);
      for (double& s : scale) s *= unit;
      heat_flux_ = conduction_flux(*mortar_, rows, l, scale, states_[c.slave_body].theta,
                                   states_[c.master_body].theta);
    }
  }
}

void Simulation::advance() {
  const auto t0 = Clock::now();
  for (auto& sv : solvers_) sv->initial_mass.reset();
  std::vector<core::Vector> old_u;
  for (const auto& st : states_) old_u.push_back(st.u.clone());
  int coupling = 0;
  if (problem_.contact) {
    if (!dual_) throw Error("the problem has contact but no contact rows (enable_contact)");
    coupling = couple_contact();
    contact_bookkeeping();
    total_qp_ += contact_stats_.qp_iterations;
    total_applications_ += contact_stats_.operator_applications;
  } else {
    for (int b = 0; b < n_bodies(); ++b) coupling = std::max(coupling, couple_body(b));
  }
  ++step_;
  finish_step_bookkeeping(old_u, coupling, seconds_since(t0));
}

void Simulation::finish_step_bookkeeping(const std::vector<core::Vector>& old_u, int coupling,
                                         double wall) {
  // External work by the trapezoidal rule, ½(F^k + F^{k+1})·(u^{k+1} − u^k): with Newmark's
  // average acceleration this makes the discrete energy balance exact for linear elasticity.
  for (int b = 0; b < n_bodies(); ++b) {
    auto& s = *solvers_[b];
    s.work_u.copy_from(states_[b].u);
    s.work_u.axpy(-1.0, old_u[b]);
    const double before = forces_[b].dot(s.work_u);
    support_forces(b, forces_[b]);
    external_work_ += 0.5 * (before + forces_[b].dot(s.work_u));
  }
  // Heat lost through the film and radiation boundaries in the step: τ Σ h∫(θ − θ∞)dS and
  // τ Σ ∫εσ(θ⁴ − θ∞⁴)dS at t^{k+1} with θ^{k+1}, the terms of the backward Euler step, so
  // that Δthermal_energy = heat in − heat_film − heat_radiation closes to the solver tolerance.
  for (int b = 0; b < n_bodies(); ++b) {
    const auto p = systems_[b]->boundary_heat_loss(time(), states_[b].theta);
    boundary_heat_.film += problem_.time.step * p.film;
    boundary_heat_.radiation += problem_.time.step * p.radiation;
  }
  total_coupling_ += coupling;
  last_coupling_ = coupling;
  last_wall_ = wall;
  history_.record();
}

double Simulation::kinetic_energy() const {
  if (problem_.time.scheme != Scheme::dynamic) return 0.0;
  double e = 0;
  for (int b = 0; b < n_bodies(); ++b)
    e += 0.5 * systems_[b]->matrices().mass_u.quadratic_form(states_[b].v, solvers_[b]->work_u);
  return e;
}

double Simulation::strain_energy() const {
  double e = 0;
  for (int b = 0; b < n_bodies(); ++b)
    e +=
        0.5 * systems_[b]->matrices().stiffness_u.quadratic_form(states_[b].u, solvers_[b]->work_u);
  return e;
}

double Simulation::thermal_energy() const {
  const double theta0 = problem_.physics.reference_temperature;
  double e = 0;
  for (int b = 0; b < n_bodies(); ++b) {
    const auto& vol = systems_[b]->node_volumes();
    const auto theta = states_[b].theta.to_std();
    const double c = systems_[b]->body().material.heat_capacity();
    for (size_t a = 0; a < vol.size(); ++a) e += c * vol[a] * (theta[a] - theta0);
  }
  return e;
}

double Simulation::thermal_free_energy() const {
  const double theta0 = problem_.physics.reference_temperature;
  double e = 0;
  for (int b = 0; b < n_bodies(); ++b) {
    auto& s = *solvers_[b];
    s.dtheta.copy_from(states_[b].theta);
    s.dtheta.shift(-theta0);
    e += systems_[b]->matrices().mass_theta.quadratic_form(s.dtheta, s.work_theta) / (2.0 * theta0);
  }
  return e;
}

void Simulation::register_history() {
  // The columns of history.csv in their order (docs/case-format.md), each with its quantity.
  auto& h = history_;
  const auto& cs = contact_stats_;
  const auto count = [](const int& n) { return [&n] { return static_cast<double>(n); }; };
  const auto value = [](const double& x) { return [&x] { return x; }; };
  h.add("step", count(step_));
  h.add("time", [this] { return time(); });
  h.add("coupling_iterations", count(last_coupling_));
  h.add("qp_iterations", count(cs.qp_iterations));
  h.add("operator_applications", count(cs.operator_applications));
  h.add("kinetic_energy", [this] { return kinetic_energy(); });
  h.add("strain_energy", [this] { return strain_energy(); });
  h.add("thermal_energy", [this] { return thermal_energy(); });
  h.add("external_work", value(external_work_));
  h.add("contact_normal_force", value(cs.normal_force));
  h.add("contact_tangential_force", value(cs.tangential_force));
  h.add("frictional_dissipation", value(cs.dissipation));
  h.add("heat_generated", value(heat_coupling_.heat().generated));
  h.add("heat_to_slave", value(heat_coupling_.heat().to_slave));
  h.add("heat_to_master", value(heat_coupling_.heat().to_master));
  h.add("heat_conducted", value(heat_coupling_.heat().conducted));
  h.add("max_temperature", [this] { return extreme_temperature(states_, true); });
  h.add("min_temperature", [this] { return extreme_temperature(states_, false); });
  h.add("active_nodes", count(cs.active_nodes));
  h.add("slip_nodes", count(cs.slip_nodes));
  h.add("wall_seconds", value(last_wall_));
  h.add("friction_iterations", count(cs.friction_iterations));
  h.add("contact_tangential_force_sum", value(cs.tangential_force_sum));
  h.add("heat_film", value(boundary_heat_.film));
  h.add("heat_radiation", value(boundary_heat_.radiation));
  // The force on each reaction group per axis, Σ F_d over its dofs (F: support_forces).
  const char* axes = "xyz";
  for (int b = 0; b < n_bodies(); ++b)
    for (const auto& g : systems_[b]->reaction_groups())
      for (int k = 0; k < problem_.dimension; ++k)
        h.add(g.label + "_" + axes[k], [this, b, &dofs = g.dofs[k]] {
          const auto f = forces_[b].read();
          double sum = 0;
          for (const PetscInt d : dofs) sum += f[d];
          return sum;
        });
}

RunStatus Simulation::run(Observer& observer, const std::atomic<int>* stop) {
  RunStatus status;
  observer.start(*this);
  const int n = problem_.time.n_steps();
  try {
    observer.step(*this);  // the initial state's output: a full disk may stop the run here
    while (step_ < n) {
      if (stop && stop->load() != 0) {
        status.message = fmt::format("interrupted by signal {} after step {} (t = {:g} s)",
                                     stop->load(), step_, time());
        status.exit_code = 1;
        break;
      }
      advance();
      observer.step(*this);
    }
  } catch (const NumericalError& e) {
    status.message = e.what();
    status.exit_code = 1;
  } catch (const PetscError& e) {
    status.message = fmt::format("{} (step {})", e.what(), step_ + 1);
    status.exit_code = 1;
  } catch (const OutputError& e) {  // a full disk: the steps written so far stay readable
    status.message = e.what();
    status.exit_code = 1;
  }
  status.completed = status.exit_code == 0;
  status.steps_done = step_;
  if (status.completed) status.message = fmt::format("completed {} steps", step_);
  observer.finish(*this, status);
  return status;
}

}  // namespace tc::physics
