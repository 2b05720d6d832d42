#pragma once
// One body's thermal energy as the heat ledger tests read it.
#include <vector>

#include "tc/run/simulation.hpp"

namespace tc::test {

/// ∫ρc_p(θ − θ₀) of body b with the nodal (lumped) volumes: the 1ᵀM_θ(θ − θ₀) that backward
/// Euler conserves up to the heat put in.
inline double body_energy(const physics::Simulation& sim, int b, double theta0) {
  const auto& vol = sim.system(b).node_volumes();
  const auto theta = sim.state(b).theta.to_std();
  const double c = sim.system(b).body().material.heat_capacity();
  double e = 0;
  for (size_t a = 0; a < vol.size(); ++a) e += c * vol[a] * (theta[a] - theta0);
  return e;
}

}  // namespace tc::test
