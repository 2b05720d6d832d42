#pragma once
// Boxes on rollers for the tests of the dual contact solve without Simulation: the stiffness
// factorised with its Dirichlet data (x = 0: u_x = 0; y = 0: u_y = 0 in 3D; the vertical
// displacement of one face prescribed, of another held), and the solution without contact.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "support/problems.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/fem/assembler.hpp"

namespace tc::test {

struct Block {
  mesh::Mesh mesh;
  fem::BodyMatrices matrices;
  std::vector<PetscInt> dirichlet;
  core::Vector u_prescribed;
  std::unique_ptr<physics::ConstrainedSolver> solver;
};

/// A box on rollers with the vertical displacement of `moved_face` prescribed to `moved_by` and
/// that of `fixed_face` held at zero (either name may be empty); of `element` cells when given
/// (mesh::make_box's), else Quad4 or Hex8.
inline Block make_block(int dim, const mesh::Point& lo, const mesh::Point& hi,
                        std::array<int, 3> cells, const std::string& moved_face, double moved_by,
                        const std::string& fixed_face,
                        std::optional<mesh::CellType> element = std::nullopt) {
  Block b;
  b.mesh =
      element ? mesh::make_box(dim, lo, hi, cells, *element) : mesh::make_box(dim, lo, hi, cells);
  b.matrices = fem::assemble_body(b.mesh, steel());
  const PetscInt n_u = dim * b.mesh.n_nodes();
  b.u_prescribed = core::Vector(n_u);
  std::map<PetscInt, double> fixed;
  for (const int a : b.mesh.boundary_nodes("xmin")) fixed[dim * a + 0] = 0;
  if (dim == 3)
    for (const int a : b.mesh.boundary_nodes("ymin")) fixed[dim * a + 1] = 0;
  const int vertical = dim - 1;
  if (!fixed_face.empty())
    for (const int a : b.mesh.boundary_nodes(fixed_face)) fixed[dim * a + vertical] = 0;
  if (!moved_face.empty())
    for (const int a : b.mesh.boundary_nodes(moved_face)) fixed[dim * a + vertical] = moved_by;
  {
    auto v = b.u_prescribed.view();
    for (const auto& [dof, value] : fixed) {
      b.dirichlet.push_back(dof);
      v[dof] = value;
    }
  }
  b.solver = std::make_unique<physics::ConstrainedSolver>(b.matrices.stiffness_u, b.dirichlet, "");
  return b;
}

/// u_free = A⁻¹f with f = 0 and the prescribed values: the block without contact.
inline core::Vector free_solution(const Block& b) {
  core::Vector f(b.u_prescribed.size());
  core::Vector u = b.u_prescribed.clone();
  b.solver->solve(f, u);
  return u;
}

}  // namespace tc::test
