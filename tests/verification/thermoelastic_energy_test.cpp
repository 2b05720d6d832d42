// Thermo-elastic coupling (2.5 with 2.8): for an insulated, unloaded body the functional
// E = ½u̇ᵀM_u u̇ + ½uᵀK_u u + (1/2θ₀)(θ−θ₀)ᵀM_θ(θ−θ₀) is non-increasing in the continuous
// problem (dE/dt = −(1/θ₀)(θ−θ₀)ᵀK_θ(θ−θ₀)). The body starts hot and free: it expands and rings.
//
// Discretely, with the thermoelastic term at the step's mean rate (u^{k+1} − u^k)/τ (the
// default) the two coupling terms cancel exactly in E: Newmark's energy identity gives
// ΔE_mech = −Δuᵀ K_uθ(θ̄ − θ₀), θ̄ = (θ^k + θ^{k+1})/2, and backward Euler's heat step gives
// Δ[(1/2θ₀)(θ−θ₀)ᵀM_θ(θ−θ₀)] = (θ̄ − θ₀)ᵀ K_uθᵀ Δu − (τ/θ₀)(θ̄ − θ₀)ᵀK_θ(θ^{k+1} − θ₀), so
// E^{k+1} − E^k = −(τ/θ₀)(θ̄ − θ₀)ᵀK_θ(θ^{k+1} − θ₀): conserved without conduction, decreasing
// by exactly that with it. With Newmark's u̇^{k+1} in the term, as (5.6) writes it, the
// cancellation is lost and E drifts by O(τ) (docs/choices.md, "The thermoelastic term at the
// step's mean rate").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "support/problems.hpp"
#include "tc/run/simulation.hpp"

using namespace tc;

namespace {

physics::Problem hot_block(double step, int n_steps, double conductivity,
                           physics::ThermoelasticRate rate) {
  auto mat = test::steel();
  // A strongly coupled material (δ = θ₀β²/(ρc_p(λ+2μ)) ≈ 0.8) so the coupling terms matter.
  mat.thermal_expansion = 1e-4;
  mat.thermal_conductivity = conductivity;
  auto p = test::box_problem(3, {0.02, 0.01, 0.01}, {4, 2, 2}, mat, physics::Scheme::dynamic, step,
                             n_steps);
  p.solver.coupling_tolerance = 1e-13;  // iterate the staggered scheme to its fixed point
  p.solver.max_coupling_iterations = 100;
  p.bodies[0].initial_temperature = p.physics.reference_temperature + 1.0;
  p.physics.thermoelastic_rate = rate;
  return p;
}

double lyapunov(const physics::Simulation& s) {
  return s.kinetic_energy() + s.strain_energy() + s.thermal_free_energy();
}

/// (τ/θ₀)(θ̄ − θ₀)ᵀK_θ(θ^{k+1} − θ₀): what conduction takes from E in the step from θ^k.
double conduction_loss(const physics::Simulation& s, const core::Vector& theta_k) {
  const double theta0 = s.problem().physics.reference_temperature;
  auto next = s.state(0).theta.clone();  // θ^{k+1} − θ₀
  next.shift(-theta0);
  auto mean = theta_k.clone();  // θ̄ − θ₀
  mean.axpy(1.0, s.state(0).theta);
  mean.scale(0.5);
  mean.shift(-theta0);
  auto work = next.duplicate();
  s.system(0).matrices().stiffness_theta.mult(next, work);
  return s.problem().time.step / theta0 * mean.dot(work);
}

struct Excursion {
  double growth = 0;    // largest (E − E(0))/E(0)
  double drift = 0;     // largest |E − E(0)|/E(0)
  double identity = 0;  // largest |E^{k+1} − E^k + conduction_loss|/E(0)
  double final_ratio = 1;
};

Excursion excursion(double tau, double t_end, double conductivity,
                    physics::ThermoelasticRate rate = physics::ThermoelasticRate::step_mean) {
  const int n = static_cast<int>(std::lround(t_end / tau));
  physics::Simulation sim(hot_block(tau, n, conductivity, rate));
  const double e0 = lyapunov(sim);
  Excursion out;
  double e = e0;
  for (int s = 0; s < n; ++s) {
    const auto theta_k = sim.state(0).theta.clone();
    sim.advance();
    const double next = lyapunov(sim);
    out.identity = std::max(out.identity, std::abs(next - e + conduction_loss(sim, theta_k)) / e0);
    e = next;
    const double rel = (e - e0) / e0;
    out.growth = std::max(out.growth, rel);
    out.drift = std::max(out.drift, std::abs(rel));
  }
  out.final_ratio = e / e0;
  return out;
}

TEST(ThermoelasticEnergy, ConservedWithoutConduction) {
  const double t_end = 1e-5;  // a few periods of the lowest mode (c ≈ 5 km/s, L = 2 cm)
  const auto e1 = excursion(2e-8, t_end, 0.0);
  const auto e2 = excursion(1e-8, t_end, 0.0);
  RecordProperty("drift_tau", std::to_string(e1.drift));
  RecordProperty("drift_tau_half", std::to_string(e2.drift));
  std::printf("mean rate: drift %.3e at τ, %.3e at τ/2\n", e1.drift, e2.drift);
  // Without conduction E is conserved by the continuous problem and, with the mean rate, by the
  // discrete one: only the staggered loop's stop (iterated to 1e-13) and round-off remain;
  // 1e-9 of E(0) is far above both and far below the thesis' form's drift below.
  EXPECT_LT(e1.drift, 1e-9);
  EXPECT_LT(e2.drift, 1e-9);
}

TEST(ThermoelasticEnergy, NewmarksRateDriftsByOrderTau) {
  // The thesis' (5.6): the coupling terms do not cancel, and backward Euler damps the temperature
  // of the high modes the sudden expansion excites: E decays (measured 27 % at τ = 2e-8 s, 16 %
  // at 1e-8 s over 10 µs with δ ≈ 0.8), never grows, and the drift shrinks with τ as a
  // first-order scheme's does (ratio ≈ 0.6).
  using physics::ThermoelasticRate;
  const auto e1 = excursion(2e-8, 1e-5, 0.0, ThermoelasticRate::newmark);
  const auto e2 = excursion(1e-8, 1e-5, 0.0, ThermoelasticRate::newmark);
  std::printf("Newmark's rate: drift %.3e at τ, %.3e at τ/2\n", e1.drift, e2.drift);
  EXPECT_LT(e1.growth, 1e-9);
  EXPECT_LT(e2.growth, 1e-9);
  EXPECT_GT(e1.drift, 1e-2);
  EXPECT_LT(e1.drift, 0.5);
  EXPECT_LT(e2.drift, 0.7 * e1.drift);
}

TEST(ThermoelasticEnergy, DecreasesByWhatConductionTakes) {
  // With a large conductivity the temperature differences the expansion makes even out: E
  // decreases at every step by the conduction term, to the loop's stop and round-off (1e-9 of
  // E(0), as above), and ends below the run without conduction.
  const auto with = excursion(2e-8, 1e-5, 5e4);
  const auto without = excursion(2e-8, 1e-5, 0.0);
  std::printf("with conduction: E/E(0) = %.9f (without %.12f), identity to %.3e\n",
              with.final_ratio, without.final_ratio, with.identity);
  EXPECT_LT(with.growth, 1e-9);
  EXPECT_LT(with.identity, 1e-9);
  EXPECT_LT(with.final_ratio, without.final_ratio - 1e-4);
}

}  // namespace
