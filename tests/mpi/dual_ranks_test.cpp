// The explicit dual operator F = Σ_i B_i S_i B_iᵀ with the bodies' factors spread over the
// ranks (MUMPS over PETSC_COMM_WORLD): the compliances S_i then have their rows dealt over the
// ranks (DofCompliance with rows_over_ranks), each rank forms its part of F from its rows and
// the parts are summed. Against F formed from each rank's own factor, on rows that grow T and
// then reach only part of it (S restricted to U). Run at 1 and 2 ranks (label mpi).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

#include "support/contact_rows.hpp"
#include "support/roller_blocks.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::test {
namespace {

std::vector<double> entries(::Mat f, PetscInt m) {
  const PetscScalar* v = nullptr;
  TC_PETSC(MatDenseGetArrayRead(f, &v));
  std::vector<double> out(v, v + m * m);
  TC_PETSC(MatDenseRestoreArrayRead(f, &v));
  return out;
}

TEST(ExplicitFOverRanks, IsTheRanksOwnFToRoundOffAndTheSameOnEveryRank) {
  auto slave = make_block(3, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, "zmax", 0.0, "");
  auto master = make_block(3, {0, 0, 0}, {1, 1, 1}, {3, 3, 3}, "", 0.0, "zmin");
  const PetscInt n_s = slave.u_prescribed.size(), n_m = master.u_prescribed.size();
  const physics::ConstrainedSolver spread_s(slave.matrices.stiffness_u, slave.dirichlet, "",
                                            linalg::FactorRanks::all_ranks);
  const physics::ConstrainedSolver spread_m(master.matrices.stiffness_u, master.dirichlet, "",
                                            linalg::FactorRanks::all_ranks);
  physics::DualContactSettings settings;
  settings.scale = false;  // explicit_matrix() is then F itself
  physics::DualContactSolver over(spread_s, spread_m, n_s, n_m, settings);
  physics::DualContactSolver own(*slave.solver, *master.solver, n_s, n_m, settings);
  // The second rows overlap the first and reach new dofs; the third are the first again: no
  // new dof, and U (the dofs they reach) smaller than T.
  const std::tuple<int, PetscInt, PetscInt> cases[] = {{6, 0, 7}, {8, 11, 5}, {6, 0, 7}};
  int rank = 0;
  MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
  for (const auto& [nodes, first, stride] : cases) {
    over.set_rows(scattered_rows(n_s, n_m, nodes, first, stride));
    own.set_rows(scattered_rows(n_s, n_m, nodes, first, stride));
    ASSERT_NE(over.explicit_matrix(), nullptr);
    ASSERT_NE(own.explicit_matrix(), nullptr);
    const PetscInt m = 3 * nodes;
    const auto a = entries(over.explicit_matrix(), m), b = entries(own.explicit_matrix(), m);
    double scale = 0, worst = 0;
    for (size_t k = 0; k < a.size(); ++k) {
      scale = std::max(scale, std::abs(b[k]));
      worst = std::max(worst, std::abs(a[k] - b[k]));
    }
    // Two direct factorisations (MUMPS's, the rank's CHOLMOD's), then the same products summed
    // in another order: round-off of a few hundred operations on O(scale) numbers; a row of S
    // missed or counted twice would change entries by their own size.
    ASSERT_GT(scale, 0.0);
    EXPECT_LE(worst, 1e-12 * scale) << nodes << " nodes";
    // The QP runs on every rank with its copy of F: the copies must be equal to the bit.
    auto root = a;
    MPI_Bcast(root.data(), static_cast<int>(root.size()), MPI_DOUBLE, 0, PETSC_COMM_WORLD);
    EXPECT_EQ(root, a) << "rank " << rank;
    for (PetscInt i = 0; i < m; ++i)  // exactly symmetric, as dsymv reads one triangle
      for (PetscInt j = 0; j < i; ++j) ASSERT_EQ(a[i * m + j], a[j * m + i]);
  }
}

}  // namespace
}  // namespace tc::test
