#pragma once
// The laws of the contact interface (2.13) as functions of its temperature: the friction
// coefficient 𝔉(θ) and the conductances γ_C^s(θ), γ_C^m(θ), with β_C and δ_C from them. They
// are evaluated per slave contact node at the interface temperature of the last coupling
// iterate, so they stay fixed while a Tresca QP, a Coulomb fixed point or a heat step runs
// (docs/choices.md, "Temperature-dependent interface laws").
#include <span>
#include <vector>

#include "tc/contact/contact_rows.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/interface_heat/contact_heat.hpp"

namespace tc::physics {

/// The laws at the contact nodes of one coupling iterate, in the order of the multipliers.
struct NodalLaws {
  std::vector<double> friction;  // 𝔉_k: the Tresca bound is 𝔉_k γ_k (6.3)
  std::vector<double> beta_c;    // β_C,k = γ^sγ^m/(γ^s + γ^m) (2.13)
  std::vector<double> delta_c;   // δ_C,k = γ^s/(γ^s + γ^m), ½ where both are 0
  bool frictional = false;       // of the law: 𝔉 > 0 at some temperature
  bool conducting = false;       // of the law: β_C > 0 at some temperature
};

class InterfaceLaws {
 public:
  InterfaceLaws() = default;
  explicit InterfaceLaws(const ContactSettings& c);

  [[nodiscard]] double friction(double theta) const { return friction_(theta); }
  /// β_C and δ_C of (2.13) at θ (δ_C = ½ when both conductances are 0).
  [[nodiscard]] double beta_c(double theta) const;
  [[nodiscard]] double delta_c(double theta) const;
  /// 𝔉 > 0 at some temperature.
  [[nodiscard]] bool frictional() const { return friction_.max_value() > 0; }
  /// β_C > 0 at some temperature: both conductances > 0 there.
  [[nodiscard]] bool conducting() const { return conducting_; }
  [[nodiscard]] bool friction_varies() const { return !friction_.is_constant(); }
  [[nodiscard]] bool conductance_varies() const {
    return !gamma_slave_.is_constant() || !gamma_master_.is_constant();
  }
  /// Radiation across the gap (GapConductance with both emissivities > 0): its conductance
  /// depends on the faces' temperatures, so the fixed point iterates θ.
  [[nodiscard]] bool gap_radiates() const { return radiates_; }

  /// The laws at the temperatures θ_k of the contact nodes.
  [[nodiscard]] NodalLaws at(std::span<const double> theta) const;
  /// The laws at the contact nodes of `rows`, at the interface temperature of θ_s, θ_m
  /// (interface_temperature; only computed when a law depends on θ, which needs the mortar
  /// pair: throws Error without it).
  [[nodiscard]] NodalLaws at_interface(const contact::MortarPair* mortar,
                                       const contact::ContactRows& rows,
                                       const core::Vector& theta_slave,
                                       const core::Vector& theta_master) const;

 private:
  [[nodiscard]] bool conducts_somewhere() const;

  core::TemperatureTable friction_, gamma_slave_, gamma_master_;
  bool conducting_ = false;  // conducts_somewhere(), fixed with the tables
  bool radiates_ = false;
};

/// θ_Γ,k = ½(θ_s,k + θ_m,k) at contact node k: θ_s at the slave node, θ_m =
/// (Mθ_m)_k/(D1)_k; θ_s alone where the master does not cover the node ((D1)_k ≤ 0).
[[nodiscard]] std::vector<double> interface_temperature(const contact::MortarPair& mortar,
                                                        const core::Vector& theta_slave,
                                                        const core::Vector& theta_master);

}  // namespace tc::physics
