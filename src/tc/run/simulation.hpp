#pragma once
// The time loop of chapters 5–6: it builds the bodies (constant matrices factorised once at
// construction, never inside the loop), wires the components of a step — BodySteps (heat and
// mechanical steps, the staggered loop 6.3 of a body), ContactCoupling (the contact pairs' loop,
// with the enforcement and contact time scheme of choose_contact_method), the time scheme
// (time_scheme.hpp: Newmark, quasistatic, backward Euler) — and keeps the run's ledger.
//
// Contract of run(): the observer sees start() once, then step() for t = 0 and for every
// completed step in order, then finish() exactly once, also when the run stops early.
#include <array>
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/error.hpp"
#include "tc/core/timer.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/physics/body/step/body_steps.hpp"
#include "tc/physics/body/step/finite_checks.hpp"
#include "tc/physics/contact/contact_enforcement.hpp"
#include "tc/physics/contact/contact_rows_builder.hpp"
#include "tc/physics/contact/step/contact_coupling.hpp"
#include "tc/record/checkpoint.hpp"
#include "tc/record/history.hpp"
#include "tc/record/ledger.hpp"
#include "tc/run/energies.hpp"

namespace tc::physics {

struct RunStatus {
  bool completed = false;
  int steps_done = 0;
  std::string message;
  int exit_code = 0;           // 0 done, 1 numerical failure or interrupted (case-format.md)
  bool between_steps = false;  // stopped by the stop flag: the state is the last step's, whole
};

class Simulation;

/// Receives the run's progress: output writers, progress lines, tests.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void start(const Simulation&) {}
  virtual void step(const Simulation&) {}
  virtual void finish(const Simulation&, const RunStatus&) {}
  /// Something the run goes on with but the user should know (one line, no "warning: ").
  virtual void warning(const Simulation&, const std::string&) {}
};

class Simulation {
 public:
  /// Assembles and factorises (collective on no communicator: each rank holds every body).
  explicit Simulation(const Problem& problem);
  ~Simulation();

