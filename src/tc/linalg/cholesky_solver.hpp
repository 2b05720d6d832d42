#pragma once
// A direct Cholesky factorisation of an SPD matrix, done once and solved many times, through one
// class over the packages (as MFEM's linalg/ puts each package behind its Solver): a
// DirectFactor per package — CHOLMOD through its own API (linalg/cholmod/cholmod_factor.hpp),
// MUMPS or PETSc's own through PETSc on this rank, MUMPS spread over the ranks
// (linalg/mumps_ranks.hpp) — chosen by CholeskySolver.
#include <petscksp.h>

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholmod/cholmod_factor.hpp"

namespace tc::linalg {

class MumpsOverRanks;  // mumps_ranks.hpp

/// One package's factor of an SPD matrix: the solves every package has. Over the ranks b and x
/// are replicated and the calls collective.
class DirectFactor {
 public:
  virtual ~DirectFactor();
  /// x = A⁻¹b (b and x distinct).
  virtual void solve(::Vec b, ::Vec x) const = 0;
  /// X = A⁻¹B for dense B and X (n × k, column-major, PETSc MATSEQDENSE): one
  /// multi-right-hand-side solve, which the packages do with level-3 BLAS.
  virtual void solve_many(::Mat b, ::Mat x) const = 0;
};

/// Where a factor lives: on the calling rank alone, or spread over the ranks of
/// PETSC_COMM_WORLD.
enum class FactorRanks { this_rank, all_ranks };

/// A direct Cholesky factorisation of an SPD SparseMatrix, done once, solved many times.
/// The package is "mumps", "cholmod" or "petsc" (PETSc's MatSolverType names); it may be
/// overridden with the PETSc option -tc_factor_package. CHOLMOD on one rank is called through
/// SuiteSparse's public API (CholmodFactor), the others through PETSc.
///
/// With FactorRanks::all_ranks on more than one rank, and the package MUMPS or left to the
/// solver, or with a matrix whose rows are spread over the ranks (SparseMatrix::over_ranks),
/// the matrix (whole on every rank, or spread) is factorised once by MUMPS over all ranks,
/// each holding its part of the factor, instead of once per rank: every method is then
/// collective, called by every rank with the same arguments, and returns the same replicated
/// result on each.
class CholeskySolver {
 public:
  CholeskySolver() = default;
  explicit CholeskySolver(const core::SparseMatrix& a, const std::string& package = "",
                          FactorRanks ranks = FactorRanks::this_rank);
  /// The factor of `a` with the rows and columns of the sorted `eliminated` replaced by
  /// diag·I (symmetric elimination of Dirichlet dofs), without a whole copy of `a` when the
  /// factor is spread over the ranks (each rank takes its rows, eliminated on the way).
  CholeskySolver(const core::SparseMatrix& a, std::span<const PetscInt> eliminated, double diag,
                 const std::string& package, FactorRanks ranks);
  /// The same consuming `a`: eliminated in place (no copy), and with CHOLMOD freed as soon as
  /// CHOLMOD holds its triangle, before the numeric factorisation, so that the factor's peak
  /// holds no whole copy of the operator (the same factor, the same bits).
  CholeskySolver(core::SparseMatrix&& a, std::span<const PetscInt> eliminated, double diag,
                 const std::string& package, FactorRanks ranks);
  void solve(const core::Vector& b, core::Vector& x) const;
  void solve_raw(::Vec b, ::Vec x) const;  // the same on bare PETSc vectors
  /// X = A⁻¹B for dense B and X (n × k, column-major, PETSc MATSEQDENSE): one multi-right-hand
  /// side solve, which the factorisation packages do with level-3 BLAS.
  void solve_many(::Mat b, ::Mat x) const;
  /// Entries of A⁻¹ with the factor spread over the ranks (distributed()): out(i, j) =
  /// (A⁻¹ e_c)[rows[i]] for c = cols[j] (−1: a zero column), column-major |rows| × |cols|, by
  /// MUMPS's selected inverse (its solves pruned to the paths of the elimination tree the
  /// unit columns and the rows touch), to round-off, any number of columns at once; collective.
  void selected_inverse(std::span<const PetscInt> cols, std::span<const PetscInt> rows,
                        double* out) const;
  /// CHOLMOD's factor when the package is CHOLMOD on this rank, else null: its supernodal
  /// solves serve the CHOLMOD compliance (linalg/compliance.hpp).
  [[nodiscard]] const CholmodFactor* cholmod() const { return cholmod_; }
  [[nodiscard]] const std::string& package() const { return package_; }
  /// Whether the factor is spread over the ranks (see the class comment).
  [[nodiscard]] bool distributed() const { return ranks_ != nullptr; }

 private:
  // Resolves package_ too; a matrix spread over the ranks is factorised there.
  [[nodiscard]] bool spread_over_ranks(FactorRanks ranks, bool spread_matrix);
  // Holds f, and what it is (CHOLMOD's, or MUMPS's over the ranks).
  void keep(std::shared_ptr<const DirectFactor> f);

  std::shared_ptr<const DirectFactor> factor_;
  const CholmodFactor* cholmod_ = nullptr;  // factor_'s CHOLMOD factor, when CHOLMOD's
  const MumpsOverRanks* ranks_ = nullptr;   // factor_, when spread over the ranks
  std::string package_;
};

/// The factorisation packages this PETSc build offers for Cholesky on sequential AIJ.
[[nodiscard]] std::vector<std::string> available_cholesky_packages();
/// The package named by the PETSc option -tc_factor_package, or "" when it is not set.
[[nodiscard]] std::string requested_factor_package();
/// The ranks an undecomposed body's factor is spread over (CholeskySolver with
/// FactorRanks::all_ranks) for the case's `package` ("" automatic; -tc_factor_package
/// overrides it): every rank of PETSC_COMM_WORLD with MUMPS or the automatic choice, else 1.
[[nodiscard]] int ranks_sharing_a_factor(const std::string& package);

}  // namespace tc::linalg
