#pragma once
// The step of the contact pair (6.3): the staggered fixed point between the pair's heat step
// (ContactHeatCoupling: L_θγ, d_θγ) and its mechanical step, whose contact is enforced by a
// ContactEnforcement inside the Tresca → Coulomb fixed point (coulomb_fixed_point), with the
// ContactTimeScheme of the run around it; the multipliers carried from step to step
// (MultiplierTransfer) and what the contact reports (ContactStatistics, heat flux).
#include <memory>
#include <span>
#include <vector>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/timer.hpp"
#include "tc/physics/bodies.hpp"
#include "tc/physics/body_steps.hpp"
#include "tc/physics/checkpoint.hpp"
#include "tc/physics/contact_heat_coupling.hpp"
#include "tc/physics/contact_method.hpp"
#include "tc/physics/finite_checks.hpp"
#include "tc/physics/friction_fixed_point.hpp"
#include "tc/physics/interface_laws.hpp"
#include "tc/physics/ledger.hpp"
#include "tc/physics/multiplier_transfer.hpp"

namespace tc::physics {

class ContactCoupling {
 public:
  ContactCoupling(const Problem& problem, Bodies& bodies, BodySteps& steps,
                  core::PhaseTimers& timers)
      : problem_(problem), bodies_(bodies), steps_(steps), timers_(timers) {}

  /// Contact of problem.contact with the rows of `builder` at each step; `step`: the number
  /// of completed steps (for messages). Chooses the method (choose_contact_method).
  void enable(ContactRowsBuilder builder, DualContactSettings settings, const int& step);
  /// The same with the mortar pair of the contact's two surfaces (contact::MortarPair),
  /// evaluated in the configuration of t^k at every step.
  void enable_mortar(DualContactSettings settings, contact::MortarOptions options, const int& step);
  [[nodiscard]] bool enabled() const { return method_.enforcement != nullptr; }

  /// The step k → `step` of the pair; returns its heat–mechanics iterations.
  int couple(int step);
  /// The step's contact statistics and heat flux, from the state after couple().
  void bookkeeping();

  [[nodiscard]] const contact::MortarPair* mortar() const { return mortar_.get(); }
  [[nodiscard]] const DualContactSolver* dual() const {
    return enabled() ? &method_.enforcement->dual() : nullptr;
  }
  [[nodiscard]] const ContactEnforcement* enforcement() const { return method_.enforcement.get(); }
  [[nodiscard]] double traction_per_multiplier() const;
  [[nodiscard]] std::vector<double> multipliers() const;
  [[nodiscard]] const std::vector<double>& slip() const { return slip_; }
  [[nodiscard]] const std::vector<double>& heat_flux() const { return heat_flux_; }
  [[nodiscard]] const ContactStatistics& statistics() const { return stats_; }
  [[nodiscard]] const ContactHeatCoupling& heat() const { return heat_; }
  [[nodiscard]] const InterfaceLaws& laws() const { return laws_; }
  [[nodiscard]] const NodalLaws& nodal_laws() const { return nodal_laws_; }
  [[nodiscard]] long total_qp_iterations() const { return total_qp_; }
  [[nodiscard]] long total_operator_applications() const { return total_applications_; }

  /// Its history.csv columns: those of its statistics and of the interface heat.
  void register_history(History& h) const {
    stats_.register_history(h);
    heat_.heat().register_history(h);
  }

  /// The contact's part of the restart record, and back.
  void save(Checkpoint& c) const;
  void restore(const Checkpoint& c);

 private:
  [[nodiscard]] BodyPair pair();
  // (4.3) for the pair: + L_θγ θ = … + d_θγ of the current iterate (ContactHeatCoupling).
  void heat_step(int step, int iteration);
  // The mechanical half of (6.3) with u_free fixed: coulomb_fixed_point over the enforcement's
  // QPs, then u (or B u); returns ‖λ_n(γ) − γ‖ of the last update.
  double mech_step(TrescaIteration& t, std::span<const double> targets, int step, int outer,
                   int max_updates);

  const Problem& problem_;
  Bodies& bodies_;
  BodySteps& steps_;
  core::PhaseTimers& timers_;
  ContactRowsBuilder rows_;
  std::unique_ptr<contact::MortarPair> mortar_;
  ContactMethod method_;
  core::Vector lambda_;
  MultiplierTransfer transfer_;  // what lambda_ refers to, for the next step's warm start
  std::vector<double> slip_;     // B_τ Δu of the last step (node-major, normal rows unused)
  // B(u − u^k) of the current iterate while the displacements are deferred (empty: from u)
  std::vector<double> iterate_slip_;
  ContactStatistics stats_;
  ContactHeatCoupling heat_;
  InterfaceLaws laws_;            // the contact's 𝔉(θ), γ_C(θ)
  NodalLaws nodal_laws_;          // …at the contact nodes of the last coupling iterate
  std::vector<double> qp_bound_;  // the Tresca bounds 𝔉_kγ_k of the step's last QP
  std::vector<double> heat_flux_;
  long total_qp_ = 0, total_applications_ = 0;
};

}  // namespace tc::physics
