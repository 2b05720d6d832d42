// Total FETI (6.2) for point loads: the compliance columns A⁻¹e_j of DofCompliance (the
// explicit contact operator of the nested form) against the undecomposed direct solve. A unit
// load on a fixing dof of its subdomain has A_s⁺f = 0, so d = 0 and the load enters only
// through e = Rᵀf: the stopping test must not take λ₀ (feasible only) for the solution.
#include <gtest/gtest.h>

#include <cmath>

#include "support/problems.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::test {
namespace {

struct Dense {
  core::Handle<::Mat, MatDestroy> m;
  Dense(PetscInt n, PetscInt k) {
    TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, m.out()));
    TC_PETSC(MatAssemblyBegin(m.get(), MAT_FINAL_ASSEMBLY));
    TC_PETSC(MatAssemblyEnd(m.get(), MAT_FINAL_ASSEMBLY));
  }
};

// A block clamped at xmin, cut into 8 subdomains: unit loads on every dof (64 per block solve,
// the compliance's block size). FETI stops at 1e-10 of the dual residual; the primal error is
// that times the dual condition number (≲ 1e2 at H/h = 2), so 1e-7 of the largest entry.
TEST(Feti, PointLoadsGiveTheDirectSolution) {
  auto p = box_problem(3, {1, 1, 1}, {4, 4, 4}, steel(), physics::Scheme::quasistatic, 1.0, 1);
  p.bodies[0].subdomains = 8;
  p.boundaries.push_back(hold("xmin", {0, 1, 2}));
  const physics::BodySystem sys(p, 0);
  feti::FetiOptions o;
  o.tolerance = 1e-10;
  o.comm = PETSC_COMM_SELF;
  const physics::ConstrainedSolver feti(std::make_unique<feti::Feti>(
      sys.subdomains(), sys.body().mesh.n_nodes(), 3, sys.u_dirichlet_dofs(), feti::Kernel::rigid,
      feti::Singular::yes, [&](int s) { return sys.subdomain_matrices(s).stiffness_u.copy(); }, o));
  const physics::ConstrainedSolver direct(sys.matrices().stiffness_u, sys.u_dirichlet_dofs(), "");
  const PetscInt n = sys.n_u();
  double worst = 0, largest = 0;
  for (PetscInt j0 = 0; j0 < n; j0 += 64) {
    const PetscInt k = std::min<PetscInt>(64, n - j0);
    Dense b1(n, k), b2(n, k), x1(n, k), x2(n, k);
    for (auto* b : {&b1, &b2}) {
      for (PetscInt c = 0; c < k; ++c)
        TC_PETSC(MatSetValue(b->m.get(), j0 + c, c, 1.0, INSERT_VALUES));
      TC_PETSC(MatAssemblyBegin(b->m.get(), MAT_FINAL_ASSEMBLY));
      TC_PETSC(MatAssemblyEnd(b->m.get(), MAT_FINAL_ASSEMBLY));
    }
    feti.solve_homogeneous_many(b1.m.get(), x1.m.get());
    direct.solve_homogeneous_many(b2.m.get(), x2.m.get());
    const double *a1 = nullptr, *a2 = nullptr;
    TC_PETSC(MatDenseGetArrayRead(x1.m.get(), &a1));
    TC_PETSC(MatDenseGetArrayRead(x2.m.get(), &a2));
    for (PetscInt i = 0; i < n * k; ++i) {
      worst = std::max(worst, std::abs(a1[i] - a2[i]));
      largest = std::max(largest, std::abs(a2[i]));
    }
    TC_PETSC(MatDenseRestoreArrayRead(x1.m.get(), &a1));
    TC_PETSC(MatDenseRestoreArrayRead(x2.m.get(), &a2));
  }
  EXPECT_GT(largest, 0.0);
  EXPECT_LT(worst, 1e-7 * largest);
}

}  // namespace
}  // namespace tc::test
