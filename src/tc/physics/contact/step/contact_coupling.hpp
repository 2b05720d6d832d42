#pragma once
// The step of the contact pairs (6.3): the staggered fixed point between the heat step of their
// bodies (ContactHeatCoupling: L_θγ, d_θγ of each pair) and their mechanical step, one QP for
// all pairs, whose contact is enforced by a
// ContactEnforcement inside the Tresca → Coulomb fixed point (coulomb_fixed_point), with the
// ContactTimeScheme of the run around it; the multipliers carried from step to step
// (MultiplierTransfer) and what the contact reports (ContactStatistics, heat flux).
#include <array>
#include <memory>
#include <span>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/timer.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/physics/body/step/body_steps.hpp"
#include "tc/physics/body/step/finite_checks.hpp"
#include "tc/physics/contact/contact_laws.hpp"
#include "tc/physics/contact/contact_rows_builder.hpp"
#include "tc/physics/contact/friction_fixed_point.hpp"
#include "tc/physics/contact/multiplier_transfer.hpp"
#include "tc/physics/contact/step/contact_method.hpp"
#include "tc/physics/interface_heat/contact_heat_coupling.hpp"
#include "tc/physics/interface_heat/interface_laws.hpp"
#include "tc/record/checkpoint.hpp"
#include "tc/record/ledger.hpp"

namespace tc::physics {

/// One contact pair within the coupling: its rows, laws, warm start and ledger.
struct ContactPairState {
  const ContactSettings* settings = nullptr;
  PairBodies bodies;  // its slave and master in the ContactGroup
  ContactRowsBuilder rows;
  std::unique_ptr<contact::MortarPair> mortar;
  InterfaceLaws laws;           // 𝔉(θ), γ_C(θ)
  NodalLaws nodal;              // …at its contact nodes of the last coupling iterate
  MultiplierTransfer transfer;  // what its multipliers refer to, for the next warm start
  ContactStatistics stats;      // its forces, node counts and dissipation
  std::vector<double> heat_flux;
  /// Slave nodes that also lie on the slave surface of an earlier pair with the same slave
  /// body (crosspoints): their multipliers are the earlier pair's, this pair's are held at 0.
  std::vector<char> crosspoint;
  /// The resultant force of the contact on its slave body after the last step, per axis
  /// (ContactCoupling::slave_force).
  std::array<double, 3> slave_force{0, 0, 0};
  /// The step's shift of the weighted gaps, per contact node: the gap linearised about the
  /// predicted configuration is g − B(u − u^k) + gap_shift (ContactCoupling::set_rows).
  std::vector<double> gap_shift;
};

class ContactCoupling {
 public:
  ContactCoupling(const Problem& problem, Bodies& bodies, BodySteps& steps,
                  core::PhaseTimers& timers)
      : problem_(problem), bodies_(bodies), steps_(steps), timers_(timers) {
    add_pairs();
  }

  /// Contact of the problem's one pair with the rows of `builder` at each step; `step`: the
  /// number of completed steps (for messages). Chooses the method (choose_contact_method).
  void enable(ContactRowsBuilder builder, DualContactSettings settings, const int& step);
  /// Contact of every pair with the mortar pair of its two surfaces (contact::MortarPair),
  /// evaluated in the configuration of t^k at every step.
  void enable_mortar(DualContactSettings settings, contact::MortarOptions options, const int& step);
  [[nodiscard]] bool enabled() const { return method_.enforcement != nullptr; }

  /// The step k → `step` of the contact bodies from the scheme's predictor (inside
  /// BodyTimeScheme::step, which moves their states on after it); returns its heat–mechanics
  /// iterations.
  int couple(int step);

