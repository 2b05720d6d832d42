// linalg::Compliance on one rank, each implementation against a dense inverse (Eigen) of the
// same SPD matrix with Dirichlet dofs eliminated: CHOLMOD's restricted solves, CHOLMOD's
// forward solves (with apply and the corrected solve), and block solves (PETSc's own Cholesky,
// MUMPS on one rank). S is covered in several chunks, and a replay of its record gives the same
// bits. MUMPS's selected inverse over the ranks is tests/mpi/cholesky_ranks_test.cpp's.
#include <gtest/gtest.h>
#include <petscsys.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "support/grid_laplacian.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/linalg/eliminated_cholesky.hpp"

namespace tc::test {
namespace {

// g = 12: CHOLMOD takes a supernodal factor from there on (grid_laplacian.hpp), and the dense
// reference (1 728 unknowns) stays a fraction of a second.
constexpr PetscInt kG = 12, kN = kG * kG * kG;

PetscInt id(PetscInt x, PetscInt y, PetscInt z) {
  return x + kG * (y + kG * z);
}

// The face z = 0 clamped, as a body's supported face.
std::vector<PetscInt> clamped() {
  std::vector<PetscInt> d;
  for (PetscInt y = 0; y < kG; ++y)
    for (PetscInt x = 0; x < kG; ++x) d.push_back(id(x, y, 0));
  return d;
}

// (A⁻¹) of the eliminated operator, dense: the inverse of A_FF on the free dofs, zero rows and
// columns on the clamped ones (what the compliance's S holds there).
Eigen::MatrixXd dense_inverse(const core::SparseMatrix& a, const std::vector<PetscInt>& fixed) {
  Eigen::MatrixXd full = Eigen::MatrixXd::Zero(kN, kN);
  for (PetscInt r = 0; r < kN; ++r) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), r, &nz, &cols, &vals));
    for (PetscInt k = 0; k < nz; ++k) full(r, cols[k]) = vals[k];
    TC_PETSC(MatRestoreRow(a.get(), r, &nz, &cols, &vals));
  }
  std::vector<PetscInt> free;
  for (PetscInt i = 0; i < kN; ++i)
    if (!std::binary_search(fixed.begin(), fixed.end(), i)) free.push_back(i);
  const auto nf = static_cast<Eigen::Index>(free.size());
  Eigen::MatrixXd aff(nf, nf);
  for (Eigen::Index i = 0; i < nf; ++i)
    for (Eigen::Index j = 0; j < nf; ++j) aff(i, j) = full(free[i], free[j]);
  const Eigen::MatrixXd inv = aff.llt().solve(Eigen::MatrixXd::Identity(nf, nf));
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(kN, kN);
  for (Eigen::Index i = 0; i < nf; ++i)
    for (Eigen::Index j = 0; j < nf; ++j) out(free[i], free[j]) = inv(i, j);
  return out;
}

// T grown as the contact rows grow it: a patch of the top face, a strip beside it that repeats
// some of the patch, then a few dofs of a side with a clamped one among them.
std::vector<std::vector<PetscInt>> chunks() {
  std::vector<PetscInt> patch, strip, side;
  for (PetscInt y = 0; y < 6; ++y)
    for (PetscInt x = 0; x < 6; ++x) patch.push_back(id(x, y, kG - 1));
  for (PetscInt y = 0; y < kG; ++y)
    for (PetscInt x = 4; x < 9; ++x) strip.push_back(id(x, y, kG - 1));
  for (PetscInt z = 0; z < kG; z += 3) side.push_back(id(0, kG - 1, z));  // z = 0 is clamped
  return {patch, strip, side};
}

// The matrix (a PETSc object: made per test, freed before PETSc finalises), the clamped dofs
// and the dense inverse (computed once: the tests share it).
struct Fixture {
  core::SparseMatrix a = shifted_laplacian(kG);
  std::vector<PetscInt> fixed = clamped();
  const Eigen::MatrixXd& inverse = reference(a, fixed);

  static const Eigen::MatrixXd& reference(const core::SparseMatrix& a,
                                          const std::vector<PetscInt>& fixed) {
    static const Eigen::MatrixXd inverse = dense_inverse(a, fixed);
    return inverse;
  }
};

// S of `c` after covering every chunk against the dense inverse on T; then the record replayed
// into a fresh compliance of the same solver gives S to the bit.
void expect_dense_inverse(const Fixture& f, const linalg::EliminatedCholesky& solver,
                          linalg::Compliance& c) {
  PetscInt solves = 0;
  for (const auto& chunk : chunks()) solves += c.cover(chunk);
  EXPECT_EQ(solves, c.size());  // one column per new dof, each counted once
  const auto t = c.size();
  ASSERT_EQ(c.matrix().rows(), t);
  ASSERT_EQ(c.matrix().cols(), t);
  // κ(A) ≤ 12.5/0.5 = 25 (the 7-point Laplacian's spectrum in [0, 12], shifted by 0.5): both
  // factorisations are backward stable, so each entry is within a few κ·n·ε of the exact one
  // relative to max|S| — 1e-12 leaves a factor of ~10 over 25 · 1 728 · 2.2e-16.
  const double scale = f.inverse.cwiseAbs().maxCoeff();
  for (PetscInt j = 0; j < t; ++j)
    for (PetscInt i = 0; i < t; ++i)
      ASSERT_NEAR(c.matrix()(i, j), f.inverse(c.dofs()[i], c.dofs()[j]), 1e-12 * scale)
          << c.path() << " (" << i << ", " << j << ")";
  EXPECT_EQ(c.matrix(), c.matrix().transpose()) << "exactly symmetric: " << c.path();
  EXPECT_EQ(c.chunks().size(), 3u);
  const auto again = solver.compliance(false);
  again->replay(c.dofs(), c.chunks());
  EXPECT_EQ(again->path(), c.path());
  EXPECT_TRUE(again->matrix() == c.matrix()) << "replay gives other bits: " << c.path();
}

