#pragma once
// The linearised problem about a case's steady sliding state (docs/theory.md, "Linear
// stability"): the contact pair's active set held (bilateral at the nodes in contact, the open
// nodes left open) and every contact node sliding (λ_τ = 𝔉 λ_n s, s the tool's slip direction),
// the perturbation x = (u, θ, λ_n[, w]) of the slave body's free dofs, the active nodes'
// normal multipliers and, under `normal_control = "force"`, the tool's normal translation w:
//   K_u u + K_uθ θ + Gᵀ λ_n                = 0       G = B_n + 𝔉 s B_τ (2.5, 4.3)
//   M_θ θ̇ − θ₀ K_uθᵀ u̇ + K_θ θ − V Q̂ λ_n  = 0       (2.8 with d_θγ of 4.4 linearised)
//   B_n u (+ g_w w)                          = 0       (the active nodes stay closed)
//   (g_wᵀ λ_n                                = 0)      (the tool's normal force held)
// With x ∝ e^{bt}: (A₀ + V A₁) x = b M x, A₀ all but the frictional heat, A₁ = Q̂ per unit
// speed in the θ rows and λ_n columns, M = [0; −θ₀K_uθᵀ M_θ 0; 0] (the −θ₀K_uθᵀ block only with
// thermoelastic heating). Matrices whole on this rank (PETSC_COMM_SELF).
#include <array>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {
class Simulation;
}

namespace tc::stability {

/// Where each unknown of x comes from.
struct Unknowns {
  std::vector<PetscInt> u;      // the slave body's displacement dof of each u unknown
  std::vector<PetscInt> theta;  // its temperature dof (mesh node) of each θ unknown
  std::vector<int> contact;     // the mortar pair's contact node of each λ_n unknown
  bool tool_free = false;       // w, the tool's normal translation, is the last unknown
  [[nodiscard]] PetscInt theta_offset() const { return static_cast<PetscInt>(u.size()); }
  [[nodiscard]] PetscInt lambda_offset() const {
    return static_cast<PetscInt>(u.size() + theta.size());
  }
  [[nodiscard]] PetscInt size() const {
    return lambda_offset() + static_cast<PetscInt>(contact.size()) + (tool_free ? 1 : 0);
  }
};

struct Linearisation {
  Unknowns x;
  int body = 0;  // the slave body
  /// A₀, A₁ (per m/s), M: size() × size(), scaled: S A S with S = diag(scale), so that an
  /// eigenvector x̂ of the scaled pencil is x = S x̂ (eigen.cpp unscales it).
  core::SparseMatrix a0, a1, mass;
  std::vector<double> scale;
  double speed = 0;                   // the tool's sliding speed after the state [m/s]
  std::array<double, 3> direction{};  // its unit direction of sliding
  double friction = 0;                // the mean 𝔉 over the active nodes
  int open_nodes = 0;                 // contact nodes left open (λ_n = 0 at the state)
  /// Λ = 𝔉 E α / (k (1 − ν)) [1/(m·(m/s))]: the frictional heating's thermoelastic wavenumber
  /// per unit speed of the slave's material (docs/theory.md).
  double heating_wavenumber = 0;
  double diffusivity = 0;  // κ = k/(ρ c_p) of the slave [m²/s]
};

/// The linearisation of `sim`'s first contact pair about its current state (after the steps
/// it has taken); without `friction_shear` G = B_n (the shear 𝔉 λ_n s left out of the
/// mechanics, as the classical closed form does). Throws Error when there is no sliding or no
/// node in contact.
[[nodiscard]] Linearisation linearise(const physics::Simulation& sim,
                                      physics::StabilitySettings::NormalControl normal,
                                      bool friction_shear = true);

}  // namespace tc::stability
