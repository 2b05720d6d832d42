#pragma once
// The thermal coupling of the contact pairs (2.13, §4.4): the heat step (4.3) of their bodies
// with the conductance L_θγ and the frictional heat d_θγ of each pair's current multiplier
// iterate, and the step's ledger of the heat that crossed each interface.
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/body_system.hpp"
#include "tc/physics/interface_heat/interface_heat_solver.hpp"
#include "tc/physics/interface_heat/interface_laws.hpp"
#include "tc/record/checkpoint.hpp"
#include "tc/record/ledger.hpp"

namespace tc::physics {

/// One contact pair's multipliers of the current iterate as the heat step reads them.
struct ContactIterate {
  const ContactSettings& settings;
  PairBodies bodies;                  // its slave and master in the group
  const contact::MortarPair* mortar;  // null for a test's rows: no thermal contact
  const contact::ContactRows& rows;
  std::span<const double> lambda;  // the pair's multipliers, node-major
  double unit;                     // traction per multiplier (traction_per_multiplier)
  std::span<const double> slip;    // B(u − u^k) when the displacements are deferred, or empty
  const NodalLaws& laws;           // β_C,k, δ_C,k of (2.13) at the last coupling iterate
};

class ContactHeatCoupling {
 public:
  [[nodiscard]] ConductanceTreatment treatment() const { return treatment_; }
  void set_treatment(ConductanceTreatment t) { treatment_ = t; }

  /// (4.3) for the bodies of the contact pairs at t, backward Euler:
  ///   (M_θ/τ + K_θ) θ + Σ_pairs L_θγ θ = rhs + Σ_pairs d_θγ(u̇),
  /// rhs_theta of every field holding the rest of the right-hand side on entry, θ into
  /// theta_new. Throws NumericalError when the Newton of a radiating or h(t) film boundary
  /// fails (`step`, `iteration` for the message).
  void heat_step(const Problem& p, const BodyGroup& group, std::span<const ContactIterate> pairs,
                 double t, int step, int iteration);
  /// Adds the heat of the step through each interface to its ledger, with the L and d of the
  /// last heat step (those that produced θ^{k+1}); the fields' work_theta is scratch.
  void account_step(const BodyGroup& group, double tau);

  /// The gap conductance h per contact node of pair q in the last heat step (empty: none).
  [[nodiscard]] std::span<const double> gap_conductance(size_t q) const {
    return q < gap_open_.size() ? std::span<const double>(gap_open_[q]) : std::span<const double>();
  }
  /// The heat through the interface of each pair, and summed over the pairs.
  [[nodiscard]] const std::vector<ContactHeat>& pair_heat() const { return heat_; }
  [[nodiscard]] std::vector<ContactHeat>& pair_heat() { return heat_; }
  [[nodiscard]] const ContactHeat& heat() const { return total_; }
  [[nodiscard]] const InterfaceHeatSolver* interface_heat_solver() const {
    return interface_heat_.get();
  }
  /// Newton corrections and their CG iterations of the pairs' heat steps so far.
  [[nodiscard]] long newton_iterations() const { return newton_; }
  [[nodiscard]] long newton_inner_iterations() const { return newton_inner_; }
  /// One ledger per pair, kept in place for the run (the history reads them by address).
  void set_pairs(size_t n) { heat_.resize(n); }
  /// The pairs' ledgers (from a checkpoint, one per pair); the sum follows.
  void set_pair_heat(std::span<const ContactHeat> heat);
  /// The interface heat solver's part of the restart record (its compliance, which grows with
  /// the nodes that carried conductance), and back: made and replayed for `group` if the run
  /// had one.
  void save(Checkpoint& c) const;
  void restore(const Checkpoint& c, const Problem& p, const BodyGroup& group);

 private:
  // The heat step with radiation or an h(t) film on any body of the group, or κ(θ), c_p(θ)
  // (`material_laws`: solve_nonlinear_heat).
  void group_boundary_heat(const Problem& p, const BodyGroup& group, bool implicit,
                           bool material_laws, double t, int step, int iteration);
  void sum_heat();
  // The interface heat solver of the group's bodies (Γ: every pair's contact surfaces).
  void make_interface_solver(const Problem& p, const BodyGroup& group);

  ConductanceTreatment treatment_ = ConductanceTreatment::implicit;
  std::unique_ptr<InterfaceHeatSolver> interface_heat_;
  // Per pair, of the last heat step: L_θγ (none when the pair does not conduct), d_θγ.
  std::vector<std::optional<contact::ThermalContact>> conductance_;
  std::vector<contact::FrictionalHeat> frictional_heat_;
  // Per pair with a gap conductance, of the last heat step: L_gap,ss1 and L_gap,ms1, whose dot
  // products with θ_s and θ_m are the heat through h(g) (slave → master).
  std::vector<std::optional<std::pair<core::Vector, core::Vector>>> gap_weights_;
  std::vector<std::vector<double>> gap_open_;  // h per contact node of each pair's last heat step
  std::vector<PairBodies> bodies_;             // each pair's slave and master in the group
  std::vector<ContactHeat> heat_;              // per pair
  ContactHeat total_;
  long newton_ = 0, newton_inner_ = 0;
};

}  // namespace tc::physics
