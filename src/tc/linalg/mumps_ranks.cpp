// MUMPS's Cholesky factor of a matrix spread over the ranks (linalg/mumps_ranks.hpp): the
// factorisation with its work-space retry, the solves of replicated vectors and blocks, and
// the selected entries of A⁻¹.
#include "tc/linalg/mumps_ranks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc_blocks.hpp"
#include "tc/core/numeric/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::linalg {

using core::Handle;
using core::KernelThreads;
using core::RowBlocks;
using core::SparseMatrix;
using core::blocks::on_blocks;

MumpsOverRanks::MumpsOverRanks(const SparseMatrix& a, std::span<const PetscInt> eliminated,
                               double diag) {
  auto& r = ranks_;
  r = RowBlocks::over(PETSC_COMM_WORLD, a.rows());
  const int size = static_cast<int>(r.count.size());
  // A matrix spread over the ranks is spread as the factor is (the same rule).
  TC_VERIFY(!a.distributed() ||
                (a.row_blocks().first() == r.first() && a.row_blocks().here() == r.here()),
            "a spread matrix is spread as its factor");
  const PetscInt first = r.first();
  const PetscInt m = r.here();

  // This rank's rows (of the replicated matrix, or its own), global columns, as an MPIAIJ.
  Handle<::Mat, MatDestroy> local;
  {
    // The eliminated rows keep diag alone, the other rows lose the eliminated columns.
    std::vector<char> gone(static_cast<size_t>(r.n), 0);
    for (const PetscInt d : eliminated) gone[static_cast<size_t>(d)] = 1;
    std::vector<PetscInt> offsets(static_cast<size_t>(m) + 1, 0), columns;
    std::vector<PetscScalar> values;
    PetscInt entries = 0;  // reserved exactly: the copy is as large as this rank's rows
    for (PetscInt row = first; row < first + m; ++row) {
      PetscInt nz = 0;
      TC_PETSC(MatGetRow(a.get(), row, &nz, nullptr, nullptr));
      entries += nz;
      TC_PETSC(MatRestoreRow(a.get(), row, &nz, nullptr, nullptr));
    }
    columns.reserve(static_cast<size_t>(entries));
    values.reserve(static_cast<size_t>(entries));
    for (PetscInt i = 0; i < m; ++i) {
      const PetscInt row = first + i;
      if (gone[static_cast<size_t>(row)]) {
        columns.push_back(row);
        values.push_back(diag);
      } else {
        PetscInt nz = 0;
        const PetscInt* cols = nullptr;
        const PetscScalar* vals = nullptr;
        TC_PETSC(MatGetRow(a.get(), row, &nz, &cols, &vals));  // columns in increasing order
        for (PetscInt e = 0; e < nz; ++e)
          if (!gone[static_cast<size_t>(cols[e])]) {
            columns.push_back(cols[e]);
            values.push_back(vals[e]);
          }
        TC_PETSC(MatRestoreRow(a.get(), row, &nz, &cols, &vals));
      }
      offsets[static_cast<size_t>(i) + 1] = static_cast<PetscInt>(columns.size());
    }
    TC_PETSC(MatCreateMPIAIJWithArrays(r.comm, m, m, r.n, r.n, offsets.data(), columns.data(),
                                       values.data(), local.out()));
  }
  TC_PETSC(MatSetOption(local.get(), MAT_SYMMETRIC, PETSC_TRUE));
  TC_PETSC(MatSetOption(local.get(), MAT_SPD, PETSC_TRUE));
  // MUMPS allocates its estimate of the factorisation's work space plus ICNTL(14) per cent
  // (20 % on more than one rank). Cholesky of an SPD matrix delays no pivot, so only the
  // ranks' dynamic scheduling can exceed the estimate: 10 % first (the 200 k-dof ch. 7 case at
  // 2 ranks: 1.50 → 1.43 GiB per rank; 5 % ran out in 4 runs of 5), and when MUMPS reports a
  // work space too small (INFOG(1) −8, −9, −11, −12, −14, −15, −17), once more with 35 %.
  const KernelThreads threads(factorisation_flops(r.n) / size);
  for (const PetscInt relaxation : {10, 35}) {
    ::Mat f = nullptr;
    TC_PETSC(MatGetFactor(local.get(), MATSOLVERMUMPS, MAT_FACTOR_CHOLESKY, &f));
    factor_ = Handle<::Mat, MatDestroy>(f);
    TC_PETSC(MatMumpsSetIcntl(f, 14, relaxation));
    MatFactorInfo info;
    TC_PETSC(MatFactorInfoInitialize(&info));
    TC_PETSC(MatCholeskyFactorSymbolic(f, local.get(), nullptr, &info));
    MatFactorError error = MAT_FACTOR_NOERROR;
    TC_PETSC(MatFactorGetError(f, &error));
    if (error == MAT_FACTOR_NOERROR) {
      TC_PETSC(MatCholeskyFactorNumeric(f, local.get(), &info));
      TC_PETSC(MatFactorGetError(f, &error));
    }
    if (error == MAT_FACTOR_NOERROR) return;
    PetscInt infog1 = 0;
    TC_PETSC(MatMumpsGetInfog(f, 1, &infog1));
    const bool work_space = infog1 == -8 || infog1 == -9 || infog1 == -11 || infog1 == -12 ||
                            infog1 == -14 || infog1 == -15 || infog1 == -17;
    if (work_space && relaxation == 10) continue;
    // Every rank has the same INFOG: a collective error, reported once.
    throw CollectiveError<PetscError>(PetscError(
        PETSC_ERR_LIB, fmt::format("MUMPS Cholesky over {} ranks failed (INFOG(1) = {}{})", size,
                                   infog1, infog1 == -13 ? ": out of memory" : "")));
  }
}

