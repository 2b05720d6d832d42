// Thermal expansion, quasistatic (verification.md "Thermo-elasticity without contact"):
// a block on rollers heated by ΔT expands by α ΔT x (by (1 + ν) α ΔT x in plane strain, where
// ε_zz = 0 holds the third axis); held between two walls in x it carries
// σ_xx = −E α ΔT (3D, other axes free) or −E α ΔT/(1 − ν) (2D plane strain), and the wall at
// xmax pushes back with that stress times the face area.
#include <gtest/gtest.h>

#include "support/problems.hpp"
#include "tc/fem/element.hpp"
#include "tc/run/simulation.hpp"

using namespace tc;

namespace {

constexpr double kDeltaT = 40.0;

physics::Problem heated_block(int dim, bool walls) {
  auto p = test::box_problem(dim, {2.0, 1.0, 0.5}, {4, 3, 2}, test::steel(),
                             physics::Scheme::quasistatic, 1.0, 1);
  p.physics.thermoelastic_heating = false;  // keeps θ uniform (no Gough–Joule cooling)
  p.bodies[0].initial_temperature = p.physics.reference_temperature + kDeltaT;
  p.boundaries.push_back(test::hold("xmin", {0}));
  p.boundaries.push_back(test::hold("ymin", {1}));
  if (dim == 3) p.boundaries.push_back(test::hold("zmin", {2}));
  if (walls) p.boundaries.push_back(test::hold("xmax", {0}));
  return p;
}

class ThermalExpansion : public ::testing::TestWithParam<int> {};

TEST_P(ThermalExpansion, FreeBlockOnRollersExpandsByAlphaDeltaTx) {
  const int dim = GetParam();
  const auto p = heated_block(dim, false);
  physics::Simulation sim(p);
  sim.advance();
  const auto& m = p.bodies[0].mesh;
  const auto u = sim.state(0).u.to_std();
  const auto& mat = p.bodies[0].material;
  // Plane strain holds z: the in-plane free strain is (1 + ν)αΔT.
  const double alpha = mat.thermal_expansion * (dim == 2 ? 1 + mat.poisson_ratio : 1.0);
  double max_err = 0, max_u = 0;
  for (int a = 0; a < m.n_nodes(); ++a)
    for (int k = 0; k < dim; ++k) {
      const double exact = alpha * kDeltaT * m.point(a)[k];
      max_err = std::max(max_err, std::abs(u[dim * a + k] - exact));
      max_u = std::max(max_u, std::abs(exact));
    }
  // A linear field is in the FE space and the solve is direct: round-off, cond(K) ~ 1e3.
  EXPECT_LT(max_err, 1e-10 * max_u);
  // Free expansion is stress free: no support reacts.
  EXPECT_LT(std::abs(sim.history("reaction_block_xmin_x")),
            1e-8 * p.bodies[0].material.young_modulus * 1e-5);
}

TEST_P(ThermalExpansion, BlockBetweenWallsCarriesTheClosedFormStress) {
  const int dim = GetParam();
  const auto p = heated_block(dim, true);
  physics::Simulation sim(p);
  sim.advance();
  const auto& mat = p.bodies[0].material;
  const double e_alpha_dt = mat.young_modulus * mat.thermal_expansion * kDeltaT;
  const double sigma = dim == 3 ? -e_alpha_dt : -e_alpha_dt / (1 - mat.poisson_ratio);
  const double area = dim == 3 ? 1.0 * 0.5 : 1.0;  // the yz face; per metre in 2D
  // Uniform stress is exact in the FE space: 1e-8 leaves room for round-off on E ~ 1e11.
  EXPECT_NEAR(sim.history("reaction_block_xmax_x"), sigma * area, 1e-8 * std::abs(sigma * area));
  EXPECT_NEAR(sim.history("reaction_block_xmin_x"), -sigma * area, 1e-8 * std::abs(sigma * area));

  const auto& m = p.bodies[0].mesh;
  const auto u = sim.state(0).u.to_std();
  Eigen::VectorXd ue(dim * 8), dte = Eigen::VectorXd::Constant(m.cell(0).size(), kDeltaT);
  ue.resize(dim * m.cell(0).size());
  for (size_t a = 0; a < m.cell(0).size(); ++a)
    for (int k = 0; k < dim; ++k) ue[dim * a + k] = u[dim * m.cell(0)[a] + k];
  const auto s = fem::cell_stress(m.cell_type(0), fem::cell_coords(m, 0), ue, dte,
                                  mat.lame_lambda(), mat.lame_mu(), mat.thermal_stress_modulus());
  EXPECT_NEAR(s(0, 0), sigma, 1e-8 * std::abs(sigma));
  EXPECT_NEAR(s(1, 1), 0.0, 1e-8 * std::abs(sigma));
}

INSTANTIATE_TEST_SUITE_P(Dimensions, ThermalExpansion, ::testing::Values(2, 3));

}  // namespace