  /// Turns on the contact of the problem's one pair, with the rows built by `builder` each step;
  /// the enforcement and the contact time scheme follow the settings (choose_contact_method).
  void enable_contact(ContactRowsBuilder builder, DualContactSettings settings = {});
  /// Turns on the contact of every pair of problem().contacts, each with the mortar pair of its
  /// two surfaces (contact::MortarPair), evaluated in the configuration of t^k at every step.
  void enable_mortar_contact(DualContactSettings settings = {},
                             contact::MortarOptions options = {});
  /// The contact pairs: their mortar pairs, multipliers, statistics (contact_coupling.hpp).
  [[nodiscard]] const ContactCoupling& contact() const { return contact_; }
  /// The first pair's mortar pair (null unless enable_mortar_contact was called).
  [[nodiscard]] const contact::MortarPair* mortar() const { return contact_.mortar(); }
  /// B_τ(u^{k+1} − u^k) of the last step, node-major like the multipliers (normal rows 0).
  [[nodiscard]] const std::vector<double>& contact_slip() const { return contact_.slip(); }
  /// Totals over the run so far (summary.json).
  [[nodiscard]] long total_qp_iterations() const { return contact_.total_qp_iterations(); }
  [[nodiscard]] long total_operator_applications() const {
    return contact_.total_operator_applications();
  }
  [[nodiscard]] const ContactStatistics& contact_statistics() const {
    return contact_.statistics();
  }
  /// The contact multipliers of the last step, node-major [λ_n, λ_τ…] (empty without contact).
  [[nodiscard]] std::vector<double> contact_multipliers() const { return contact_.multipliers(); }
  /// The contact traction per multiplier: ½ with the contact-stabilised Newmark (λ is
  /// twice the step's mean traction there, docs/choices.md), 1 otherwise.
  [[nodiscard]] double traction_per_multiplier() const {
    return contact_.traction_per_multiplier();
  }
  [[nodiscard]] const DualContactSolver* dual_solver() const { return contact_.dual(); }
  /// The contact enforcement that runs (null without contact): the combined TFETI QP or the
  /// nested dual; [solver] contact_dual.
  [[nodiscard]] const ContactEnforcement* contact_enforcement() const {
    return contact_.enforcement();
  }
  /// SMALBE's outer iterations so far (combined contact dual; 0 otherwise).
  [[nodiscard]] long total_smalbe_outer_iterations() const {
    return contact_.enforcement() ? contact_.enforcement()->outer_iterations() : 0;
  }
  [[nodiscard]] const ContactHeat& contact_heat() const { return contact_.heat().heat(); }
  [[nodiscard]] const BoundaryHeat& boundary_heat() const { return boundary_heat_; }
  /// Newton corrections and their conjugate-gradient iterations so far (heat steps with
  /// radiation or a film with h(t); boundary_heat_newton.hpp).
  [[nodiscard]] long total_newton_iterations() const {
    return steps_.newton_iterations() + contact_.heat().newton_iterations();
  }
  [[nodiscard]] long total_newton_inner_iterations() const {
    return steps_.newton_inner_iterations() + contact_.heat().newton_inner_iterations();
  }
  /// 𝔉(θ), β_C(θ), δ_C(θ) of (2.13) from the contact's friction and conductances.
  [[nodiscard]] const InterfaceLaws& interface_laws() const { return contact_.laws(); }
  /// 𝔉_k, β_C,k, δ_C,k per contact node of the last step, at the interface temperature of its
  /// last coupling iterate (order of the multipliers).
  [[nodiscard]] const NodalLaws& nodal_laws() const { return contact_.nodal_laws(); }
  /// Per contact node of the last step (order of the multipliers): q_C^s conduction part
  /// β_C λ_n [θ] (λ_n/2 with the contact-stabilised scheme), [θ] = θ_s − θ_m (θ_m of the master at
  /// the node, (Mθ_m)_k/(D1)_k), in W/m²: the heat flux out of the slave into the master (positive
  /// when the slave is hotter). Zero with heat_conduction = false; empty without the mortar pair.
  [[nodiscard]] std::vector<double> contact_heat_flux() const { return contact_.heat_flux(); }
  /// The solver of the implicit heat step (null until conductance first appears).
  [[nodiscard]] const InterfaceHeatSolver* interface_heat_solver() const {
    return contact_.heat().interface_heat_solver();
  }

  /// The state after the current step (restart: io/restart/checkpoint.hpp).
  [[nodiscard]] Checkpoint checkpoint() const;
  /// Continues from a checkpoint of the same problem (sizes checked: throws Error).
  void restore(const Checkpoint& c);

  /// Runs all steps, or until `stop` becomes non-zero (checked between steps).
  RunStatus run(Observer& observer, const std::atomic<int>* stop = nullptr);
  /// Steps cut back so far ([solver] max_cutbacks): how many steps of τ were taken as
  /// sub-steps, and the smallest sub-step used (τ when none).
  [[nodiscard]] int cut_back_steps() const { return cut_back_steps_; }
  /// Re-assemblies of K_u, K_uθ and refactorisations of A_u so far, summed over the bodies whose
  /// E or ν is a table in θ ([solver] modulus_tolerance; refresh_moduli).
  [[nodiscard]] int mechanical_refactorisations() const { return refactorisations_; }
  [[nodiscard]] double smallest_step() const { return smallest_step_; }

  /// Advances one step (public for tests); throws NumericalError on failure. A step that
  /// fails is cut back: retried from its start as two steps of τ/2 (advance_by_halves).
  void advance();

  [[nodiscard]] const Problem& problem() const { return problem_; }
  [[nodiscard]] int n_bodies() const { return bodies_.size(); }
  [[nodiscard]] const BodySystem& system(int b) const { return *bodies_.systems[b]; }
  [[nodiscard]] const BodyState& state(int b) const { return bodies_.states[b]; }
  [[nodiscard]] int step() const { return step_; }
  [[nodiscard]] double time() const { return step_ * problem_.time.step; }
  [[nodiscard]] const core::PhaseTimers& timers() const { return timers_; }
  [[nodiscard]] const std::string& factorization() const { return factorization_; }
  [[nodiscard]] PetscInt n_dofs() const;
  /// FETI solves and projected-CG iterations so far, summed over the decomposed bodies' solvers.
  [[nodiscard]] feti::FetiStatistics feti_statistics() const;

