// A factor spread over the ranks (linalg::CholeskySolver with FactorRanks::all_ranks: MUMPS over
// PETSC_COMM_WORLD) against the same matrix factorised on each rank alone: its solves, its
// block solves, its selected entries of A⁻¹, and the Dirichlet-constrained solver and the
// contact compliance built on them (whole on every rank, or its rows dealt over the ranks). Run at
// 1 and 2 ranks (label mpi): at 1 rank both factors are the rank's own, at 2 the first is MUMPS's
// over both ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "support/vectors.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::test {
namespace {

int world_size() {
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  return size;
}

// The 7-point Laplacian of an n³ grid plus 0.05 on the diagonal, with the entries of one
// unknown scaled by its (uneven) weight: SPD, κ ≈ 250, every row different, so that a row or
// column taken from the wrong place shows.
core::SparseMatrix grid_operator(int n) {
  const PetscInt size = n * n * n;
  std::vector<PetscInt> nnz(static_cast<size_t>(size), 7);
  core::SparseMatrix a(size, size, nnz);
  auto id = [n](int i, int j, int k) { return static_cast<PetscInt>(i + n * (j + n * k)); };
  auto weight = [](PetscInt r) { return 1.0 + 0.5 * std::sin(0.37 * static_cast<double>(r)); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const PetscInt r = id(i, j, k);
        std::vector<std::pair<PetscInt, double>> row{{r, 6.05 * weight(r) * weight(r)}};
        const int step[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (const auto& s : step)
          for (const int sign : {-1, 1}) {
            const int ii = i + sign * s[0], jj = j + sign * s[1], kk = k + sign * s[2];
            if (ii < 0 || jj < 0 || kk < 0 || ii >= n || jj >= n || kk >= n) continue;
            const PetscInt c = id(ii, jj, kk);
            row.emplace_back(c, -weight(r) * weight(c));
          }
        std::sort(row.begin(), row.end());
        for (const auto& [c, v] : row) a.add_values(std::span(&r, 1), std::span(&c, 1), &v);
      }
  a.assemble();
  return a;
}

// Both factors are direct, each exact to a backward error of a few ε: their solutions differ
// by about κ·ε‖x‖ ≈ 250 · 2.2e-16 · ‖x‖ ≈ 6e-14‖x‖; 1e-11 leaves a margin of 100 and still
// fails for any misplaced row, column or rank block (errors of order ‖x‖).
constexpr double kTolerance = 1e-11;

TEST(CholeskyOverRanks, SolvesAsTheRanksOwnFactor) {
  const auto a = grid_operator(11);
  const linalg::CholeskySolver spread(a, "", linalg::FactorRanks::all_ranks);
  const linalg::CholeskySolver own(a, "", linalg::FactorRanks::this_rank);
  EXPECT_EQ(spread.distributed(), world_size() > 1);
  EXPECT_FALSE(own.distributed());
  for (const double phase : {0.0, 1.3}) {
    const auto b = some_vector(a.rows(), phase);
    core::Vector x(a.rows()), y(a.rows());
    spread.solve(b, x);
    own.solve(b, y);
    EXPECT_LT(max_abs_diff(x, y), kTolerance * y.max_abs());
    // The same answer on every rank: the replicated result is gathered whole.
    double here = x.max_abs(), low = 0, high = 0;
    MPI_Allreduce(&here, &low, 1, MPI_DOUBLE, MPI_MIN, PETSC_COMM_WORLD);
    MPI_Allreduce(&here, &high, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
    EXPECT_EQ(low, high);
  }
}

TEST(CholeskyOverRanks, BlockSolvesAndSelectedInverseEntriesAgreeWithColumnSolves) {
  const auto a = grid_operator(9);
  const PetscInt n = a.rows();
  const linalg::CholeskySolver spread(a, "", linalg::FactorRanks::all_ranks);
  const linalg::CholeskySolver own(a, "", linalg::FactorRanks::this_rank);
  // Columns in no order, one repeated and one absent (−1: a zero column); rows likewise.
  const std::vector<PetscInt> cols{17, 3, 700, -1, 3, 452};
  const std::vector<PetscInt> rows{0, 452, 17, 728, 3, 100, 17};
  const auto k = static_cast<PetscInt>(cols.size());
  core::Handle<::Mat, MatDestroy> b, x;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, b.out()));
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, x.out()));
  {
    PetscScalar* p = nullptr;
    TC_PETSC(MatDenseGetArray(b.get(), &p));
    std::fill_n(p, n * k, 0.0);
    for (PetscInt j = 0; j < k; ++j)
      if (cols[static_cast<size_t>(j)] >= 0) p[j * n + cols[static_cast<size_t>(j)]] = 1.0;
    TC_PETSC(MatDenseRestoreArray(b.get(), &p));
  }
  TC_PETSC(MatAssemblyBegin(b.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(b.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyBegin(x.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(x.get(), MAT_FINAL_ASSEMBLY));
  spread.solve_many(b.get(), x.get());

  std::vector<double> entries(rows.size() * cols.size(), -99.0);
  if (spread.distributed()) spread.selected_inverse(cols, rows, entries.data());
  const PetscScalar* xp = nullptr;
  TC_PETSC(MatDenseGetArrayRead(x.get(), &xp));
  for (size_t j = 0; j < cols.size(); ++j) {
    core::Vector e(n), column(n);
    if (cols[j] >= 0) e.view()[cols[j]] = 1.0;
    own.solve(e, column);
    const auto c = column.read();
    const double scale = column.max_abs() > 0 ? column.max_abs() : 1.0;
    for (PetscInt i = 0; i < n; ++i)
      ASSERT_NEAR(xp[static_cast<PetscInt>(j) * n + i], c[i], kTolerance * scale) << j << " " << i;
    if (!spread.distributed()) continue;
    for (size_t i = 0; i < rows.size(); ++i)
      EXPECT_NEAR(entries[i + j * rows.size()], c[rows[i]], kTolerance * scale) << i << ", " << j;
  }
  TC_PETSC(MatDenseRestoreArrayRead(x.get(), &xp));
}

TEST(CholeskyOverRanks, SelectedInverseEntriesOfMoreColumnsThanOneRequestHolds) {
  // 1 200 columns: MUMPS is asked for them in two requests (chunks of 1024 columns), whose
  // entries must land in their own columns of the answer.
  const auto a = grid_operator(11);
  const PetscInt n = a.rows();
  const linalg::CholeskySolver spread(a, "", linalg::FactorRanks::all_ranks);
  const linalg::CholeskySolver own(a, "", linalg::FactorRanks::this_rank);
  if (!spread.distributed()) GTEST_SKIP() << "one rank: no selected inverse";
  std::vector<PetscInt> cols;
  for (PetscInt c = n - 1; c >= n - 1200; --c) cols.push_back(c);  // descending
  const std::vector<PetscInt> rows{0, n - 1, 500, n - 1200, 1024};
  std::vector<double> entries(rows.size() * cols.size(), -99.0);
  spread.selected_inverse(cols, rows, entries.data());
  for (size_t j = 0; j < cols.size(); j += 7) {  // every 7th column: both chunks, any offset
    core::Vector e(n), column(n);
    e.view()[cols[j]] = 1.0;
    own.solve(e, column);
    const auto c = column.read();
    for (size_t i = 0; i < rows.size(); ++i)
      ASSERT_NEAR(entries[i + j * rows.size()], c[rows[i]], kTolerance * column.max_abs())
          << i << ", " << j;
  }
}

TEST(CholeskyOverRanks, ConstrainedSolverAndComplianceAgreeWithTheRanksOwn) {
  const auto a = grid_operator(10);
  const PetscInt n = a.rows();
  std::vector<PetscInt> fixed;  // the face k = 0, as a clamped face
  for (PetscInt r = 0; r < 100; ++r) fixed.push_back(r);
  const physics::ConstrainedSolver spread(a, fixed, "", linalg::FactorRanks::all_ranks);
  const physics::ConstrainedSolver own(a, fixed, "", linalg::FactorRanks::this_rank);
  EXPECT_EQ(spread.unit_rows_at_once(), world_size() > 1);

  auto b = some_vector(n, 0.4);
  core::Vector x(n), y(n);
  for (const PetscInt d : fixed) x.view()[d] = y.view()[d] = 0.01 * static_cast<double>(d);
  spread.solve(b, x);
  own.solve(b, y);
  EXPECT_LT(max_abs_diff(x, y), kTolerance * y.max_abs());

  // The compliance on a growing set T (the top face, then part of a side, with a fixed dof
  // among them), as the contact dual grows it.
  const auto spread_compliance = spread.compliance(n), own_compliance = own.compliance(n);
  auto& s_spread = *spread_compliance;
  auto& s_own = *own_compliance;
  EXPECT_EQ(s_spread.path() == "mumps selected inverse", world_size() > 1) << s_spread.path();
  std::vector<PetscInt> top, side{5, 215, 425, 635};
  for (PetscInt r = 900; r < 1000; r += 3) top.push_back(r);
  for (auto* s : {&s_spread, &s_own}) {
    s->cover(top);
    s->cover(side);
  }
  ASSERT_EQ(s_spread.dofs(), s_own.dofs());
  const double scale = s_own.matrix().cwiseAbs().maxCoeff();
  EXPECT_LT((s_spread.matrix() - s_own.matrix()).cwiseAbs().maxCoeff(), kTolerance * scale);
  EXPECT_EQ(s_spread.matrix(), s_spread.matrix().transpose());  // exactly symmetric

  // Its rows dealt over the ranks: each rank keeps the rows q ≡ rank (mod ranks) of the same
  // columns, and the new block's means are taken the same way, so that the rows gathered are
  // s_spread's S to the bit. On one rank (or a rank's own factor) S stays whole.
  const auto rows_compliance = spread.compliance(n, true);
  auto& s_rows = *rows_compliance;
  s_rows.cover(top);
  s_rows.cover(side);
  EXPECT_EQ(s_rows.rows_spread(), world_size() > 1);
  const auto t = s_spread.matrix().rows();
  ASSERT_EQ(s_rows.matrix().cols(), t);
  ASSERT_EQ(s_rows.matrix().rows(), static_cast<Eigen::Index>(s_rows.rows().size()));
  Eigen::MatrixXd gathered = Eigen::MatrixXd::Zero(t, t);
  for (size_t j = 0; j < s_rows.rows().size(); ++j) {
    const auto q = static_cast<Eigen::Index>(s_rows.rows()[j]);
    EXPECT_EQ(s_rows.row_of(q), static_cast<PetscInt>(j));
    gathered.row(q) = s_rows.matrix().row(static_cast<Eigen::Index>(j));
  }
  MPI_Allreduce(MPI_IN_PLACE, gathered.data(), static_cast<int>(t * t), MPI_DOUBLE, MPI_SUM,
                PETSC_COMM_WORLD);  // each row from one rank, zeros from the others: exact
  EXPECT_EQ(gathered, s_spread.matrix());
  const auto s_whole = own.compliance(n, true);  // a rank's own factor: nothing to deal
  EXPECT_FALSE(s_whole->rows_spread());
}

}  // namespace
}  // namespace tc::test
