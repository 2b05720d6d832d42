#pragma once
// Node-to-node contact rows between matching faces (the slave's lower face on the master's
// upper one, each slave node paired with the master node at the same horizontal position),
// weighted by the slave's nodal areas, normal −e_vertical, tangents along the other axes, gap
// in the configuration X + u (the reference one without u). For the benchmarks and the tests
// of the dual solves (tests/support/contact_rows.hpp), which compare solvers on the same rows,
// so the mortar layer is not needed.
#include <cmath>
#include <string>

#include "tc/contact/contact_rows.hpp"
#include "tc/core/error.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::bench {

inline contact::ContactRows matching_rows(const mesh::Mesh& slave, const mesh::Mesh& master,
                                          const core::Vector* u_slave = nullptr,
                                          const core::Vector* u_master = nullptr) {
  const int dim = slave.dim();
  const std::string bottom = dim == 3 ? "zmin" : "ymin", top = dim == 3 ? "zmax" : "ymax";
  const auto weights = fem::boundary_integrals(slave, bottom);
  const auto s_nodes = slave.boundary_nodes(bottom);
  const auto m_nodes = master.boundary_nodes(top);
  const std::vector<double> us = u_slave ? u_slave->to_std() : std::vector<double>{};
  const std::vector<double> um = u_master ? u_master->to_std() : std::vector<double>{};
  contact::ContactRows rows;
  rows.dim = dim;
  const PetscInt m = dim * static_cast<PetscInt>(s_nodes.size());
  std::vector<PetscInt> nnz(static_cast<size_t>(m), 1);
  rows.slave = core::SparseMatrix(m, dim * slave.n_nodes(), nnz);
  rows.master = core::SparseMatrix(m, dim * master.n_nodes(), nnz);
  const int v = dim - 1;  // the vertical axis
  for (size_t k = 0; k < s_nodes.size(); ++k) {
    const auto& xs = slave.point(s_nodes[k]);
    int partner = -1;
    for (const int a : m_nodes) {
      const auto& xm = master.point(a);
      double d = 0;
      for (int i = 0; i < v; ++i) d += std::abs(xm[i] - xs[i]);
      if (d < 1e-12) partner = a;
    }
    if (partner < 0) throw Error("matching_rows: the meshes do not match");
    const double w = weights[static_cast<size_t>(s_nodes[k])];
    const double zs = xs[v] + (us.empty() ? 0.0 : us[dim * s_nodes[k] + v]);
    const double zm = master.point(partner)[v] + (um.empty() ? 0.0 : um[dim * partner + v]);
    rows.gap.push_back(w * (zs - zm));  // (x_m − x_s)·n, n = −e_v
    rows.weights.push_back(w);
    rows.nodes.push_back(s_nodes[k]);
    for (int r = 0; r < dim; ++r) {
      const int axis = r == 0 ? v : r - 1;  // row 0 the normal, then the tangents
      const double sign = r == 0 ? -1.0 : 1.0;
      const PetscInt row = dim * static_cast<PetscInt>(k) + r;
      const PetscInt cs = dim * s_nodes[k] + axis, cm = dim * partner + axis;
      const double vs = sign * w, vm = -sign * w;
      rows.slave.add_values({&row, 1}, {&cs, 1}, &vs);
      rows.master.add_values({&row, 1}, {&cm, 1}, &vm);
    }
  }
  rows.slave.assemble();
  rows.master.assemble();
  return rows;
}

}  // namespace tc::bench
