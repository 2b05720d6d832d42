#include "tc/physics/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>

#include "tc/core/error.hpp"
#include "tc/physics/body_field.hpp"
#include "tc/physics/time_scheme.hpp"

namespace tc::physics {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

Simulation::Simulation(const Problem& problem)
    : problem_(problem),
      steps_(problem, bodies_, timers_),
      contact_(problem, bodies_, steps_, timers_),
      energy_(problem, bodies_) {
  // The set-up outside assembly and factorisation (the initial state's bookkeeping, the
  // history's columns): a phase of its own, so that summary.json's phases add up.
  auto setup = timers_.scope("setup");
  for (int b = 0; b < static_cast<int>(problem_.bodies.size()); ++b) {
    {
      auto t = timers_.scope("assembly");
      bodies_.systems.push_back(std::make_unique<BodySystem>(problem_, b));
    }
    const auto& sys = *bodies_.systems.back();
    std::unique_ptr<BodyField> s;
    {
      auto t = timers_.scope("factorization");
      s = std::make_unique<BodyField>(problem_, sys);
    }
    factorization_ = s->mech->package();
    bodies_.fields.push_back(std::move(s));
  }
  initialise();
  check_setup_finite(bodies_.systems, bodies_.states);
}

Simulation::~Simulation() = default;

PetscInt Simulation::n_dofs() const {
  PetscInt n = 0;
  for (const auto& s : bodies_.systems) n += s->n_u() + s->n_theta();
  return n;
}

feti::FetiStatistics Simulation::feti_statistics() const {
  feti::FetiStatistics total;
  for (const auto& s : bodies_.fields)
    for (const auto* solver : {s->mech.get(), s->heat.get(), s->mass.get()})
      if (solver && solver->feti()) total += solver->feti()->statistics();
  return total;
}

void Simulation::initialise() {
  for (int b = 0; b < n_bodies(); ++b) {
    const auto& sys = *bodies_.systems[b];
    auto& s = *bodies_.fields[b];
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
      // with ü = 0 on the supports.
      auto t = timers_.scope("factorization");
      const auto& m = sys.matrices();
      sys.mechanical_load(0.0, s.rhs_u);
      m.stiffness_u.mult(st.u, s.work_u);
      s.rhs_u.axpy(-1.0, s.work_u);
      if (problem_.physics.thermal_expansion)
        subtract_thermal_force(problem_, sys, s, st.theta, s.rhs_u);
      s.g_free = s.rhs_u.clone();  // g⁰ = M ü⁰ (no contact force at t = 0)
      solve_initial_acceleration(sys, s.rhs_u, st.a);
    }
    bodies_.states.push_back(std::move(st));
  }

  energy_.start(time());
  register_history();
  history_.record();
}

void Simulation::static_initial_state(int b, BodyState& st) {
  // K u⁰ = f(0) − K_uθ(θ⁰ − θ₀) with u⁰ = u_D(0) on the supports: the body starts expanded
  // by its initial temperature and loaded, so ü⁰ = 0 off the supports. Released from u⁰ = 0
  // instead, a body 80 K above θ₀ rings with ~2e4 J (example 05's cube), at frequencies that
  // Newmark's τ aliases to the step-to-step oscillation without damping it.
  auto t = timers_.scope("factorization");
  const auto& sys = *bodies_.systems[b];
  const auto& m = sys.matrices();
  auto& s = *bodies_.fields[b];
  sys.mechanical_load(0.0, s.rhs_u);
  if (problem_.physics.thermal_expansion)
    subtract_thermal_force(problem_, sys, s, st.theta, s.rhs_u);
  body_solver(problem_, sys, m.stiffness_u, BodyOperator::statics)->solve(s.rhs_u, st.u);
  require_finite(st.u, "displacement", 0, 0);
}

void Simulation::enable_contact(ContactRowsBuilder builder, DualContactSettings settings) {
  auto t = timers_.scope("setup");
  contact_.enable(std::move(builder), std::move(settings), step_);
}

void Simulation::enable_mortar_contact(DualContactSettings settings,
                                       contact::MortarOptions options) {
  auto t = timers_.scope("setup");
  contact_.enable_mortar(std::move(settings), options, step_);
}

void Simulation::advance() {
  const auto t0 = Clock::now();
  // What a step does outside the solver phases (predictor, right-hand sides, energies,
  // reactions, the history row): the phases opened inside take their own time.
  auto scope = timers_.scope("step_other");
  std::vector<core::Vector> old_u;
  for (const auto& st : bodies_.states) old_u.push_back(st.u.clone());
  int coupling = 0;
  if (!problem_.contacts.empty()) {
    if (!contact_.enabled())
      throw Error("the problem has contact but no contact rows (enable_contact)");
    coupling = contact_.couple(step_ + 1);
    const auto& members = contact_.members();
    for (int b = 0; b < n_bodies(); ++b)  // the bodies in no pair
      if (std::find(members.begin(), members.end(), b) == members.end())
        steps_.couple(b, step_ + 1);
    contact_.bookkeeping();
  } else {
    for (int b = 0; b < n_bodies(); ++b) coupling = std::max(coupling, steps_.couple(b, step_ + 1));
  }
  ++step_;
  finish_step_bookkeeping(old_u, coupling, seconds_since(t0));
}

void Simulation::finish_step_bookkeeping(const std::vector<core::Vector>& old_u, int coupling,
                                         double wall) {
  energy_.account_step(old_u, time());
  boundary_heat_.account_step(bodies_, time(), problem_.time.step);
  total_coupling_ += coupling;
  last_coupling_ = coupling;
  last_wall_ = wall;
  history_.record();
}

void Simulation::register_history() {
  // Each component registers the columns it owns; History keeps the file's order.
  auto& h = history_;
  h.add("step", History::value_of(step_));
  h.add("time", [this] { return time(); });
  h.add("coupling_iterations", History::value_of(last_coupling_));
  h.add("wall_seconds", History::value_of(last_wall_));
  energy_.register_history(h);
  contact_.register_history(h);
  boundary_heat_.register_history(h);
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
        status.between_steps = true;
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