TEST(Compliance, CholmodRestrictedSolvesAreTheDenseInverse) {
  const Fixture f;
  const linalg::EliminatedCholesky solver(f.a, f.fixed, MATSOLVERCHOLMOD);
  const auto c = solver.compliance(false);
  expect_dense_inverse(f, solver, *c);
  EXPECT_EQ(c->path(), "cholmod-supernodal (restricted solves)");
  // No kept forward columns: nothing cheaper than the caller's own solves.
  core::Vector b(kN), x(kN);
  linalg::CorrectedSolve s;
  EXPECT_FALSE(c->apply(b, x));
  EXPECT_FALSE(c->begin_corrected(b, x, s));
  EXPECT_FALSE(c->finish_corrected(s, b, x));
}

TEST(Compliance, CholmodForwardSolvesAreTheDenseInverseAndShareTheBodysSolves) {
  const Fixture f;
  const linalg::EliminatedCholesky solver(f.a, f.fixed, MATSOLVERCHOLMOD);
  // -tc_forward_compliance takes S = YᵀY at any size (a test's is below the flop bound).
  TC_PETSC(PetscOptionsSetValue(nullptr, "-tc_forward_compliance", nullptr));
  const auto c = solver.compliance(false);
  expect_dense_inverse(f, solver, *c);
  TC_PETSC(PetscOptionsClearValue(nullptr, "-tc_forward_compliance"));
  EXPECT_EQ(c->path(), "cholmod-supernodal (forward solves)");

  // apply: x = A⁻¹w for w on T, against the dense inverse (the tolerance of the entries above:
  // a sum of |T| of them, each within 1e-12 max|S|).
  core::Vector w(kN), x(kN), b(kN);
  {
    auto wv = w.view();
    auto bv = b.view();
    for (PetscInt q = 0; q < c->size(); ++q) wv[c->dofs()[q]] = 1.0 + 0.01 * static_cast<double>(q);
    for (PetscInt i = 0; i < kN; ++i) bv[i] = std::sin(0.1 * static_cast<double>(i));
  }
  Eigen::VectorXd we(kN), be(kN);
  for (PetscInt i = 0; i < kN; ++i) {
    we(i) = w.read()[i];
    be(i) = b.read()[i];
  }
  ASSERT_TRUE(c->apply(w, x));
  const Eigen::VectorXd xw = f.inverse * we;
  const double tol = 1e-12 * f.inverse.cwiseAbs().maxCoeff() * static_cast<double>(c->size());
  for (PetscInt i = 0; i < kN; ++i) ASSERT_NEAR(x.read()[i], xw(i), tol) << i;

  // The corrected solve x = A⁻¹(b − E_T w) with zero Dirichlet values: (A⁻¹b)_T after the
  // first call, all of x after the second (b's sum over n entries: n in the tolerance).
  core::Vector y(kN);
  linalg::CorrectedSolve s;
  ASSERT_TRUE(c->begin_corrected(b, y, s));
  EXPECT_TRUE(s.pending());
  const Eigen::VectorXd xb = f.inverse * be;
  const double tol_b = 1e-12 * f.inverse.cwiseAbs().maxCoeff() * static_cast<double>(kN);
  for (PetscInt q = 0; q < c->size(); ++q)
    ASSERT_NEAR(y.read()[c->dofs()[q]], xb(c->dofs()[q]), tol_b) << q;
  ASSERT_TRUE(c->finish_corrected(s, w, y));
  EXPECT_FALSE(s.pending());
  for (PetscInt i = 0; i < kN; ++i) ASSERT_NEAR(y.read()[i], xb(i) - xw(i), tol_b) << i;
}

TEST(Compliance, BlockSolvesOfTheOtherPackagesAreTheDenseInverse) {
  const Fixture f;
  for (const auto& package : linalg::available_cholesky_packages()) {
    if (package == MATSOLVERCHOLMOD) continue;
    const linalg::EliminatedCholesky solver(f.a, f.fixed, package);
    const auto c = solver.compliance(false);
    EXPECT_EQ(c->path(), "block solves") << package;
    expect_dense_inverse(f, solver, *c);
  }
}

TEST(Compliance, TheRecordOfSeveralRestoresEachAndRefusesAnotherBodyCount) {
  const Fixture f;
  const linalg::EliminatedCholesky solver(f.a, f.fixed, MATSOLVERCHOLMOD);
  std::vector<std::unique_ptr<linalg::Compliance>> two, again, one;
  for (int i = 0; i < 2; ++i) {
    two.push_back(solver.compliance(false));
    again.push_back(solver.compliance(false));
  }
  one.push_back(solver.compliance(false));
  two[0]->cover(chunks()[0]);
  two[1]->cover(chunks()[1]);
  two[1]->cover(chunks()[2]);
  std::vector<std::vector<int>> record;
  linalg::save_compliances(two, record);
  ASSERT_EQ(record.size(), 4u);
  linalg::replay_compliances(again, record, "test");
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(again[i]->dofs(), two[i]->dofs());
    EXPECT_TRUE(again[i]->matrix() == two[i]->matrix());
  }
  EXPECT_THROW(linalg::replay_compliances(one, record, "test"), Error);
  record[0].push_back(static_cast<int>(kN));  // a dof the body does not have
  EXPECT_THROW(linalg::replay_compliances(again, record, "test"), Error);
}

}  // namespace
}  // namespace tc::test
