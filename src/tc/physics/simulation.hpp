#pragma once
// The time loop of chapters 5–6 without contact: Newmark average acceleration for u
// (5.1–5.3) or the quasistatic scheme, backward Euler for θ (5.5–5.6), and the staggered
// fixed point of 6.3 between the heat step and the mechanical step. Constant matrices are
// factorised once at construction, never inside the loop.
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
#include "tc/core/timer.hpp"
#include "tc/feti/contact_feti.hpp"
#include "tc/physics/body_field.hpp"
#include "tc/physics/body_system.hpp"
#include "tc/physics/checkpoint.hpp"
#include "tc/physics/constrained_solver.hpp"
#include "tc/physics/contact_heat_coupling.hpp"
#include "tc/physics/dual_contact.hpp"
#include "tc/physics/finite_checks.hpp"
#include "tc/physics/friction_fixed_point.hpp"
#include "tc/physics/history.hpp"
#include "tc/physics/ledger.hpp"
#include "tc/physics/multiplier_transfer.hpp"
#include "tc/physics/thermal_contact.hpp"

namespace tc::physics {

struct RunStatus {
  bool completed = false;
  int steps_done = 0;
  std::string message;
  int exit_code = 0;  // 0 done, 1 numerical failure or interrupted (case-format.md)
};

class Simulation;

/// Receives the run's progress: output writers, progress lines, tests.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void start(const Simulation&) {}
  virtual void step(const Simulation&) {}
  virtual void finish(const Simulation&, const RunStatus&) {}
};

class Simulation {
 public:
  /// Assembles and factorises (collective on no communicator: each rank holds every body).
  explicit Simulation(const Problem& problem);
  ~Simulation();

  /// Turns on the contact of problem().contact, with the rows built by `builder` each step.
  void enable_contact(ContactRowsBuilder builder, DualContactSettings settings = {});
  /// Turns on the contact of problem().contact with the mortar pair of its two surfaces
  /// (contact::MortarPair), evaluated in the configuration of t^k at every step.
  void enable_mortar_contact(DualContactSettings settings = {},
                             contact::MortarOptions options = {});
  /// The mortar pair (null unless enable_mortar_contact was called).
  [[nodiscard]] const contact::MortarPair* mortar() const { return mortar_.get(); }
  /// B_τ(u^{k+1} − u^k) of the last step, node-major like the multipliers (normal rows 0).
  [[nodiscard]] const std::vector<double>& contact_slip() const { return slip_; }
  /// Totals over the run so far (summary.json).
  [[nodiscard]] long total_qp_iterations() const { return total_qp_; }
  [[nodiscard]] long total_operator_applications() const { return total_applications_; }
  [[nodiscard]] const ContactStatistics& contact_statistics() const { return contact_stats_; }
  /// The contact multipliers of the last step, node-major [λ_n, λ_τ…] (empty without contact).
  [[nodiscard]] std::vector<double> contact_multipliers() const;
  /// The contact traction per unit multiplier: ½ with the contact-stabilised Newmark (λ is
  /// twice the step's mean traction there, docs/choices.md), 1 otherwise.
  [[nodiscard]] double traction_per_multiplier() const;
  [[nodiscard]] const DualContactSolver* dual_solver() const { return dual_.get(); }
  /// The contact dual that runs: the combined TFETI QP (feti::ContactFeti, SMALBE) or the
  /// nested one (DualContactSolver on each body's solver); [solver] contact_dual.
  [[nodiscard]] bool combined_contact_dual() const { return combined_; }
  /// SMALBE's outer iterations so far (combined contact dual; 0 otherwise).
  [[nodiscard]] long total_smalbe_outer_iterations() const { return total_smalbe_outer_; }
  /// Implicit (default) or lagged conductance; for measurements (docs/choices.md).
  void set_conductance_treatment(ConductanceTreatment t) { heat_coupling_.set_treatment(t); }
  [[nodiscard]] const ContactHeat& contact_heat() const { return heat_coupling_.heat(); }
  [[nodiscard]] const BoundaryHeat& boundary_heat() const { return boundary_heat_; }
  /// Newton corrections and their conjugate-gradient iterations so far (heat steps with
  /// radiation or a film with h(t); boundary_heat.hpp).
  [[nodiscard]] long total_newton_iterations() const {
    return total_newton_ + heat_coupling_.newton_iterations();
  }
  [[nodiscard]] long total_newton_inner_iterations() const {
    return total_newton_inner_ + heat_coupling_.newton_inner_iterations();
  }
  /// Aitken relaxation of the Tresca → Coulomb fixed point (default on; docs/choices.md).
  void set_coupling_acceleration(bool on) { accelerate_ = on; }
  /// Overrides problem().solver.friction_loop (comparisons).
  void set_friction_loop(FrictionLoop loop) { friction_loop_ = loop; }
  /// 𝔉(θ), β_C(θ), δ_C(θ) of (2.13) from the contact's friction and conductances.
  [[nodiscard]] const InterfaceLaws& interface_laws() const { return laws_; }
  /// 𝔉_k, β_C,k, δ_C,k per contact node of the last step, at the interface temperature of its
  /// last coupling iterate (order of the multipliers).
  [[nodiscard]] const NodalLaws& nodal_laws() const { return nodal_laws_; }
  /// Per contact node of the last step (order of the multipliers): q_C^s conduction part
  /// β_C λ_n [θ] (λ_n/2 with the contact-stabilised scheme), [θ] = θ_s − θ_m (θ_m of the master at
  /// the node, (Mθ_m)_k/(D1)_k), in W/m²: the heat flux out of the slave into the master (positive
  /// when the slave is hotter). Zero with heat_conduction = false; empty without the mortar pair.
  [[nodiscard]] const std::vector<double>& contact_heat_flux() const { return heat_flux_; }
  /// The solver of the implicit heat step (null until conductance first appears).
  [[nodiscard]] const InterfaceHeatSolver* interface_heat_solver() const {
    return heat_coupling_.interface_heat_solver();
  }

