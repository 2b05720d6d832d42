#pragma once
// Material constants of one body (case-format.md [materials.*]) and the moduli derived
// from them (thesis 2.5, 2.8; docs/choices.md for the thermal stress modulus β), with the
// properties the case gives as tables in θ (docs/theory.md, "Temperature-dependent materials").
#include "tc/core/table.hpp"

namespace tc::fem {

/// The properties given as tables in the body's temperature θ. A law that is constant (the
/// default, or a flat table: core::TemperatureTable) is not used: the number in Material is
/// the property, and the run takes the constant-property code path bit for bit.
struct MaterialLaws {
  core::TemperatureTable thermal_conductivity;  // κ(θ) [W/(m K)]
  core::TemperatureTable specific_heat;         // c_p(θ) [J/(kg K)]
  /// α(θ) [1/K], the instantaneous (tangent) coefficient dε/dθ; the strain is its integral
  /// from θ₀ (docs/choices.md, "Thermal expansion as a table").
  core::TemperatureTable thermal_expansion;
  /// E(θ) [Pa] and ν(θ): the moduli of σ = C(θ)(ε − ε_th(θ)), per cell at the cell's mean
  /// nodal temperature, lagged to the step start (docs/choices.md, "E(θ), ν(θ)").
  core::TemperatureTable young_modulus;
  core::TemperatureTable poisson_ratio;
};

/// λ and μ of (E, ν) (thesis 2.5).
[[nodiscard]] inline double lame_lambda(double e, double nu) {
  return e * nu / ((1 + nu) * (1 - 2 * nu));
}
[[nodiscard]] inline double lame_mu(double e, double nu) {
  return e / (2 * (1 + nu));
}

struct Material {
  // When a property is a table (`laws`), its number here is the table at the body's initial
  // temperature: what the constant matrices (and the preconditioner of the heat step's Newton)
  // are assembled with.
  double density = 0;               // ρ [kg/m³]
  double young_modulus = 0;         // E [Pa]
  double poisson_ratio = 0;         // ν
  double thermal_expansion = 0;     // α [1/K]
  double specific_heat = 0;         // c_p [J/(kg K)]
  double thermal_conductivity = 0;  // κ [W/(m K)]
  MaterialLaws laws;

  [[nodiscard]] double lame_lambda() const {
    return fem::lame_lambda(young_modulus, poisson_ratio);
  }
  [[nodiscard]] double lame_mu() const { return fem::lame_mu(young_modulus, poisson_ratio); }
  /// β = (3λ + 2μ)α = 3Kα of the 3D material: the thesis' dKα in 3D. In 2D plane strain the
  /// material stays 3D, so β keeps this value (not 2(λ+μ)α): docs/choices.md.
  [[nodiscard]] double thermal_stress_modulus() const {
    return (3 * lame_lambda() + 2 * lame_mu()) * thermal_expansion;
  }
  /// c of (2.8) = ρ c_p [J/(m³ K)] (docs/choices.md).
  [[nodiscard]] double heat_capacity() const { return density * specific_heat; }
  /// κ or c_p depends on θ: the heat step is nonlinear (fem::NonlinearHeat).
  [[nodiscard]] bool nonlinear_heat() const {
    return !laws.thermal_conductivity.is_constant() || !laws.specific_heat.is_constant();
  }
  /// α depends on θ: the thermal strain is ∫_{θ₀}^{θ} α dθ, not α(θ − θ₀).
  [[nodiscard]] bool nonlinear_expansion() const { return !laws.thermal_expansion.is_constant(); }
  /// E or ν depends on θ: K_u and K_uθ are re-assembled (and A_u refactorised) when the
  /// temperature moved them beyond [solver] modulus_tolerance (physics::BodySystem).
  [[nodiscard]] bool nonlinear_moduli() const {
    return !laws.young_modulus.is_constant() || !laws.poisson_ratio.is_constant();
  }
  /// E(θ), ν(θ): the law, or the number when it is constant.
  [[nodiscard]] double young_modulus_at(double theta) const {
    return laws.young_modulus.is_constant() ? young_modulus : laws.young_modulus(theta);
  }
  [[nodiscard]] double poisson_ratio_at(double theta) const {
    return laws.poisson_ratio.is_constant() ? poisson_ratio : laws.poisson_ratio(theta);
  }
  /// ϑ_α(θ) with α ϑ_α = ε_th(θ) = ∫_{θ₀}^{θ} α(s) ds, α the number: the temperature change
  /// that K_uθ (assembled with α) turns into the thermal strain of the law; θ − θ₀ for a
  /// constant α, where the secant α_s(θ) = ε_th(θ)/(θ − θ₀) is α itself.
  [[nodiscard]] double expansion_deviation(double theta, double theta0) const {
    if (!nonlinear_expansion()) return theta - theta0;
    return laws.thermal_expansion.integral(theta0, theta) / thermal_expansion;
  }
  /// dϑ_α/dθ = α(θ)/α: the factor of the thermoelastic heating at θ (docs/theory.md).
  [[nodiscard]] double expansion_rate(double theta) const {
    return nonlinear_expansion() ? laws.thermal_expansion(theta) / thermal_expansion : 1.0;
  }
  /// Sets the numbers of the table laws: κ, c_p, E and ν at θ (the body's initial temperature:
  /// the heat operator factorised with them is the Newton's preconditioner, the mechanical
  /// operator the first factorisation), α at its largest
  /// value (the modulus K_uθ is assembled with; the secant strain rescales it, and a table
  /// with α = 0 at θ would make the rescaling 0/0).
  void evaluate_laws_at(double theta) {
    if (!laws.thermal_conductivity.is_constant())
      thermal_conductivity = laws.thermal_conductivity(theta);
    if (!laws.specific_heat.is_constant()) specific_heat = laws.specific_heat(theta);
    if (!laws.thermal_expansion.is_constant())
      thermal_expansion = laws.thermal_expansion.max_value();
    if (!laws.young_modulus.is_constant()) young_modulus = laws.young_modulus(theta);
    if (!laws.poisson_ratio.is_constant()) poisson_ratio = laws.poisson_ratio(theta);
  }
};

}  // namespace tc::fem
