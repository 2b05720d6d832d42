#pragma once
// MUMPS's Cholesky factor of one matrix spread over the ranks of PETSC_COMM_WORLD, each rank
// holding its part: CholeskySolver's DirectFactor for a body shared by the ranks, and the
// selected entries of A⁻¹ of the compliance over the ranks (MumpsCompliance). Private to linalg.
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::linalg {

/// The work of factorising n rows, for the thread policy: n², nested dissection's flops for a
/// 3D body (a 2D body's n^1.5 are fewer: it may get threads it could do without, never the
/// reverse). 10⁴ rows (a 3D body's 0.4 s on one core) sit at the threshold.
[[nodiscard]] double factorisation_flops(PetscInt n);

/// Every call is collective, with the same arguments on every rank; vectors and blocks are
/// replicated, each rank giving the factor its rows (RowBlocks::over) and gathering the result.
class MumpsOverRanks final : public DirectFactor {
 public:
  /// The factor of `a` (whole on every rank, or spread as the factor is) with the rows and
  /// columns of the sorted `eliminated` replaced by diag·I, each rank taking its rows.
  explicit MumpsOverRanks(const core::SparseMatrix& a, std::span<const PetscInt> eliminated = {},
                          double diag = 1.0);
  void solve(::Vec b, ::Vec x) const override;
  void solve_many(::Mat b, ::Mat x) const override;
  /// out(i, j) = (A⁻¹ e_c)[rows[i]] for c = cols[j] (−1: a zero column), column-major
  /// |rows| × |cols|: CholeskySolver::selected_inverse.
  void selected_inverse(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                        double* out) const;
  [[nodiscard]] MPI_Comm comm() const { return ranks_.comm; }

 private:
  // Entries (A⁻¹)(wanted, asked), column-major, on every rank: one MUMPS request.
  void inverse_entries_chunk(std::span<const PetscInt> asked, std::span<const PetscInt> wanted,
                             std::vector<double>& entries) const;

  core::Handle<::Mat, MatDestroy> factor_;  // MUMPS's factored matrix
  core::RowBlocks ranks_;
};

}  // namespace tc::linalg