  /// history.csv: names of the columns and the row of the current step.
  [[nodiscard]] const std::vector<std::string>& history_columns() const {
    return history_.columns();
  }
  [[nodiscard]] const std::vector<double>& history_row() const { return history_.row(); }
  [[nodiscard]] double history(const std::string& column) const { return history_[column]; }
  [[nodiscard]] long total_coupling_iterations() const { return total_coupling_; }

  /// Discrete energies of the current state (J, or J/m in 2D; energies.hpp).
  [[nodiscard]] double kinetic_energy() const { return physics::kinetic_energy(problem_, bodies_); }
  [[nodiscard]] double strain_energy() const { return physics::strain_energy(bodies_); }
  /// Σ ∫ ρ c_p (θ − θ₀) dx.
  [[nodiscard]] double thermal_energy() const { return physics::thermal_energy(problem_, bodies_); }
  /// (1/2θ₀)(θ−θ₀)ᵀ M_θ (θ−θ₀): the thermal part of the thermo-elastic Lyapunov function.
  [[nodiscard]] double thermal_free_energy() const {
    return physics::thermal_free_energy(problem_, bodies_);
  }

 private:
  void set_up();  // the constructor's work: assembly, factorisations, the initial state
  void initialise();
  void static_initial_state(int b, BodyState& st);
  void finish_step_bookkeeping(const std::vector<core::Vector>& old_u, int coupling, double wall);
  void register_history();  // the columns of history.csv: its own and its components'
  void register_load_history(History& h);  // faces under load control: w and the resultant

  /// Throws NumericalError when a body's absolute temperature after step `step` is ≤ 0 (the
  /// linearised model has left physics: tables and radiation would be read below 0 K); the
  /// first time the state leaves |θ − θ₀| ≤ θ₀ with a thermoelastic coupling on, a warning is
  /// queued (docs/choices.md).
  void check_temperature_range(int step, int iteration);

  void advance_once();  // the step k → k + 1 at τ
  /// At a step's start: the bodies whose moduli at θ^k moved beyond [solver] modulus_tolerance
  /// from those factorised get K_u, K_uθ re-assembled and A_u refactorised, the contact's
  /// compliance with it (lagged: the moduli of θ^k for the step to t^{k+1}).
  void refresh_moduli();
  /// The step from `start` (its state, step k) as two steps of τ/2 on a copy of the problem
  /// with that step, whose own cut-backs go one level less deep; then this simulation takes
  /// the copy's state at t^{k+1} (docs/choices.md, "Step cut-back").
  void advance_by_halves(const Checkpoint& start, const NumericalError& failure);

  const Problem& problem_;
  core::PhaseTimers timers_;
  Bodies bodies_;
  BodySteps steps_;          // the heat and mechanical steps of one body, its loop (6.3)
  ContactCoupling contact_;  // the contact pairs' loop (6.3) and their enforcement
  EnergyBalance energy_;     // support forces and external work
  int step_ = 0;
  long total_coupling_ = 0;
  int last_coupling_ = 0;
  double last_wall_ = 0;  // seconds of the last step (history.csv wall_seconds)
  std::string factorization_;
  History history_;
  BoundaryHeat boundary_heat_;
  bool range_warned_ = false;          // the linearisation warning is given once per run
  std::vector<std::string> warnings_;  // queued for the observer by run()

  // How contact was enabled (the τ/2 copy is enabled the same way), the depth of this
  // simulation among cut-backs (0: the run's own), and what the cut-backs did.
  std::function<void(Simulation&)> enable_contact_again_;
  int cutback_depth_ = 0;
  int cut_back_steps_ = 0;
  int refactorisations_ = 0;
  double smallest_step_ = 0;
};

}  // namespace tc::physics
