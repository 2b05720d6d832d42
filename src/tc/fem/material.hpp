#pragma once
// Material constants of one body (case-format.md [materials.*]) and the moduli derived
// from them (thesis 2.5, 2.8; docs/choices.md for the thermal stress modulus β).
namespace tc::fem {

struct Material {
  double density = 0;               // ρ [kg/m³]
  double young_modulus = 0;         // E [Pa]
  double poisson_ratio = 0;         // ν
  double thermal_expansion = 0;     // α [1/K]
  double specific_heat = 0;         // c_p [J/(kg K)]
  double thermal_conductivity = 0;  // κ [W/(m K)]

  [[nodiscard]] double lame_lambda() const {
    return young_modulus * poisson_ratio / ((1 + poisson_ratio) * (1 - 2 * poisson_ratio));
  }
  [[nodiscard]] double lame_mu() const { return young_modulus / (2 * (1 + poisson_ratio)); }
  /// β = (3λ + 2μ)α = 3Kα of the 3D material: the thesis' dKα in 3D. In 2D plane strain the
  /// material stays 3D, so β keeps this value (not 2(λ+μ)α): docs/choices.md.
  [[nodiscard]] double thermal_stress_modulus() const {
    return (3 * lame_lambda() + 2 * lame_mu()) * thermal_expansion;
  }
  /// c of (2.8) = ρ c_p [J/(m³ K)] (docs/choices.md).
  [[nodiscard]] double heat_capacity() const { return density * specific_heat; }
};

}  // namespace tc::fem
