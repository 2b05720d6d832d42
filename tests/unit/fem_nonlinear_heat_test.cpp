// fem::NonlinearHeat, the heat step's material part with κ(θ), c_p(θ), against independent
// computations:
//  - the Jacobian product N'(θ)x against central differences of N(θ): with θ inside one
//    segment of each table, c_p and κ are linear there, so N is a quadratic polynomial of θ
//    and the central difference is exact up to round-off (‖N‖ ~ 1e3 ‖N'x‖ here, 1e-15 of
//    ‖N‖ per evaluation: ~1e-12 of ‖N'x‖, asserted to 1e-9; a missing or wrong term, the κ'
//    one say, misses by O(0.1));
//  - Σ H_a of a uniform temperature equals V ρ∫_{θ₀}^{θ} c_p dθ by hand, consistent and
//    lumped (1e-13: a sum of a few hundred positive terms);
//  - N at constant laws: the material part of a constant-property step is −M_θθ₀/τ (H(θ) =
//    M_θ(θ − θ₀) and C(θ) = K_θθ), checked with the assembled M_θ (1e-12 of ‖M_θθ₀/τ‖).
#include <gtest/gtest.h>

#include <cmath>

#include "tc/fem/assembler.hpp"
#include "tc/fem/nonlinear_heat.hpp"
#include "tc/mesh/box.hpp"

using namespace tc;

namespace {

constexpr double kTheta0 = 293.15, kInvTau = 10.0;

fem::Material material(core::TemperatureTable kappa, core::TemperatureTable cp) {
  fem::Material m;
  m.density = 7850;
  m.young_modulus = 2e11;
  m.poisson_ratio = 0.3;
  m.specific_heat = 450;
  m.thermal_conductivity = 50;
  m.laws.thermal_conductivity = std::move(kappa);
  m.laws.specific_heat = std::move(cp);
  return m;
}

// base + amplitude · a smooth non-polynomial variation over the box.
core::Vector field(const mesh::Mesh& m, double base, double amplitude) {
  core::Vector v(m.n_nodes());
  auto w = v.view();
  for (int a = 0; a < m.n_nodes(); ++a) {
    const auto& x = m.point(a);
    w[a] = base + amplitude * std::sin(7.0 * x[0] + 3.0 * x[1] + 5.0 * x[2]);
  }
  return v;
}

TEST(NonlinearHeat, JacobianProductIsTheDerivativeOfTheResidual) {
  const core::TemperatureTable kappa({250.0, 400.0, 600.0}, {70.0, 40.0, 30.0});
  const core::TemperatureTable cp({250.0, 400.0, 600.0}, {400.0, 600.0, 700.0});
  for (const int dim : {2, 3})
    for (const bool lumped : {false, true}) {
      const auto m = mesh::make_box(dim, {0, 0, 0}, {0.3, 0.2, 0.1}, {3, 2, 2});
      const fem::NonlinearHeat heat(m, material(kappa, cp), kTheta0, lumped);
      const auto theta = field(m, 330.0, 25.0);  // 305–355 K, in (250, 400) K
      const auto x = field(m, 0.3, 1.0);         // a direction, varying too
      core::Vector jx(m.n_nodes()), plus(m.n_nodes()), minus(m.n_nodes());
      heat.add_nonlinear_derivative(theta, x, kInvTau, jx);
      const double h = 1.0;  // K: N is quadratic in θ here, so any step is exact
      auto tp = theta.clone(), tm = theta.clone();
      tp.axpy(h, x);
      tm.axpy(-h, x);
      heat.add_nonlinear_part(tp, kInvTau, plus);
      heat.add_nonlinear_part(tm, kInvTau, minus);
      plus.axpy(-1.0, minus);
      plus.scale(0.5 / h);
      plus.axpy(-1.0, jx);
      EXPECT_LT(plus.norm(), 1e-9 * jx.norm())
          << "dim " << dim << (lumped ? " lumped" : " consistent") << ": |J x| = " << jx.norm();
      EXPECT_GT(jx.norm(), 0.0);
    }
}

TEST(NonlinearHeat, TotalEnthalpyOfAUniformTemperatureIsTheIntegralOfTheSpecificHeat) {
  // c_p: 400 at 300 K, 600 at 400 K, 650 at 700 K; ∫_{θ₀}^{500} by hand: 400·6.85 (constant
  // below 300 K) + ½(400 + 600)·100 + ½(600 + 616.667)·100.
  const core::TemperatureTable cp({300.0, 400.0, 700.0}, {400.0, 600.0, 650.0});
  const double c500 = 600.0 + 50.0 / 3.0;
  const double integral =
      400.0 * (300.0 - kTheta0) + 0.5 * (400.0 + 600.0) * 100.0 + 0.5 * (600.0 + c500) * 100.0;
  for (const bool lumped : {false, true}) {
    const auto m = mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {3, 2, 2});
    const fem::NonlinearHeat heat(m, material(50.0, cp), kTheta0, lumped);
    core::Vector theta(m.n_nodes());
    theta.fill(500.0);
    const double volume = 0.3 * 0.2 * 0.1;
    const double expected = volume * 7850 * integral;
    EXPECT_NEAR(heat.total_enthalpy(theta), expected, 1e-13 * expected);
    EXPECT_NEAR(heat.enthalpy_density(500.0), 7850 * integral, 1e-13 * 7850 * integral);
  }
}

TEST(NonlinearHeat, AtTheReferencePropertiesTheMaterialPartIsTheConstantStepsShift) {
  // Tables whose values are the reference numbers between the field and θ₀ (the field stays
  // below 260 K, θ₀ = 293.15 K, both tables constant at their first value = the number below
  // 300 K): then h(θ) = ρc_ref(θ − θ₀) and N(θ) = H(θ)/τ − M_θθ/τ + C(θ) − K_θθ = −M_θθ₀1/τ
  // exactly in exact arithmetic.
  const core::TemperatureTable kappa({300.0, 400.0}, {50.0, 80.0});
  const core::TemperatureTable cp({300.0, 400.0}, {450.0, 900.0});
  const auto m = mesh::make_box(2, {0, 0, 0}, {0.3, 0.2, 0}, {3, 2, 1});
  const auto mat = material(kappa, cp);
  const fem::NonlinearHeat heat(m, mat, kTheta0, false);
  core::Vector theta(m.n_nodes());
  {
    auto w = theta.view();
    for (int a = 0; a < m.n_nodes(); ++a) w[a] = 250.0 + 20.0 * m.point(a)[0];
  }
  core::Vector n(m.n_nodes());
  heat.add_nonlinear_part(theta, kInvTau, n);
  const auto mats = fem::assemble_body(m, mat);
  core::Vector ones(m.n_nodes()), shift(m.n_nodes());
  ones.fill(kTheta0 * kInvTau);
  mats.mass_theta.mult(ones, shift);  // M_θθ₀1/τ
  n.axpy(1.0, shift);
  EXPECT_LT(n.norm(), 1e-12 * shift.norm());
}

}  // namespace
