#pragma once
// Global assembly of element kernels into PETSc matrices with exact preallocation from the
// node graph, and of load integrals into nodal vectors.
#include <functional>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/fem/element.hpp"
#include "tc/fem/material.hpp"

namespace tc::fem {

/// Node adjacency (CSR, each row sorted, including the node itself) of a mesh.
struct NodeGraph {
  std::vector<int> offsets;  // n_nodes + 1
  std::vector<int> columns;
  [[nodiscard]] int degree(int node) const { return offsets[node + 1] - offsets[node]; }
};
[[nodiscard]] NodeGraph node_graph(const mesh::Mesh& m);

/// An element kernel: the dense element matrix of cell c, (row_block·n) × (col_block·n).
using CellKernel = std::function<Eigen::MatrixXd(int cell, CellType, const Coords&)>;

/// Assembles Σ_cells kernel into a (row_block·N) × (col_block·N) matrix; dof of node a,
/// component k is row_block·a + k. Preallocation is exact (from the node graph). With
/// `spread` each rank assembles its rows alone, from the cells that touch them
/// (core::SparseMatrix::over_ranks), the columns dealt in `spread_cols` (`spread` when null).
[[nodiscard]] core::SparseMatrix assemble(const mesh::Mesh& m, const NodeGraph& g, int row_block,
                                          int col_block, const CellKernel& kernel,
                                          const core::RowBlocks* spread = nullptr,
                                          const core::RowBlocks* spread_cols = nullptr);

/// Replaces the values of `out` (its pattern and rows kept) by Σ_cells kernel, as assemble does;
/// `spread` as there (the rows this rank holds).
void reassemble(const mesh::Mesh& m, int row_block, int col_block, const CellKernel& kernel,
                core::SparseMatrix& out, const core::RowBlocks* spread = nullptr);

/// The constant matrices of one body (ch. 4): M_u, K_u, K_uθ, M_θ, K_θ.
struct BodyMatrices {
  core::SparseMatrix mass_u, stiffness_u, coupling_u_theta, mass_theta, stiffness_theta;
};
/// With `spread` (the displacement dofs' blocks), M_u and K_u have their rows spread over the
/// ranks; with `spread_theta` (the temperature dofs'), M_θ and K_θ, and with both K_uθ, its
/// columns dealt in `spread_theta`.
[[nodiscard]] BodyMatrices assemble_body(const mesh::Mesh& m, const Material& mat,
                                         const core::RowBlocks* spread = nullptr,
                                         const core::RowBlocks* spread_theta = nullptr);

/// The moduli of every cell: λ, μ of E(θ_c), ν(θ_c) and β = (3λ + 2μ)α, α the material's number
/// (fem::Material::thermal_stress_modulus per cell).
struct CellModuli {
  std::vector<double> lambda, mu, beta;
};
/// K_u and K_uθ of `b` re-assembled in place with the cells' moduli (E(θ), ν(θ) tables:
/// physics::BodySystem::update_moduli); `spread`, `spread_theta` as for assemble_body.
void reassemble_mechanics(const mesh::Mesh& m, const CellModuli& cells, BodyMatrices& b,
                          const core::RowBlocks* spread = nullptr,
                          const core::RowBlocks* spread_theta = nullptr);

/// M_u without inertia on the nodes flagged in `massless` (the potential contact boundary):
/// the modified mass matrix of Hager, Hüeber & Wohlmuth (IJNME 73, 2008), built cell by cell
/// as P_eᵀ M_e P_e where P_e gives a massless node the mean displacement of its nearest
/// massive nodes of the cell (Khenous, Laborde & Renard's mass redistribution in the same
/// spirit). P_e reproduces constant fields, so the total mass and the momentum of a
/// translation are those of M_u; the change is confined to the cells at the boundary, O(h).
/// The pattern is M_u's. Throws when a cell touching the boundary has no massive node.
[[nodiscard]] core::SparseMatrix singular_mass_u(const mesh::Mesh& m, const Material& mat,
                                                 const std::vector<char>& massless,
                                                 const core::RowBlocks* spread = nullptr);

/// A boundary facet with a coefficient: h of a film boundary (its nodes numbered in the mesh
/// the matrix is assembled on, its `cell` a cell of that mesh).
struct WeightedFacet {
  mesh::Facet facet;
  double weight = 0;
};
/// Σ weight ∫ N_a N_b dS over the facets (the film term h∫θv of a Robin boundary), assembled
/// cell by cell with the node graph's pattern: the pattern of M_θ and K_θ, so that
/// a·M_θ + b·K_θ + H is formed with the same nonzeros (and the same rows, spread over the
/// ranks in `spread` as theirs are).
[[nodiscard]] core::SparseMatrix boundary_mass(const mesh::Mesh& m,
                                               const std::vector<WeightedFacet>& facets,
                                               const core::RowBlocks* spread = nullptr);

/// Row-sum lumping in place: each row's sum on its diagonal, the other entries zero but kept
/// in the pattern (so a·M + b·K still shares it with K); whole or spread over the ranks.
void lump_rows(core::SparseMatrix& m);

/// The lumped heat capacity per unit ρc at each node (length n_nodes): ∫N_a over the cells whose
/// row sums are positive (first order, Quad9, Hex27: row-sum lumping), and Hinton, Rock &
/// Zienkiewicz's diagonal scaling V_e (M_e)_aa / tr M_e over Tri6, Quad8, Tet10 and Hex20 cells,
/// whose row sums ∫N_a are zero or negative at the corners (docs/choices.md, "Mass of
/// second-order cells"). Both keep each cell's volume; a mesh without HRZ cells gets
/// volume_integrals to the bit.
[[nodiscard]] std::vector<double> lumped_volumes(const mesh::Mesh& m);
/// Row-sum lumping of a cell of type t gives every node a positive share (∫N_a > 0): false for
/// Tri6, Quad8, Tet10 and Hex20, which lumped_volumes lumps by HRZ.
[[nodiscard]] bool lumps_by_row_sums(mesh::CellType t);
/// Every cell of `m` lumps by row sums (no HRZ cell): lumped_volumes is volume_integrals.
[[nodiscard]] bool lumps_by_row_sums(const mesh::Mesh& m);
/// M_θ (of heat capacity ρc) lumped in place to ρc·lumped_volumes: lump_rows itself, to the bit,
/// on a mesh whose cells all have positive row sums; whole or spread over the ranks.
void lump_heat_capacity(core::SparseMatrix& mass_theta, const mesh::Mesh& m, double heat_capacity);

/// ∫ f N_a dx per node (length n_nodes); f = 1 when empty.
[[nodiscard]] std::vector<double> volume_integrals(const mesh::Mesh& m, const Func& f = {});
/// ∫ f N_a dS over the facets of a boundary, per node of the mesh (length n_nodes).
[[nodiscard]] std::vector<double> boundary_integrals(const mesh::Mesh& m,
                                                     const std::string& boundary,
                                                     const Func& f = {});

/// Errors of a discrete field against an exact one, by quadrature on each cell:
/// ‖u_h − u‖_L2 and |u_h − u|_H1 (seminorm). `components` is 1 (temperature) or dim
/// (interleaved displacement); exact(x, k) and exact_grad(x, k) give component k.
struct ErrorNorms {
  double l2 = 0, h1 = 0;
};
[[nodiscard]] ErrorNorms error_norms(
    const mesh::Mesh& m, std::span<const double> field, int components,
    const std::function<double(const mesh::Point&, int)>& exact,
    const std::function<Eigen::Vector3d(const mesh::Point&, int)>& exact_grad);

}  // namespace tc::fem
