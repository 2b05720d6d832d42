// Total FETI (6.2) for point loads: the compliance columns A⁻¹e_j of linalg::Compliance (the
// explicit contact operator of the nested form) against the undecomposed direct solve, and
// FETI's compliance (FetiCompliance) against a dense inverse. A unit
// load on a fixing dof of its subdomain has A_s⁺f = 0, so d = 0 and the load enters only
// through e = Rᵀf: the stopping test must not take λ₀ (feasible only) for the solution.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
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

// A block of 4³ cells clamped at xmin, cut into 8 subdomains.
auto clamped_block() {
  auto p = box_problem(3, {1, 1, 1}, {4, 4, 4}, steel(), physics::Scheme::quasistatic, 1.0, 1);
  p.bodies[0].subdomains = 8;
  p.boundaries.push_back(hold("xmin", {0, 1, 2}));
  return p;
}

// Its displacements by Total FETI to 1e-10 of the dual residual.
physics::ConstrainedSolver feti_solver(const physics::BodySystem& sys) {
  feti::FetiOptions o;
  o.tolerance = 1e-10;
  o.comm = PETSC_COMM_SELF;
  return physics::ConstrainedSolver(std::make_unique<feti::Feti>(
      sys.subdomains(), sys.body().mesh.n_nodes(), 3, sys.u_dirichlet_dofs(), feti::Kernel::rigid,
      feti::Singular::yes, [&](int s) { return sys.subdomain_matrices(s).stiffness_u.copy(); }, o));
}

// A block clamped at xmin, cut into 8 subdomains: unit loads on every dof (64 per block solve,
// the compliance's block size). FETI stops at 1e-10 of the dual residual; the primal error is
// that times the dual condition number (≲ 1e2 at H/h = 2), so 1e-7 of the largest entry.
TEST(Feti, PointLoadsGiveTheDirectSolution) {
  const auto p = clamped_block();
  const physics::BodySystem sys(p, 0);
  const auto feti = feti_solver(sys);
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

// FetiCompliance: S = (A⁻¹)_TT on dofs of the free face (a clamped dof among them), covered in
// two chunks, against Eigen's inverse of the eliminated stiffness; a replay of its record gives
// the same bits (FETI's block PCG is deterministic on one rank). Tolerance: FETI's, as above.
TEST(Feti, ItsComplianceIsTheDenseInverse) {
  const auto p = clamped_block();
  const physics::BodySystem sys(p, 0);
  const auto feti = feti_solver(sys);
  const PetscInt n = sys.n_u();
  auto fixed = sys.u_dirichlet_dofs();
  std::sort(fixed.begin(), fixed.end());
  const auto is_fixed = [&](PetscInt d) {
    return std::binary_search(fixed.begin(), fixed.end(), d);
  };
  // A with the clamped rows and columns replaced by the identity: its inverse is A_FF⁻¹ on the
  // free dofs and zero across, so zeroing the clamped rows and columns after gives S's entries.
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
  const auto& k = sys.matrices().stiffness_u;
  for (PetscInt r = 0; r < n; ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(k.get(), r, &nz, &cols, &vals));
    for (PetscInt q = 0; q < nz; ++q)
      if (!is_fixed(r) && !is_fixed(cols[q])) a(r, cols[q]) = vals[q];
    TC_PETSC(MatRestoreRow(k.get(), r, &nz, &cols, &vals));
    if (is_fixed(r)) a(r, r) = 1.0;
  }
  Eigen::MatrixXd inverse = a.llt().solve(Eigen::MatrixXd::Identity(n, n));
  for (const PetscInt d : fixed) {
    inverse.row(d).setZero();
    inverse.col(d).setZero();
  }
  std::vector<PetscInt> first, second;  // dofs of nodes near xmax, then more, and a clamped one
  for (PetscInt d = n - 60; d < n - 20; ++d) first.push_back(d);
  for (PetscInt d = n - 30; d < n; ++d) second.push_back(d);
  second.push_back(fixed.front());
  const auto c = feti.compliance(n);
  EXPECT_EQ(c->path(), "feti");
  c->cover(first);
  c->cover(second);
  const double scale = inverse.cwiseAbs().maxCoeff();
  for (PetscInt j = 0; j < c->size(); ++j)
    for (PetscInt i = 0; i < c->size(); ++i)
      ASSERT_NEAR(c->matrix()(i, j), inverse(c->dofs()[i], c->dofs()[j]), 1e-7 * scale)
          << i << ", " << j;
  EXPECT_EQ(c->matrix(), c->matrix().transpose());  // exactly symmetric (the mean of two)
  const auto again = feti.compliance(n);
  again->replay(c->dofs(), c->chunks());
  EXPECT_TRUE(again->matrix() == c->matrix());
}

}  // namespace
}  // namespace tc::test
