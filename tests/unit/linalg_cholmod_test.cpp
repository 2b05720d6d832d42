// CHOLMOD through SuiteSparse's public API (linalg/cholmod/cholmod_factor.hpp) against PETSc's own
// CHOLMOD matrix type, which CholeskySolver called before: the same matrix handed to CHOLMOD,
// the same default ordering and supernodes, hence the same factor and the same solves bit for
// bit. That is what keeps every history byte-identical across the change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "support/grid_laplacian.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/linalg/cholmod/cholmod_factor.hpp"

namespace {

using tc::core::Handle;

/// PETSc's MATSOLVERCHOLMOD factor of `a`, made as CholeskySolver made it before: a KSPPREONLY
/// with PCCHOLESKY set up once.
class PetscCholmod {
 public:
  explicit PetscCholmod(const tc::core::SparseMatrix& a) {
    TC_PETSC(MatSetOption(a.get(), MAT_SYMMETRIC, PETSC_TRUE));
    TC_PETSC(MatSetOption(a.get(), MAT_SPD, PETSC_TRUE));
    TC_PETSC(KSPCreate(PETSC_COMM_SELF, ksp_.out()));
    TC_PETSC(KSPSetOperators(ksp_.get(), a.get(), a.get()));
    TC_PETSC(KSPSetType(ksp_.get(), KSPPREONLY));
    PC pc = nullptr;
    TC_PETSC(KSPGetPC(ksp_.get(), &pc));
    TC_PETSC(PCSetType(pc, PCCHOLESKY));
    TC_PETSC(PCFactorSetMatSolverType(pc, MATSOLVERCHOLMOD));
    TC_PETSC(KSPSetUp(ksp_.get()));
    TC_PETSC(PCFactorGetMatrix(pc, &factor_));
  }
  [[nodiscard]] ::Mat factor() const { return factor_; }

 private:
  Handle<::KSP, KSPDestroy> ksp_;
  ::Mat factor_ = nullptr;  // owned by the KSP's PC
};

/// A dense n × k right-hand side whose entries are all distinct (no accidental symmetry).
Handle<::Mat, MatDestroy> dense_rhs(PetscInt n, PetscInt k) {
  Handle<::Mat, MatDestroy> b;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, b.out()));
  double* v = nullptr;
  TC_PETSC(MatDenseGetArrayWrite(b.get(), &v));
  for (PetscInt i = 0; i < n * k; ++i) v[i] = std::sin(0.37 * static_cast<double>(i) + 0.1);
  TC_PETSC(MatDenseRestoreArrayWrite(b.get(), &v));
  return b;
}

std::vector<double> entries(::Mat m) {
  PetscInt n = 0, k = 0;
  TC_PETSC(MatGetSize(m, &n, &k));
  const double* v = nullptr;
  TC_PETSC(MatDenseGetArrayRead(m, &v));
  std::vector<double> out(v, v + n * k);
  TC_PETSC(MatDenseRestoreArrayRead(m, &v));
  return out;
}

/// Bit for bit: memcmp, so that a −0 against +0 or another NaN payload would show.
void expect_same_bits(const std::vector<double>& a, const std::vector<double>& b,
                      const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (std::memcmp(&a[i], &b[i], sizeof(double)) != 0) ++differ;
  EXPECT_EQ(differ, 0u) << what << ": " << differ << " of " << a.size() << " entries differ";
}

void compare_with_petsc(const tc::core::SparseMatrix& a, bool supernodal) {
  const PetscInt n = a.rows();
  const PetscCholmod reference(a);
  const tc::linalg::CholeskySolver ours(a, MATSOLVERCHOLMOD);
  {
    const tc::linalg::CholmodFactor f(a.get());
    EXPECT_EQ(f.supernodal(), supernodal) << "CHOLMOD's choice of factor for n = " << n;
  }
  for (const PetscInt k : {1, 7}) {  // one column (MatSolve) and a block (MatMatSolve)
    const auto b = dense_rhs(n, k);
    Handle<::Mat, MatDestroy> x_ref, x_ours;
    TC_PETSC(MatDuplicate(b.get(), MAT_DO_NOT_COPY_VALUES, x_ref.out()));
    TC_PETSC(MatDuplicate(b.get(), MAT_DO_NOT_COPY_VALUES, x_ours.out()));
    TC_PETSC(MatMatSolve(reference.factor(), b.get(), x_ref.get()));
    ours.solve_many(b.get(), x_ours.get());
    expect_same_bits(entries(x_ref.get()), entries(x_ours.get()),
                     "solve_many, n = " + std::to_string(n) + ", k = " + std::to_string(k));
  }
  tc::core::Vector b(n), x_ref(n), x_ours(n);
  {
    auto v = b.view();
    for (PetscInt i = 0; i < n; ++i) v[i] = std::cos(0.11 * static_cast<double>(i));
  }
  TC_PETSC(MatSolve(reference.factor(), b.get(), x_ref.get()));
  ours.solve(b, x_ours);
  const auto r = x_ref.read();
  const auto o = x_ours.read();
  expect_same_bits(std::vector<double>(r.span().begin(), r.span().end()),
                   std::vector<double>(o.span().begin(), o.span().end()),
                   "solve, n = " + std::to_string(n));
}

}  // namespace

TEST(Cholmod, SupernodalSolvesArePetscsCholmodBitForBit) {
  // 14³ rows: above CHOLMOD's flop threshold for a supernodal factor, with AMD's ordering.
  compare_with_petsc(tc::test::shifted_laplacian(14), true);
}

TEST(Cholmod, SimplicialSolvesArePetscsCholmodBitForBit) {
  // A small band: CHOLMOD keeps a simplicial factor (no restricted solves there).
  compare_with_petsc(tc::test::tridiagonal(60, 2.5), false);
}

TEST(Cholmod, IsTheAutomaticPackageOnOneRank) {
  // Built in (CMake fails without it), so the automatic choice whatever PETSc was built with.
  const auto packages = tc::linalg::available_cholesky_packages();
  ASSERT_FALSE(packages.empty());
  EXPECT_EQ(packages.front(), MATSOLVERCHOLMOD);
  EXPECT_NE(tc::linalg::cholmod_path().find("public API"), std::string::npos);
}

TEST(Cholmod, AnIndefiniteMatrixIsRefusedNamingTheColumn) {
  // The supernodal LLᵀ of the 14³ Laplacian with one diagonal entry made negative: no LLᵀ
  // exists (a negative diagonal entry is a negative Rayleigh quotient), CHOLMOD stops at a
  // column and the factor must not be used. (A simplicial factor is CHOLMOD's LDLᵀ, which PETSc
  // did not check either: the bodies' matrices large enough to matter are supernodal.)
  auto a = tc::test::shifted_laplacian(14);
  TC_PETSC(MatSetValue(a.get(), 1000, 1000, -20.0, ADD_VALUES));  // 6.5 − 20 < 0
  a.assemble();
  try {
    const tc::linalg::CholeskySolver solver(a, MATSOLVERCHOLMOD);
    ADD_FAILURE() << "an indefinite matrix was factorised";
  } catch (const tc::PetscError& e) {
    EXPECT_NE(std::string(e.what()).find("not positive definite"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("column"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), PETSC_ERR_MAT_CH_ZRPVT);
  }
}
