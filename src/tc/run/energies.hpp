#pragma once
// What the energy balance of the bodies reads (history.csv): the discrete energies of the
// current state and the support reactions, whose work is the external work (EnergyBalance).
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/model/problem.hpp"
#include "tc/physics/body/bodies.hpp"
#include "tc/record/history.hpp"

namespace tc::physics {

class ContactCoupling;

/// ½ u̇ᵀM_u u̇ summed over the bodies (0 quasistatic) [J, or J/m in 2D].
[[nodiscard]] double kinetic_energy(const Problem& p, const Bodies& bodies);
/// ½ uᵀK_u u summed over the bodies.
[[nodiscard]] double strain_energy(const Bodies& bodies);
/// Σ ∫ ρ c_p (θ − θ₀) dx.
[[nodiscard]] double thermal_energy(const Problem& p, const Bodies& bodies);
/// (1/2θ₀)(θ−θ₀)ᵀ M_θ (θ−θ₀): the thermal part of the thermo-elastic Lyapunov function.
[[nodiscard]] double thermal_free_energy(const Problem& p, const Bodies& bodies);
/// The largest (or smallest) temperature of all bodies.
[[nodiscard]] double extreme_temperature(const Bodies& bodies, bool largest);

/// F = f_ext + R of body b at time t into r, R = M ü + K u + K_uθ(θ − θ₀) − f_ext + B_bᵀλ on
/// the constrained dofs: the force the supports exert on the body, which with f_ext does the
/// external work. B_bᵀλ is minus the contact force on the body (`contact`'s last step; none
/// when null): a supported node on a contact surface passes it to its support, so that the
/// reactions balance every applied and contact force (issue 42 D4). The body's f_u is
/// scratch.
void support_forces(const Problem& p, const Bodies& bodies, int b, double t, core::Vector& r,
                    const ContactCoupling* contact = nullptr);

/// The energy balance of the bodies: the support forces F^k of every body and the external work
/// W = Σ_steps ½(F^k + F^{k+1})·(u^{k+1} − u^k), with the energies of the state (history.csv).
class EnergyBalance {
 public:
  /// `contact`: the contact pairs' coupling whose multipliers load the supports (may be null).
  EnergyBalance(const Problem& p, const Bodies& bodies, const ContactCoupling* contact = nullptr)
      : problem_(p), bodies_(bodies), contact_(contact) {}

  /// F⁰ of every body, once the initial states are set.
  void start(double t);
  /// Adds the external work of the step from `old_u` (u^k per body) to the states' u^{k+1},
  /// and takes the support forces of t^{k+1}.
  void account_step(const std::vector<core::Vector>& old_u, double t);
  /// Its history.csv columns: the energies, external_work, max_/min_temperature, and the force
  /// on each reaction group per axis (reaction_<body>_<where>_x|y|z).
  void register_history(History& h) const;

  /// F = f_ext + R of body b at the current step (checkpoint).
  [[nodiscard]] const core::Vector& force(int b) const { return forces_[b]; }
  [[nodiscard]] core::Vector& force(int b) { return forces_[b]; }
  [[nodiscard]] double external_work() const { return external_work_; }
  void set_external_work(double w) { external_work_ = w; }

 private:
  const Problem& problem_;
  const Bodies& bodies_;
  const ContactCoupling* contact_;
  std::vector<core::Vector> forces_;  // f_ext + reactions at the current step, per body
  double external_work_ = 0;
};

}  // namespace tc::physics
