#pragma once
// The constraint rows of one step, as the mortar pair produces them and the dual solve
// (physics::DualContactSolver, 6.9) consumes them: B = [B_s B_m] of (4.3) in node-major order,
// the weighted gap g of (2.6) and the nodal weights of the multiplier basis.
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::contact {

/// Row dim·k is the normal of contact node k, row dim·k + 1 + l its tangent l. Columns are
/// each body's displacement dofs (interleaved, k + d·j).
struct ContactRows {
  int dim = 3;
  core::SparseMatrix slave, master;
  std::vector<double> gap;      // weighted gap g_k ≥ 0 when open, in the configuration of B
  std::vector<double> weights;  // ∫ψ_k over the contact: λ_k × weight_k is a force
  std::vector<int> nodes;       // slave mesh node of each contact node (may be empty)
  // The rows' node structure, when known (the mortar pair's rows; empty otherwise):
  // B_s = V (D ⊗ I) and B_m = −V (M ⊗ I), V = diag(V_k) with V_k's rows the directions of
  // node k's rows (normal, then tangents: dim × dim, row-major), D and M of (4.3) by contact
  // node (rows) and body node (columns). The explicit dual forms its products on D and M,
  // a dim-th of B's entries (physics::DualContactSolver::form_from_compliance).
  std::vector<double> directions;
  core::SparseMatrix d, m;
  [[nodiscard]] PetscInt n_nodes() const { return static_cast<PetscInt>(gap.size()); }
  [[nodiscard]] PetscInt n_rows() const { return dim * n_nodes(); }
  /// The same rows with the matrices shared, not copied (the vectors are copied).
  [[nodiscard]] ContactRows shared() const {
    ContactRows s{dim, slave.share(), master.share(), gap, weights, nodes, directions, {}, {}};
    if (d.get()) s.d = d.share();
    if (m.get()) s.m = m.share();
    return s;
  }
  /// Whether directions, D and M are there and fit the rows.
  [[nodiscard]] bool node_structured() const {
    return directions.size() == static_cast<size_t>(dim * dim * n_nodes()) && d.get() && m.get() &&
           d.rows() == n_nodes() && m.rows() == n_nodes();
  }
};

}  // namespace tc::contact
