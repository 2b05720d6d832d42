#include "tc/run/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "tc/core/error.hpp"
#include "tc/core/heap.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/time_scheme.hpp"

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
      energy_(problem, bodies_, &contact_) {
  try {
    set_up();
  } catch (const NumericalError& e) {  // a FETI or CG solve of the set-up: it has no step
    rethrow_at_step(e, 0);
  }
}

void Simulation::set_up() {
  // The set-up outside assembly and factorisation (the initial state's bookkeeping, the
  // history's columns): a phase of its own, so that summary.json's phases add up.
  auto setup = timers_.scope("setup");
  if (int ranks = 1; MPI_Comm_size(PETSC_COMM_WORLD, &ranks) == MPI_SUCCESS && ranks > 1)
    for (const auto& b : problem_.bodies)
      if (b.material.nonlinear_moduli())
        throw Error(fmt::format(
            "body \"{}\": young_modulus or poisson_ratio is a table in θ, which runs on one "
            "rank only (its refactorisation is not collective); run it without mpirun, or "
            "give E and ν as numbers",
            b.name));
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
    // The assembly's node graphs, the copies made to factorise and CHOLMOD's work, freed in
    // small blocks amid what stays: returned before the next body's factor is added to them.
    core::release_free_heap();
  }
  smallest_step_ = problem_.time.step;
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

    const bool inertia = body_time_scheme(problem_).inertia();
    if (inertia && sys.body().start_in_equilibrium) static_initial_state(b, st);
    if (inertia) {
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
  enable_contact_again_ = [builder, settings](Simulation& s) {
    s.enable_contact(builder, settings);
  };
  auto t = timers_.scope("setup");
  contact_.enable(std::move(builder), std::move(settings), step_);
}

void Simulation::enable_mortar_contact(DualContactSettings settings,
                                       contact::MortarOptions options) {
  enable_contact_again_ = [settings, options](Simulation& s) {
    s.enable_mortar_contact(settings, options);
  };
  auto t = timers_.scope("setup");
  contact_.enable_mortar(std::move(settings), options, step_);
}

void Simulation::advance() {
  if (problem_.solver.max_cutbacks <= 0) return advance_once();
  // The state of the step's start, in memory: what a checkpoint holds, so that a retry starts
  // from the bits a restart would.
  const Checkpoint start = checkpoint();
  try {
    advance_once();
  } catch (const NumericalError& e) {
    advance_by_halves(start, e);
  }
}

void Simulation::advance_by_halves(const Checkpoint& start, const NumericalError& failure) {
  const double tau = problem_.time.step;
  const int left = problem_.solver.max_cutbacks;
  // A copy of the problem with τ/2 (its end unchanged: twice the steps), its bodies assembled
  // and factorised anew for τ/2, its state that of the step's start (step 2k of τ/2 is t^k:
  // 2k·(τ/2) = k·τ exactly in binary floating point).
  auto half = std::make_unique<Problem>(problem_);
  half->time.step = tau / 2;
  half->solver.max_cutbacks = left - 1;
  std::unique_ptr<Simulation> sub;
  try {
    sub = std::make_unique<Simulation>(*half);
    sub->cutback_depth_ = cutback_depth_ + 1;
    if (enable_contact_again_) enable_contact_again_(*sub);
    Checkpoint from = start;
    from.step = 2 * start.step;
    sub->restore(from);
    sub->advance();
    std::vector<double> first = sub->history_.row();
    sub->advance();
    Checkpoint end = sub->checkpoint();
    // One row for the whole step (docs/choices.md): the state at t^{k+1}, the per-step counts
    // summed over the sub-steps, the step and time of this run.
    end.step = start.step + 1;
    const auto& columns = history_.columns();
    for (size_t i = 0; i < columns.size() && i < end.row.size(); ++i) {
      const auto& c = columns[i];
      if (c == "step")
        end.row[i] = end.step;
      else if (c == "time")
        end.row[i] = end.step * tau;
      else if (c == "coupling_iterations" || c == "wall_seconds" || c == "qp_iterations" ||
               c == "operator_applications" || c == "friction_iterations")
        end.row[i] += first[i];
    }
    restore(end);
    contact_.merge_laws(sub->contact_.laws_checked(), step_);
    cut_back_steps_ += 1 + sub->cut_back_steps_;
    refactorisations_ += sub->refactorisations_;
    smallest_step_ = std::min(smallest_step_, sub->smallest_step_);
    last_coupling_ = static_cast<int>(history_["coupling_iterations"]);
    last_wall_ = history_["wall_seconds"];
  } catch (const NumericalError& e) {
    if (cutback_depth_ > 0) throw;  // the run's own simulation says what happened
    throw NumericalError(
        fmt::format("{}; cut back {} time(s) to τ = {:g} s it still failed: {}; raise [solver] "
                    "max_cutbacks (now {}) or change what the messages name",
                    failure.at_step(step_ + 1).what(), left, tau / std::pow(2.0, left),
                    e.at_step(step_ + 1).what(), left),
        step_ + 1, 0, e.residual());
  }
}

void Simulation::refresh_moduli() {
  for (int b = 0; b < n_bodies(); ++b) {
    auto& sys = *bodies_.systems[b];
    if (!sys.moduli_follow_temperature()) continue;
    {
      auto t = timers_.scope("assembly");
      if (!sys.update_moduli(bodies_.states[b].theta, problem_.solver.modulus_tolerance)) continue;
    }
    auto t = timers_.scope("factorization");
    bodies_.fields[b]->refactorise_mechanics(problem_, sys);
    contact_.refactorised(b);
    ++refactorisations_;
  }
}