void MumpsOverRanks::solve(::Vec b, ::Vec x) const {
  on_blocks(ranks_, ranks_, b, x,
            [&](::Vec bl, ::Vec xl) { TC_PETSC(MatSolve(factor_.get(), bl, xl)); });
}

void MumpsOverRanks::solve_many(::Mat b, ::Mat x) const {
  const auto& r = ranks_;
  const PetscInt first = r.start[static_cast<size_t>(r.rank)];
  const PetscInt m = r.count[static_cast<size_t>(r.rank)];
  PetscInt n = 0, k = 0;
  TC_PETSC(MatGetSize(b, &n, &k));
  PetscInt ldb = n, ldx = n;
  TC_PETSC(MatDenseGetLDA(b, &ldb));
  TC_PETSC(MatDenseGetLDA(x, &ldx));
  std::vector<PetscScalar> rows(static_cast<size_t>(m * k));
  {
    const PetscScalar* bp = nullptr;
    TC_PETSC(MatDenseGetArrayRead(b, &bp));
    for (PetscInt j = 0; j < k; ++j) std::copy_n(bp + j * ldb + first, m, rows.begin() + j * m);
    TC_PETSC(MatDenseRestoreArrayRead(b, &bp));
  }
  Handle<::Mat, MatDestroy> bl, xl;
  TC_PETSC(MatCreateDense(r.comm, m, PETSC_DECIDE, r.n, k, rows.data(), bl.out()));
  TC_PETSC(MatCreateDense(r.comm, m, PETSC_DECIDE, r.n, k, nullptr, xl.out()));
  TC_PETSC(MatMatSolve(factor_.get(), bl.get(), xl.get()));
  const PetscScalar* mine = nullptr;
  PetscInt ldl = m;
  TC_PETSC(MatDenseGetLDA(xl.get(), &ldl));
  TC_PETSC(MatDenseGetArrayRead(xl.get(), &mine));
  PetscScalar* xp = nullptr;
  TC_PETSC(MatDenseGetArray(x, &xp));
  for (PetscInt j = 0; j < k; ++j) {
    std::copy_n(mine + j * ldl, m, xp + j * ldx + first);
    TC_MPI(MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, xp + j * ldx, r.count.data(),
                          r.start.data(), MPIU_SCALAR, r.comm));
  }
  TC_PETSC(MatDenseRestoreArray(x, &xp));
  TC_PETSC(MatDenseRestoreArrayRead(xl.get(), &mine));
}

