#pragma once
// The material part of the backward-Euler heat step (5.6) when κ or c_p depends on θ
// (docs/theory.md, "Temperature-dependent materials"). With the enthalpy density
//   h(θ) = ρ ∫_{θ₀}^{θ} c_p(s) ds                                    [J/m³]
// the step is, for every test function N_a,
//   r_a(θ) = (H_a(θ) − H_a(θ^k))/τ + C_a(θ) − f_a = 0,
//   H_a(θ) = ∫ N_a h(θ_h) dx,   C_a(θ) = ∫ κ(θ_h) ∇N_a·∇θ_h dx,
// integrated by the cell's rule (quadrature(t)); with a lumped heat capacity H_a = V_a h(θ_a),
// V_a = ∫N_a. Σ_a H_a is the thermal energy the ledger counts, and Σ_a C_a = 0, so the
// discrete energy balance holds to the Newton tolerance whatever c_p(θ) is. For constant
// properties H(θ) − H(θ₀·1) = M_θ(θ − θ₀) and C(θ) = K_θθ: the linear step.
//
// The solver keeps A = M_θ/τ + K_θ, assembled with the material's reference numbers c_ref,
// κ_ref, and adds this class's N(θ) = (H(θ) − M_θθ)/τ + C(θ) − K_θθ: the residual of the
// whole step is A θ + N(θ) − b with b = f + H(θ^k)/τ. Holds the mesh's quadrature data
// (N, ∇N, weight per point of every cell); not collective.
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/fem/element.hpp"
#include "tc/fem/material.hpp"

namespace tc::fem {

class NonlinearHeat {
 public:
  /// `lumped`: the heat capacity lumped to nodes as M_θ is (lumped_volumes: row sums, HRZ on
  /// Tri6, Quad8, Tet10, Hex20; [physics] heat_capacity).
  NonlinearHeat(const mesh::Mesh& m, const Material& mat, double theta0, bool lumped);

  /// h(θ) = ρ ∫_{θ₀}^{θ} c_p dθ [J/m³].
  [[nodiscard]] double enthalpy_density(double theta) const;
  /// y += s H(θ).
  void add_enthalpy(const core::Vector& theta, double s, core::Vector& y) const;
  /// Σ_a H_a(θ) = ∫ h(θ_h) dx [J]: the thermal energy relative to θ₀.
  [[nodiscard]] double total_enthalpy(const core::Vector& theta) const;
  /// y += N(θ) = (H(θ) − M_θθ)/τ + C(θ) − K_θθ, `inv_tau` = 1/τ.
  void add_nonlinear_part(const core::Vector& theta, double inv_tau, core::Vector& y) const;
  /// y += N'(θ) x = (ρc_p(θ_h) − ρc_ref) x_h/τ tested with N_a
  ///               + ∫ [(κ(θ_h) − κ_ref)∇x_h + κ'(θ_h) x_h ∇θ_h]·∇N_a:
  /// the Jacobian of the whole step is A + N'(θ), not symmetric when κ' ≠ 0.
  void add_nonlinear_derivative(const core::Vector& theta, const core::Vector& x, double inv_tau,
                                core::Vector& y) const;

 private:
  struct Cell {
    std::vector<int> nodes;
    std::vector<CellPoint> points;
  };
  // visit(cell, point, θ_h, ∇θ_h) at every quadrature point
  template <class Visit>
  void for_each_point(std::span<const double> theta, Visit&& visit) const;

  const Material mat_;
  double theta0_;
  bool lumped_;
  int dim_;
  std::vector<Cell> cells_;
  std::vector<double> volumes_;  // V_a = ∫ N_a (lumped)
  // Work of the cell loops, sized once for the largest cell: GMRES applies the derivative
  // several times per Newton correction, at every quadrature point of the mesh, and an Eigen
  // temporary there is a heap allocation per point (example 06 tabulated: most of its
  // heat_solve). The same Eigen kernels write into them, so the results are those of the
  // temporaries to the bit.
  mutable Eigen::VectorXd te_, grad_, xe_, gx_, kg_, flux_;
};

}  // namespace tc::fem