void Simulation::advance_once() {
  const auto t0 = Clock::now();
  refresh_moduli();
  // What a step does outside the solver phases (predictor, right-hand sides, energies,
  // reactions, the history row): the phases opened inside take their own time.
  auto scope = timers_.scope("step_other");
  std::vector<core::Vector> old_u;
  for (const auto& st : bodies_.states) old_u.push_back(st.u.clone());
  // Each group of bodies enters the time scheme once: its beginning, the group's fixed point
  // (the contact pairs' bodies together, every other body alone), its end.
  const auto& scheme = body_time_scheme(problem_);
  const int next = step_ + 1;
  const double t = next * problem_.time.step;
  int coupling = 0;
  if (!problem_.contacts.empty()) {
    if (!contact_.enabled())
      throw Error("the problem has contact but no contact rows (enable_contact)");
    const auto& members = contact_.members();
    coupling = scheme.step(problem_, bodies_, members, t, [&] { return contact_.couple(next); });
    for (int b = 0; b < n_bodies(); ++b)  // the bodies in no pair
      if (std::find(members.begin(), members.end(), b) == members.end())
        scheme.step(problem_, bodies_, {b}, t, [&] { return steps_.couple(b, next); });
  } else {
    for (int b = 0; b < n_bodies(); ++b)
      coupling = std::max(
          coupling, scheme.step(problem_, bodies_, {b}, t, [&] { return steps_.couple(b, next); }));
  }
  check_temperature_range(step_ + 1, coupling);
  ++step_;
  finish_step_bookkeeping(old_u, coupling, seconds_since(t0));
}

void Simulation::check_temperature_range(int step, int iteration) {
  const double theta0 = problem_.physics.reference_temperature;
  for (int b = 0; b < n_bodies(); ++b) {
    const auto& theta = bodies_.states[b].theta;
    PetscInt lo_at = -1, hi_at = -1;
    PetscReal lo = 0, hi = 0;
    TC_PETSC(VecMin(theta.get(), &lo_at, &lo));
    TC_PETSC(VecMax(theta.get(), &hi_at, &hi));
    const auto& name = problem_.bodies[static_cast<size_t>(b)].name;
    // One θ dof per node: the index is the mesh node.
    const auto where = [&](PetscInt node) {
      const auto& x = bodies_.systems[b]->body().mesh.point(static_cast<int>(node));
      return fmt::format("node {} ({:g}, {:g}, {:g})", node, x[0], x[1], x[2]);
    };
    if (!(lo > 0))
      throw NumericalError(
          fmt::format("heat step: the absolute temperature of body \"{}\" fell to {:.6g} K at {} "
                      "(θ ≤ 0 K): the model, linearised about θ₀ = {:g} K, no longer describes "
                      "the state (a smaller time step, or θ₀ and the loads nearer the run's "
                      "temperatures)",
                      name, static_cast<double>(lo), where(lo_at), theta0),
          step, iteration, static_cast<double>(lo));
    // The linearisation about θ₀ is that of the thermoelastic coupling (θ₀K_uθᵀu̇, K_uθ(θ − θ₀)):
    // without it there is nothing to warn about.
    const bool coupled =
        problem_.physics.thermal_expansion || problem_.physics.thermoelastic_heating;
    if (range_warned_ || !coupled) continue;
    const bool low = theta0 - lo >= hi - theta0;
    const double far = low ? static_cast<double>(lo) : static_cast<double>(hi);
    if (std::abs(far - theta0) <= theta0) continue;
    range_warned_ = true;
    warnings_.push_back(fmt::format(
        "step {}: body \"{}\" reached θ = {:.6g} K at {}, |θ − θ₀| > θ₀ = {:g} K: beyond the "
        "range where the thermoelastic model, linearised about θ₀, holds (results stay "
        "finite but may be inaccurate; warned once per run)",
        step, name, far, where(low ? lo_at : hi_at), theta0));
  }
}

void Simulation::finish_step_bookkeeping(const std::vector<core::Vector>& old_u, int coupling,
                                         double wall) {
  energy_.account_step(old_u, time());
  for (int b = 0; b < bodies_.size(); ++b) {
    const auto p = bodies_.systems[b]->boundary_heat_loss(time(), bodies_.states[b].theta);
    boundary_heat_.account_step(p.film, p.radiation, problem_.time.step);
  }
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
  register_load_history(h);
}

void Simulation::register_load_history(History& h) {
  // Per face under load control and loaded component: its displacement w (the face's first
  // node) and the resultant Σ_D(K u + M ü + K_uθ(θ − θ₀) − f) the body exerts on it, which the
  // coupling balances with the prescribed force (support_forces gives the first part).
  const char* axes = "xyz";
  for (int b = 0; b < n_bodies(); ++b)
    for (const auto& face : bodies_.systems[b]->coupled_faces()) {
      const std::string axis(1, axes[face.component]);
      h.add("displacement_" + face.label + "_" + axis,
            [this, b, &face] { return bodies_.states[b].u.read()[face.dofs.front()]; });
      h.add("force_" + face.label + "_" + axis, [this, b, &face] {
        const auto& sys = *bodies_.systems[b];
        core::Vector r(sys.n_u()), f(sys.n_u());
        support_forces(problem_, bodies_, b, time(), r);
        sys.mechanical_load(time(), f);
        const auto rv = r.read();
        const auto fv = f.read();
        double sum = 0;
        for (const PetscInt d : face.dofs) sum += rv[d] - fv[d];
        return sum;
      });
    }
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
      for (const auto& w : warnings_) observer.warning(*this, w);
      warnings_.clear();
      observer.step(*this);
    }
  } catch (const NumericalError& e) {
    // FETI and the QPs do not know the step they solve for (step < 0): the one under way.
    status.message = e.at_step(step_ + 1).what();
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