  /// The state after the current step (restart: io/checkpoint.hpp).
  [[nodiscard]] Checkpoint checkpoint() const;
  /// Continues from a checkpoint of the same problem (sizes checked: throws Error).
  void restore(const Checkpoint& c);

  /// Runs all steps, or until `stop` becomes non-zero (checked between steps).
  RunStatus run(Observer& observer, const std::atomic<int>* stop = nullptr);
  /// Advances one step (public for tests); throws NumericalError on failure.
  void advance();

  [[nodiscard]] const Problem& problem() const { return problem_; }
  [[nodiscard]] int n_bodies() const { return static_cast<int>(systems_.size()); }
  [[nodiscard]] const BodySystem& system(int b) const { return *systems_[b]; }
  [[nodiscard]] const BodyState& state(int b) const { return states_[b]; }
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

  /// Discrete energies of the current state (J, or J/m in 2D).
  [[nodiscard]] double kinetic_energy() const;
  [[nodiscard]] double strain_energy() const;
  /// Σ ∫ ρ c_p (θ − θ₀) dx.
  [[nodiscard]] double thermal_energy() const;
  /// (1/2θ₀)(θ−θ₀)ᵀ M_θ (θ−θ₀): the thermal part of the thermo-elastic Lyapunov function.
  [[nodiscard]] double thermal_free_energy() const;

 private:
  void initialise();
  int couple_body(int b);  // the staggered loop of 6.3 for one body; returns iterations
  void heat_step(int b, int iteration);   // (6.1)/(5.6) with the current u iterate
  void heat_rhs(int b);                   // right-hand side of (6.1) without contact terms
  void contact_heat_step(int iteration);  // (4.3) for the contact pair: + L_θγ θ = … + d_θγ
  [[nodiscard]] HeatPair heat_pair();     // the contact pair's fields, systems and states
  void mech_load(int b);  // right-hand side of (5.3) at the current θ iterate, Dirichlet values
  void mech_step(int b, int iteration);  // (5.3) with the current θ iterate, no contact
  void static_initial_state(int b, BodyState& st);
  int couple_contact();  // the staggered loop of 6.3 for the contact pair (heat, dual QP)
  // The mechanical half of (6.3) with u_free fixed: coulomb_fixed_point over the contact QPs
  // (nested dual or combined TFETI), then u; returns ‖λ_n(γ) − γ‖ of the last update.
  double contact_mech_step(TrescaIteration& t, std::span<const double> targets, int outer,
                           int max_updates);
  void stabilise_predictor(std::span<const double> normal_targets);
  void contact_bookkeeping();
  void finish_step_bookkeeping(const std::vector<core::Vector>& old_u, int coupling, double wall);
  void support_forces(int b, core::Vector& r) const;  // reactions at constrained dofs
  void register_history();  // the columns of history.csv, each with what fills it

  const Problem& problem_;
  std::vector<std::unique_ptr<BodySystem>> systems_;
  std::vector<std::unique_ptr<BodyField>> solvers_;
  std::vector<BodyState> states_;
  std::vector<core::Vector> forces_;  // f_ext + reactions at the current step, per body
  int step_ = 0;
  double external_work_ = 0;
  long total_coupling_ = 0;
  long total_qp_ = 0, total_applications_ = 0;
  int last_coupling_ = 0;
  double last_wall_ = 0;  // seconds of the last step (history.csv wall_seconds)
  core::PhaseTimers timers_;
  std::string factorization_;
  History history_;

  ContactRowsBuilder contact_rows_;
  std::unique_ptr<contact::MortarPair> mortar_;
  std::unique_ptr<DualContactSolver> dual_;
  std::unique_ptr<DualContactSolver> stabiliser_;  // the mass projection (contact-stabilised)
  // The combined contact dual ([solver] contact_dual): one TFETI QP per Tresca bound, rebuilt
  // on each step's rows; dual_ keeps the rows and targets only (F never formed).
  bool combined_ = false;
  std::unique_ptr<feti::ContactFeti> contact_feti_;
  feti::ContactFetiState feti_state_;
  long total_smalbe_outer_ = 0;
  core::Vector lambda_;
  MultiplierTransfer transfer_;  // what lambda_ refers to, for the next step's warm start
  std::vector<double> slip_;     // B_τ Δu of the last step (node-major, normal rows unused)
  // B(u − u^k) of the current iterate while couple_contact defers forming u (empty: from u)
  std::vector<double> iterate_slip_;
  ContactStatistics contact_stats_;

  // Thermal contact (2.13, §4.4), with the mortar pair only.
  bool accelerate_ = true;
  FrictionLoop friction_loop_;
  ContactHeatCoupling heat_coupling_;
  InterfaceLaws laws_;    // the contact's 𝔉(θ), γ_C(θ)
  NodalLaws nodal_laws_;  // …at the contact nodes of the last coupling iterate
  BoundaryHeat boundary_heat_;
  long total_newton_ = 0, total_newton_inner_ = 0;
  std::vector<double> heat_flux_;
};

}  // namespace tc::physics
