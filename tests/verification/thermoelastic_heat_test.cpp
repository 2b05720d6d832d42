// The thermoelastic term's heat summed over a run (2.8, 5.6). An insulated steel bar, held at
// one end and pulled at the other from rest at 1 m/s (a jump of velocity: Newmark then rings,
// without damping). Conduction moves heat but 1ᵀK_θ = 0, so summing the heat step over the nodes
// leaves 1ᵀM_θ(θ^{k+1} − θ^k) = θ₀ 1ᵀK_uθᵀ(u^{k+1} − u^k) with the default rate (u^{k+1} − u^k)/τ:
// the body's thermal energy is −θ₀β∫tr(ε) dV at every step, β = Eα/(1 − 2ν) (the adiabatic
// Gough–Joule cooling of a stretched bar), whatever the velocities did. ∫tr(ε) dV = ∮u·n dS is
// computed here from the boundary displacements alone (exact for trilinear u on the box faces),
// independently of K_uθ. With Newmark's u̇^{k+1} as (5.6) writes it the identity holds only on
// average over two steps: the ringing adds a heat that alternates in sign.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/body_energy.hpp"
#include "support/problems.hpp"

namespace tc::test {
namespace {

constexpr double kTheta0 = 293.15;
constexpr double kLength = 0.1, kSide = 0.02;
constexpr int kCells[3] = {10, 2, 2};

/// ∮u·n dS over the faces of the box [0, L] × [0, a]², trapezoidal weights of its grid.
double boundary_flux(const physics::Simulation& sim) {
  const auto& mesh = sim.system(0).body().mesh;
  const auto u = sim.state(0).u.to_std();
  const double size[3] = {kLength, kSide, kSide};
  double flux = 0;
  for (int a = 0; a < mesh.n_nodes(); ++a) {
    const auto& x = mesh.point(a);
    for (int d = 0; d < 3; ++d) {
      const bool lo = std::abs(x[d]) < 1e-12, hi = std::abs(x[d] - size[d]) < 1e-12;
      if (!lo && !hi) continue;
      double w = 1;  // the node's share of the face: h per direction, halved on its edges
      for (int e = 0; e < 3; ++e) {
        if (e == d) continue;
        const double h = size[e] / kCells[e];
        const bool edge = std::abs(x[e]) < 1e-12 || std::abs(x[e] - size[e]) < 1e-12;
        w *= edge ? h / 2 : h;
      }
      flux += (hi ? 1.0 : -1.0) * w * u[static_cast<size_t>(3 * a + d)];
    }
  }
  return flux;
}

/// The largest |E_θ + θ₀β∮u·n| over the steps, relative to the largest |θ₀β∮u·n|.
double worst_mismatch(physics::ThermoelasticRate rate) {
  const auto mat = steel();
  const double tau = 2e-6;  // a wave crosses the bar in 20 µs: ten steps, the ringing unresolved
  const int n_steps = 30;
  auto p = box_problem(3, {kLength, kSide, kSide}, {kCells[0], kCells[1], kCells[2]}, mat,
                       physics::Scheme::dynamic, tau, n_steps);
  p.physics.thermoelastic_rate = rate;
  p.boundaries.push_back(hold("xmin", {0, 1, 2}));
  const double v = 1.0;  // m/s from t = 0: a jump of velocity
  p.boundaries.push_back(displacement_bc(
      0, "xmax", {{0, core::TimeTable({0.0, tau * n_steps}, {0.0, v * tau * n_steps})}}));
  physics::Simulation sim(p);
  const double beta = mat.young_modulus * mat.thermal_expansion / (1 - 2 * mat.poisson_ratio);
  const double e0 = body_energy(sim, 0, kTheta0);
  double worst = 0, scale = 0;
  for (int k = 0; k < n_steps; ++k) {
    sim.advance();
    const double expected = -kTheta0 * beta * boundary_flux(sim);
    worst = std::max(worst, std::abs(body_energy(sim, 0, kTheta0) - e0 - expected));
    scale = std::max(scale, std::abs(expected));
  }
  EXPECT_GT(scale, 0.0);
  return worst / scale;
}

TEST(ThermoelasticHeat, TheBodysHeatIsTheStrainsWorkAtEveryStep) {
  const double mean = worst_mismatch(physics::ThermoelasticRate::step_mean);
  const double newmark = worst_mismatch(physics::ThermoelasticRate::newmark);
  std::printf("worst |E_θ + θ₀β∮u·n| / max|θ₀β∮u·n|: step mean %.3e, Newmark %.3e\n", mean,
              newmark);
  // The identity is exact in exact arithmetic once the staggered loop has converged; the loop
  // stops at coupling_tolerance = 1e-6 of ‖u‖ and ‖θ‖: 1e-5 is ten times that.
  EXPECT_LT(mean, 1e-5);
  // Newmark's rate misses it by the ringing's share of the strain rate, of order one.
  EXPECT_GT(newmark, 1e-2);
}

}  // namespace
}  // namespace tc::test
