#pragma once
// Pieces of case files that tests write inline (docs/case-format.md).

namespace tc::test {

/// The steel of the small inline cases: [materials.steel] with every key a thermo-mechanical
/// case needs (SI units).
inline constexpr const char* kSteelToml = R"([materials.steel]
density = 7850.0
young_modulus = 2.0e11
poisson_ratio = 0.3
thermal_expansion = 1.2e-5
specific_heat = 450.0
thermal_conductivity = 50.0
)";

}  // namespace tc::test