  /// Body `body` (Problem::bodies index) had A_u refactorised (E(θ), ν(θ)): the dual solver's
  /// compliance of it is formed anew. Nothing when the body is in no pair.
  void refactorised(int body);
  /// The bodies of the pairs (Problem::bodies indices).
  [[nodiscard]] const std::vector<int>& members() const { return group_.members; }
  [[nodiscard]] int n_pairs() const { return static_cast<int>(pairs_.size()); }
  [[nodiscard]] const ContactPairState& pair(int q) const { return pairs_[q]; }
  /// The first pair's mortar pair (null without one).
  [[nodiscard]] const contact::MortarPair* mortar() const {
    return pairs_.empty() ? nullptr : pairs_.front().mortar.get();
  }
  [[nodiscard]] const DualContactSolver* dual() const {
    return enabled() ? &method_.enforcement->dual() : nullptr;
  }
  [[nodiscard]] const ContactEnforcement* enforcement() const { return method_.enforcement.get(); }
  [[nodiscard]] double traction_per_multiplier() const;
  /// r += (traction per multiplier)·B_bᵀλ on body b (Problem::bodies index) from the rows and
  /// multipliers of the last step: minus the force the contact puts on the body's dofs, which
  /// the reactions of its constrained dofs must take in (EnergyBalance, issue 42 D4).
  void add_multiplier_load(int body, core::Vector& r) const;
  /// The multipliers of every pair (pair after pair), or of pair q.
  [[nodiscard]] std::vector<double> multipliers() const;
  [[nodiscard]] std::vector<double> multipliers(int q) const;
  /// B_τ Δu of the last step, every pair's rows (pair after pair), or pair q's.
  [[nodiscard]] const std::vector<double>& slip() const { return slip_; }
  [[nodiscard]] std::vector<double> slip(int q) const;
  /// The conducted heat flux per contact node of every pair (pair after pair).
  [[nodiscard]] std::vector<double> heat_flux() const;
  /// Summed over the pairs (the QP's counts are of the one QP of all pairs).
  [[nodiscard]] const ContactStatistics& statistics() const { return stats_; }
  [[nodiscard]] const ContactHeatCoupling& heat() const { return heat_; }
  [[nodiscard]] const InterfaceLaws& laws() const { return pairs_.front().laws; }
  /// The laws at the contact nodes of every pair (pair after pair).
  [[nodiscard]] const NodalLaws& nodal_laws() const { return nodal_laws_; }
  /// The contact laws checked after every step since the run (or its restart) began: the
  /// worst violations relative to their bounds (contact_laws.hpp, summary.json).
  [[nodiscard]] const ContactLaws& laws_checked() const { return laws_; }
  /// Takes in the record of a cut-back's sub-steps (their worst, counted at `step`).
  void merge_laws(const ContactLaws& sub, int step) { laws_.merge(sub, step); }
  [[nodiscard]] long total_qp_iterations() const { return total_qp_; }
  [[nodiscard]] long total_operator_applications() const { return total_applications_; }

  /// Its history.csv columns: those of its statistics and of the interface heat, summed over
  /// the pairs, and with several pairs each pair's own, suffixed by its name; with contact
  /// pairs, the resultant contact force on the slave bodies, contact_force_x|y(|z).
  void register_history(History& h) const;

  /// The contact's part of the restart record, and back.
  void save(Checkpoint& c) const;
  void restore(const Checkpoint& c);

