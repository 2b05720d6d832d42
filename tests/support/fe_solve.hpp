#pragma once
// Test helpers for steady FE solves through physics::ConstrainedSolver (the solver the
// time loop uses), with Dirichlet data given per node and component.
#include <functional>

#include "support/test_meshes.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/mesh/box.hpp"

namespace tc::test {

/// The box mesh split into simplices (Tri3 in 2D, Tet4 in 3D).
inline mesh::Mesh split_to_simplices(const mesh::Mesh& box) {
  return box.dim() == 2 ? split_quads(box) : split_hexes(box);
}

/// Solves A x = b with x = g(node, component) on the listed nodes (block = dofs per node).
inline std::vector<double> solve_dirichlet(const core::SparseMatrix& a, const core::Vector& b,
                                           const std::vector<int>& nodes, int block,
                                           const std::function<double(int, int)>& g) {
  std::vector<PetscInt> dofs;
  core::Vector x(a.rows());
  {
    auto xv = x.view();
    for (const int n : nodes)
      for (int k = 0; k < block; ++k) {
        dofs.push_back(block * n + k);
        xv[block * n + k] = g(n, k);
      }
  }
  physics::ConstrainedSolver solver(a, dofs, "");
  solver.solve(b, x);
  return x.to_std();
}

}  // namespace tc::test
