#pragma once
// Contact rows without the mortar layer, for tests of the dual solve: matching meshes, each
// slave node paired with the master node at the same (x, y) [2D: x], node-to-node rows
// weighted by the slave's nodal areas, normal −e_vertical (the slave lies on top), tangents
// along the other axes, and the gap measured in the configuration X + u.
#include "../../bench/support/matching_rows.hpp"
#include "tc/physics/dual_contact.hpp"

namespace tc::test {

inline physics::ContactRows node_to_node_rows(const mesh::Mesh& slave, const mesh::Mesh& master,
                                              const core::Vector* u_slave = nullptr,
                                              const core::Vector* u_master = nullptr) {
  return bench::matching_rows(slave, master, u_slave, u_master);
}

/// Rows with pseudo-random values on chosen dofs of each body (B_s: one dof per row, B_m:
/// three, like mortar rows), to exercise F = Σ B_i,T S_i B_i,Tᵀ on sets of dofs that grow.
inline physics::ContactRows scattered_rows(PetscInt n_s, PetscInt n_m, int nodes, PetscInt first,
                                           PetscInt stride) {
  physics::ContactRows rows;
  rows.dim = 3;
  const PetscInt m = 3 * nodes;
  std::vector<PetscInt> nnz(m, 3);
  rows.slave = core::SparseMatrix(m, n_s, nnz);
  rows.master = core::SparseMatrix(m, n_m, nnz);
  for (PetscInt r = 0; r < m; ++r) {
    const PetscInt cs = (first + stride * r) % n_s;
    const double vs = 1.0 + 0.1 * static_cast<double>(r % 7);
    rows.slave.add_values({&r, 1}, {&cs, 1}, &vs);
    for (PetscInt q = 0; q < 3; ++q) {
      const PetscInt cm = (first + stride * r + 5 * q) % n_m;
      const double vm = -0.3 - 0.05 * static_cast<double>((r + q) % 5);
      rows.master.add_values({&r, 1}, {&cm, 1}, &vm);
    }
  }
  rows.slave.assemble();
  rows.master.assemble();
  rows.gap.assign(static_cast<size_t>(nodes), 0.0);
  rows.weights.assign(static_cast<size_t>(nodes), 1.0);
  return rows;
}

}  // namespace tc::test