 private:
  void add_pairs();
  void mark_loaded();  // loaded_: the contact body with a face under load control
  [[nodiscard]] BodyGroup group();
  // The contact rows of every pair in the configuration of t^k, λ of the last step moved onto
  // them, the crosspoints' multipliers held at 0.
  void set_rows(BodyGroup& g);
  void interface_laws();  // nodal_laws_ at the interface temperature of the last iterate
  // (4.3) for the contact bodies: + L_θγ θ = … + d_θγ of the current iterate of each pair.
  void heat_step(int step, int iteration);
  // The mechanical half of (6.3) with u_free fixed: coulomb_fixed_point over the enforcement's
  // QPs, then u (or B u); returns ‖λ_n(γ) − γ‖ of the last update.
  double mech_step(TrescaIteration& t, std::span<const double> targets, int step, int outer,
                   int max_updates);
  // The contact QP at one Tresca bound; with a face under load control in the group, the QPs
  // of its proximal balance, the face's w eliminated by a rank-one term (docs/theory.md).
  void solve_qp(const BodyGroup& g, const TrescaIteration& t, std::span<const double> targets,
                double rtol, int step, int outer);
  // The loaded body's u += (w − w_written)Φ (the QPs moved the face after u_free was solved).
  void shift_loaded_face(const BodyGroup& g);
  [[nodiscard]] bool any_pair(bool (InterfaceLaws::*law)() const) const;
  void sum_pair_statistics();  // the pairs' forces, counts and dissipation into stats_
  /// Entries [dim·from, dim·to) of a node-major vector (empty if it is shorter).
  static std::vector<double> nodes_of(std::span<const double> v, int dim, PetscInt from,
                                      PetscInt to);
  // −(traction per multiplier)·Σ_{dofs d of axis x}(B_sᵀλ)_d of pair q's rows and multipliers
  // `lq`: the force the master puts on the slave body, per axis.
  [[nodiscard]] std::array<double, 3> slave_force(int q, std::span<const double> lq) const;
  // λ_τ,k scaled into the cone of 𝔉_k max(λ_n,k, 0) where outside it; with `u_formed`, u_new
  // moved to the scaled multipliers (a solve per body), else recover() forms it from them.
  void scale_into_cones(const BodyGroup& g, bool u_formed);
  // The gap lengths of each mortar pair's slave nodes at u^k + τu̇^k, and the normal targets'
  // shift that linearises the gap about that configuration (set_rows).
  std::vector<std::vector<double>> predicted_gaps(const BodyGroup& g);
  void shift_to_prediction(const BodyGroup& g, const std::vector<std::vector<double>>& predicted);
  // Non-penetration and the friction cone at every contact node of u_new and λ (ContactLaws):
  // throws NumericalError beyond the solvers' bounds.
  void check_laws(const BodyGroup& g, std::span<const double> targets, int step);
  // After the staggered loop of `couple`: the cones, u recovered from λ when deferred, the laws
  // checked, the slip B_τΔu, the interface's heat of the step and the bookkeeping.
  void finish_step(const BodyGroup& g, TrescaIteration& tresca, std::span<const double> targets,
                   int step, int iteration);
  // The step's contact statistics and heat flux at u^{k+1}, θ^{k+1} of the fields.
  void bookkeeping();

  const Problem& problem_;
  Bodies& bodies_;
  BodySteps& steps_;
  core::PhaseTimers& timers_;
  ContactGroup group_;
  std::vector<ContactPairState> pairs_;
  ContactMethod method_;
  core::Vector lambda_;              // every pair's multipliers, pair after pair
  std::vector<PetscInt> lambda_at_;  // the first node of each pair in lambda_, then the total
  std::vector<double> slip_;         // B_τ Δu of the last step (node-major, normal rows unused)
  // B(u − u^k) of the current iterate while the displacements are deferred (empty: from u)
  std::vector<double> iterate_slip_;
  ContactStatistics stats_;
  std::array<double, 3> slave_force_{0, 0, 0};  // the pairs' slave_force summed
  ContactHeatCoupling heat_;
  NodalLaws nodal_laws_;          // every pair's, at the last coupling iterate
  std::vector<double> qp_bound_;  // the Tresca bounds 𝔉_kγ_k of the step's last QP
  long total_qp_ = 0, total_applications_ = 0;
  // Load control in contact: the group's body with the one face under load control (−1: none),
  // BΦ of the step's rows (rigid_coupling.hpp).
  int loaded_ = -1;
  std::vector<double> loaded_rows_;

  ContactLaws laws_;
  int step_of_last_couple_ = 0;
};

}  // namespace tc::physics
