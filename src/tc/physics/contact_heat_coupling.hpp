#pragma once
// The thermal coupling of the contact pair (2.13, §4.4): the heat step (4.3) of the two bodies
// with the conductance L_θγ and the frictional heat d_θγ of the current multiplier iterate, and
// the step's ledger of the heat that crossed the interface.
#include <memory>
#include <optional>
#include <span>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/physics/bodies.hpp"
#include "tc/physics/body_field.hpp"
#include "tc/physics/body_system.hpp"
#include "tc/physics/interface_laws.hpp"
#include "tc/physics/ledger.hpp"
#include "tc/physics/problem.hpp"
#include "tc/physics/thermal_contact.hpp"

namespace tc::physics {

/// The two bodies of the contact pair in the heat step.
using HeatPair = BodyPair;

/// The multipliers of the current iterate as the heat step reads them.
struct ContactIterate {
  const contact::MortarPair* mortar;  // null for a test's rows: no thermal contact
  const contact::ContactRows& rows;
  const core::Vector& lambda;
  double unit;                   // traction per multiplier (traction_per_multiplier)
  std::span<const double> slip;  // B(u − u^k) when the displacements are deferred, or empty
  const NodalLaws& laws;         // β_C,k, δ_C,k of (2.13) at the last coupling iterate
};

class ContactHeatCoupling {
 public:
  [[nodiscard]] ConductanceTreatment treatment() const { return treatment_; }
  void set_treatment(ConductanceTreatment t) { treatment_ = t; }

  /// (4.3) for the two bodies of the contact pair at t, backward Euler:
  ///   (M_θ/τ + K_θ) θ + L_θγ θ = rhs + d_θγ(u̇),
  /// rhs_theta of both fields holding the rest of the right-hand side on entry, θ into
  /// theta_new. Throws NumericalError when the Newton of a radiating or h(t) film boundary
  /// fails (`step`, `iteration` for the message).
  void heat_step(const Problem& p, const HeatPair& pair, const ContactIterate& it, double t,
                 int step, int iteration);
  /// Adds the heat of the step through the interface to the ledger, with the L and d of the
  /// last heat step (those that produced θ^{k+1}); the slave's work_theta is scratch.
  void account_step(const HeatPair& pair, double tau);

  [[nodiscard]] const ContactHeat& heat() const { return heat_; }
  [[nodiscard]] ContactHeat& heat() { return heat_; }
  [[nodiscard]] const InterfaceHeatSolver* interface_heat_solver() const {
    return interface_heat_.get();
  }
  /// Newton corrections and their CG iterations of the pair's heat steps so far.
  [[nodiscard]] long newton_iterations() const { return newton_; }
  [[nodiscard]] long newton_inner_iterations() const { return newton_inner_; }

 private:
  // The pair's heat step with radiation or an h(t) film on either body.
  void pair_boundary_heat(const Problem& p, const HeatPair& pair, bool implicit, double t, int step,
                          int iteration);

  ConductanceTreatment treatment_ = ConductanceTreatment::implicit;
  std::unique_ptr<InterfaceHeatSolver> interface_heat_;
  std::optional<contact::ThermalContact> conductance_;  // L_θγ of the last heat step
  contact::FrictionalHeat frictional_heat_;             // d_θγ of the last heat step
  ContactHeat heat_;
  long newton_ = 0, newton_inner_ = 0;
};

}  // namespace tc::physics
