#pragma once
// What the energy balance of the bodies reads (history.csv): the discrete energies of the
// current state and the support reactions, whose work is the external work.
#include "tc/core/petsc.hpp"
#include "tc/physics/bodies.hpp"
#include "tc/physics/problem.hpp"

namespace tc::physics {

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

/// F = f_ext + R of body b at time t into r, R = M ü + K u + K_uθ(θ − θ₀) − f_ext on the
/// constrained dofs: the force the supports exert on the body, which with f_ext does the
/// external work. The body's f_u is scratch.
void support_forces(const Problem& p, const Bodies& bodies, int b, double t, core::Vector& r);

}  // namespace tc::physics
