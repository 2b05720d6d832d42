#pragma once
// Contact rows without the mortar layer, for tests of the dual solve: matching meshes, each
// slave node paired with the master node at the same (x, y) [2D: x], node-to-node rows
// weighted by the slave's nodal areas, normal −e_vertical (the slave lies on top), tangents
// along the other axes, and the gap measured in the configuration X + u.
#include <array>
#include <cmath>
#include <vector>

#include "../../bench/support/matching_rows.hpp"
#include "tc/dual/dual_contact.hpp"

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

/// Rows with the mortar pair's node structure (ContactRows::node_structured): contact node k
/// on slave node (first + stride·k) mod the slave's nodes with weight D_kk, on three master
/// nodes with weights M_kj, and directions V_k (a pseudo-random unit normal, then tangents
/// orthonormal to it); B_s = V(D ⊗ I), B_m = −V(M ⊗ I) entry by entry as MortarPair builds
/// them. Clearing `directions` leaves the same B without the structure.
inline physics::ContactRows node_structured_rows(int dim, PetscInt n_s_nodes, PetscInt n_m_nodes,
                                                 int nodes, PetscInt first, PetscInt stride) {
  physics::ContactRows rows;
  rows.dim = dim;
  const PetscInt m = dim * nodes;
  std::vector<PetscInt> one(static_cast<size_t>(nodes), 1), three(static_cast<size_t>(nodes), 3);
  rows.d = core::SparseMatrix(nodes, n_s_nodes, one);
  rows.m = core::SparseMatrix(nodes, n_m_nodes, three);
  std::vector<PetscInt> nnz_s(static_cast<size_t>(m), dim), nnz_m(static_cast<size_t>(m), 3 * dim);
  rows.slave = core::SparseMatrix(m, dim * n_s_nodes, nnz_s);
  rows.master = core::SparseMatrix(m, dim * n_m_nodes, nnz_m);
  for (PetscInt k = 0; k < nodes; ++k) {
    const double a = 0.3 + 0.7 * static_cast<double>(k % 5), b = 0.2 * static_cast<double>(k % 3);
    std::array<double, 3> n{std::sin(a) * std::cos(b), std::sin(a) * std::sin(b), std::cos(a)};
    if (dim == 2) n = {std::sin(a), std::cos(a), 0.0};
    std::array<std::array<double, 3>, 3> v{};
    v[0] = n;
    v[1] = dim == 2 ? std::array<double, 3>{n[1], -n[0], 0.0}
                    : std::array<double, 3>{n[2], 0.0, -n[0]};  // ⟂ n
    if (dim == 3) {
      const double t = std::hypot(v[1][0], v[1][2]);
      for (double& c : v[1]) c /= t;
      v[2] = {n[1] * v[1][2] - n[2] * v[1][1], n[2] * v[1][0] - n[0] * v[1][2],
              n[0] * v[1][1] - n[1] * v[1][0]};
    }
    for (int r = 0; r < dim; ++r)
      for (int c = 0; c < dim; ++c) rows.directions.push_back(v[r][c]);
    const PetscInt js = (first + stride * k) % n_s_nodes;
    const double ds = 1.0 + 0.1 * static_cast<double>(k % 7);
    rows.d.add_values({&k, 1}, {&js, 1}, &ds);
    std::array<PetscInt, 3> jm{};
    std::array<double, 3> mm{};
    for (PetscInt q = 0; q < 3; ++q) {
      jm[q] = (first + stride * k + 5 * q) % n_m_nodes;
      mm[q] = 0.3 + 0.05 * static_cast<double>((k + q) % 5);
    }
    rows.m.add_values({&k, 1}, jm, mm.data());
    for (int r = 0; r < dim; ++r) {
      const PetscInt row = dim * k + r;
      std::vector<PetscInt> cs, cm;
      std::vector<double> vs, vm;
      for (int c = 0; c < dim; ++c) {
        cs.push_back(dim * js + c);
        vs.push_back(1.0 * ds * v[r][c]);
        for (PetscInt q = 0; q < 3; ++q) {
          cm.push_back(dim * jm[q] + c);
          vm.push_back(-1.0 * mm[q] * v[r][c]);
        }
      }
      rows.slave.add_values({&row, 1}, cs, vs.data());
      rows.master.add_values({&row, 1}, cm, vm.data());
    }
  }
  for (auto* b : {&rows.d, &rows.m, &rows.slave, &rows.master}) b->assemble();
  rows.gap.assign(static_cast<size_t>(nodes), 0.0);
  rows.weights.assign(static_cast<size_t>(nodes), 1.0);
  return rows;
}

}  // namespace tc::test
