#pragma once
// Reference elements (shape functions, gradients) and quadrature rules, and the element
// kernels of chapters 3–4 as pure functions of the element's coordinates and constants.
// Element matrices use interleaved displacement dofs, local dof d·a + k for node a and
// component k (thesis 4.1), and one temperature dof per node.
#include <Eigen/Dense>
#include <functional>
#include <span>
#include <vector>

#include "tc/mesh/mesh.hpp"

namespace tc::fem {

using mesh::CellType;
using mesh::FacetType;

struct QuadraturePoint {
  std::array<double, 3> xi{};  // reference coordinates
  double weight = 0;
};

/// Rules exact for the products of two shape functions (mass matrices) on cells with straight
/// edges: Gauss 2×2(×2) on Quad4/Hex8, degree-2 rules on Tri3/Tet4; Gauss 3×3(×3) on Quad8,
/// Quad9, Hex20, Hex27, the degree-4 6-point rule on Tri6 and the degree-5 14-point rule on
/// Tet10; Line2/Line3 and the facet rules likewise.
[[nodiscard]] std::span<const QuadraturePoint> quadrature(CellType t);
[[nodiscard]] std::span<const QuadraturePoint> quadrature(FacetType t);

/// Shape function values N (n) and reference gradients dN (n × dim) at xi.
void shape(CellType t, const std::array<double, 3>& xi, Eigen::VectorXd& n, Eigen::MatrixXd& dn);
void shape(FacetType t, const std::array<double, 3>& xi, Eigen::VectorXd& n, Eigen::MatrixXd& dn);

/// Node coordinates of one element, one row per node, `dim` columns.
using Coords = Eigen::MatrixXd;

using Func = std::function<double(const mesh::Point&)>;

// ---- Kernels (ch. 4). Each integrates over one cell with quadrature(t). -----------------

/// M_u: ∫ ρ φ_a·φ_b, (d·n)².
[[nodiscard]] Eigen::MatrixXd mass_u(CellType t, const Coords& x, double rho);
/// K_u: ∫ ε(φ_a) : C : ε(φ_b); 2D is plane strain of the 3D material (λ, μ), (d·n)².
[[nodiscard]] Eigen::MatrixXd stiffness_u(CellType t, const Coords& x, double lambda, double mu);
/// K_uθ: −∫ β N_b div φ_a, (d·n) × n, so that M ü + K u + K_uθ (θ − θ₀) = f is (2.5) with
/// the total stress σ(u) − β(θ − θ₀)I (docs/choices.md). K_θu of (2.8) is −θ₀ K_uθᵀ.
[[nodiscard]] Eigen::MatrixXd coupling_u_theta(CellType t, const Coords& x, double beta);
/// M_θ: ∫ ρ c_p N_a N_b, n².
[[nodiscard]] Eigen::MatrixXd mass_theta(CellType t, const Coords& x, double rho_cp);
/// K_θ: ∫ κ ∇N_a·∇N_b, n².
[[nodiscard]] Eigen::MatrixXd stiffness_theta(CellType t, const Coords& x, double kappa);
/// ∫ f N_a over the cell (f = 1 when empty), n.
[[nodiscard]] Eigen::VectorXd cell_load(CellType t, const Coords& x, const Func& f = {});
/// ∫ f N_a over a boundary facet (f = 1 when empty), n; x has `dim` columns of the body.
[[nodiscard]] Eigen::VectorXd facet_load(FacetType t, const Coords& x, const Func& f = {});
/// ∫ N_a N_b over a boundary facet, n²: the film (Robin) matrix of one facet per unit h.
[[nodiscard]] Eigen::MatrixXd facet_mass(FacetType t, const Coords& x);

/// One point of quadrature(t) mapped onto a cell: N_a, the physical gradients ∇N_a (n × dim)
/// and weight · det J. For kernels evaluated many times with fields that change (the heat
/// residual with κ(θ), c_p(θ): nonlinear_heat.hpp).
struct CellPoint {
  Eigen::VectorXd n;
  Eigen::MatrixXd grad;
  double jxw = 0;
};
[[nodiscard]] std::vector<CellPoint> cell_points(CellType t, const Coords& x);

// ---- Post-processing at the cell centre (the reference cell's centroid). -----------------

/// Small-strain tensor ε(u) at the cell centre (3×3; zero third row and column in 2D).
[[nodiscard]] Eigen::Matrix3d cell_strain(CellType t, const Coords& x, const Eigen::VectorXd& u_e);
/// Cauchy stress σ(u) − β(θ − θ₀)I at the cell centre (3×3; plane strain gives σ_zz ≠ 0).
/// u_e: interleaved nodal displacements, dtheta_e: nodal θ − θ₀.
[[nodiscard]] Eigen::Matrix3d cell_stress(CellType t, const Coords& x, const Eigen::VectorXd& u_e,
                                          const Eigen::VectorXd& dtheta_e, double lambda, double mu,
                                          double beta);
/// Heat flux −κ∇θ at the cell centre (3 components, z = 0 in 2D).
[[nodiscard]] Eigen::Vector3d cell_heat_flux(CellType t, const Coords& x,
                                             const Eigen::VectorXd& theta_e, double kappa);
[[nodiscard]] double von_mises(const Eigen::Matrix3d& s);

/// Rows of the element's node coordinates taken from the mesh (dim columns).
[[nodiscard]] Coords cell_coords(const mesh::Mesh& m, int c);
[[nodiscard]] Coords facet_coords(const mesh::Mesh& m, const mesh::Facet& f);

}  // namespace tc::fem