// Entries of A⁻¹ by MUMPS's own selected-inverse solve (ICNTL(30)): the sparse right-hand
// sides e_c and the requested rows let it prune both triangular solves to the paths of the
// elimination tree they touch, and no n × k block is formed. MUMPS takes the request on the
// host, as a sparse matrix whose row c lists the rows wanted of column c, and writes the
// entries into its values there; the host then sends them to every rank.
void MumpsOverRanks::selected_inverse(std::span<const PetscInt> cols,
                                      std::span<const PetscInt> rows, double* out) const {
  const auto nr = static_cast<PetscInt>(rows.size());
  const auto nc = static_cast<PetscInt>(cols.size());
  std::fill_n(out, nr * nc, 0.0);
  auto distinct = [](std::span<const PetscInt> ids) {  // those ≥ 0, sorted, each once
    std::vector<PetscInt> out;
    for (const PetscInt i : ids)
      if (i >= 0) out.push_back(i);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  };
  const auto wanted = distinct(rows);  // the pattern of each request row
  const auto asked = distinct(cols);
  const auto w = static_cast<PetscInt>(wanted.size());
  const auto a = static_cast<PetscInt>(asked.size());
  if (w == 0 || a == 0) return;

  std::vector<PetscInt> at(rows.size(), -1);  // each row's place in `wanted`
  for (PetscInt i = 0; i < nr; ++i)
    if (rows[i] >= 0)
      at[i] = std::lower_bound(wanted.begin(), wanted.end(), rows[i]) - wanted.begin();
  std::vector<PetscInt> place(cols.size(), -1);  // each column's place in `asked`
  for (PetscInt j = 0; j < nc; ++j)
    if (cols[j] >= 0)
      place[j] = std::lower_bound(asked.begin(), asked.end(), cols[j]) - asked.begin();
  // In chunks of columns: the request and its entries, |chunk| × |wanted| each, are held on
  // the host (and MUMPS copies the request), so their memory no longer grows with the columns
  // asked at once (the ch. 7 case ×5.3 on 4 ranks: the dual set-up's rise of a rank's peak
  // 0.56 → 0.43 GiB, its time the same). 1024 columns are four of MUMPS's blocks of 256
  // (ICNTL 27).
  constexpr PetscInt chunk = 1024;
  std::vector<double> entries;
  for (PetscInt q0 = 0; q0 < a; q0 += chunk) {
    const PetscInt q1 = std::min(a, q0 + chunk);
    inverse_entries_chunk(std::span(asked).subspan(q0, q1 - q0), wanted, entries);
    for (PetscInt j = 0; j < nc; ++j) {
      const PetscInt q = place[j];
      if (q < q0 || q >= q1) continue;
      for (PetscInt i = 0; i < nr; ++i)
        if (at[i] >= 0) out[i + j * nr] = entries[static_cast<size_t>((q - q0) * w + at[i])];
    }
  }
}

void MumpsOverRanks::inverse_entries_chunk(std::span<const PetscInt> asked,
                                           std::span<const PetscInt> wanted,
                                           std::vector<double>& entries) const {
  const auto& r = ranks_;
  const auto w = static_cast<PetscInt>(wanted.size());
  const auto a = static_cast<PetscInt>(asked.size());
  // The request, all of it on the host (rank 0): rows and columns 0..n-1 there, none elsewhere.
  const bool host = r.rank == 0;
  const PetscInt mine = host ? r.n : 0;
  std::vector<PetscInt> offsets(static_cast<size_t>(mine) + 1, 0), columns;
  std::vector<PetscScalar> values;
  if (host) {
    for (const PetscInt c : asked) offsets[static_cast<size_t>(c) + 1] = w;
    for (PetscInt i = 0; i < r.n; ++i)
      offsets[static_cast<size_t>(i) + 1] += offsets[static_cast<size_t>(i)];
    columns.reserve(static_cast<size_t>(a * w));
    for (PetscInt q = 0; q < a; ++q) columns.insert(columns.end(), wanted.begin(), wanted.end());
    values.assign(columns.size(), 0.0);
  }
  Handle<::Mat, MatDestroy> request, transposed;
  TC_PETSC(MatCreateMPIAIJWithArrays(r.comm, mine, mine, r.n, r.n, offsets.data(), columns.data(),
                                     values.data(), request.out()));
  TC_PETSC(MatCreateTranspose(request.get(), transposed.out()));
  // The request sets MUMPS's right-hand side and solution formats (ICNTL 20, 21) and its
  // selected-inverse mode (30) and leaves them set: restored for the ordinary solves after.
  // Its columns go in blocks of 256 (ICNTL 27, MUMPS's default 32): the ch. 7 case ×3 at 2
  // ranks, first dual set-up 5.06 → 3.36 s (8: 9.35 s, 64: 4.08 s, 1024: 3.25 s).
  constexpr std::array<int, 4> kept{20, 21, 27, 30};
  std::array<PetscInt, 4> saved{};
  for (size_t q = 0; q < kept.size(); ++q)
    TC_PETSC(MatMumpsGetIcntl(factor_.get(), kept[q], &saved[q]));
  TC_PETSC(MatMumpsSetIcntl(factor_.get(), 27, 256));
  TC_PETSC(MatMumpsGetInverse(factor_.get(), transposed.get()));
  for (size_t q = 0; q < kept.size(); ++q)
    TC_PETSC(MatMumpsSetIcntl(factor_.get(), kept[q], saved[q]));

  entries.assign(static_cast<size_t>(a * w), 0.0);  // column q of `asked`, row of `wanted`
  if (host) {
    ::Mat diagonal = nullptr;  // the host's rows and columns: all of the request
    TC_PETSC(MatMPIAIJGetSeqAIJ(request.get(), &diagonal, nullptr, nullptr));
    const PetscScalar* v = nullptr;
    TC_PETSC(MatSeqAIJGetArrayRead(diagonal, &v));
    std::copy_n(v, entries.size(), entries.begin());
    TC_PETSC(MatSeqAIJRestoreArrayRead(diagonal, &v));
  }
  TC_MPI(MPI_Bcast(entries.data(), static_cast<int>(entries.size()), MPI_DOUBLE, 0, r.comm));
}

}  // namespace tc::linalg
