#pragma once
// A x = b with x prescribed on a fixed set of dofs (Dirichlet data, 2.2 and 2.9) by symmetric
// elimination: the reduced matrix (rows and columns of the constrained dofs replaced by a
// scaled identity) is factorised once; each solve lifts the prescribed values to the
// right-hand side. The constrained set must not change over the run; their values may.
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholesky_solver.hpp"

namespace tc::linalg {

class Compliance;

class EliminatedCholesky {
 public:
  /// `ranks`: FactorRanks::all_ranks spreads the factor over the ranks (MUMPS; every method is
  /// then collective), as CholeskySolver says.
  EliminatedCholesky(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                     const std::string& package, FactorRanks ranks = FactorRanks::this_rank);
  /// The same consuming `a` (CholeskySolver's consuming constructor): the factor's peak holds
  /// no copy of the operator.
  EliminatedCholesky(core::SparseMatrix&& a, std::vector<PetscInt> dofs, const std::string& package,
                     FactorRanks ranks = FactorRanks::this_rank);

  /// On entry x holds the prescribed values at the constrained dofs (other entries are
  /// ignored); on exit x solves the equations of the free dofs.
  void solve(const core::Vector& b, core::Vector& x) const;
  /// X = A⁻¹B with zero prescribed values, for k right-hand sides at once (dense n × k; the
  /// constrained rows of B are zeroed in place).
  void solve_homogeneous_many(::Mat b, ::Mat x) const;
  /// The right-hand side with the prescribed values x_D lifted (symmetric elimination): the
  /// one the factor solves in solve(). Valid until the next call of solve() or lifted().
  [[nodiscard]] const core::Vector& lifted(const core::Vector& b, const core::Vector& x) const;
  /// `dofs` with the constrained ones replaced by −1: the elimination decouples them, their
  /// rows and columns of A⁻¹ are zero.
  [[nodiscard]] std::vector<PetscInt> free_or_none(std::span<const PetscInt> dofs) const;
  /// The compliance (A⁻¹)_TT on this solver's factor by the best path its package has
  /// (linalg/compliance.hpp): CHOLMOD's supernodal solves, MUMPS's selected inverse over the
  /// ranks (its rows dealt over them with `rows_over_ranks`), or block solves.
  [[nodiscard]] std::unique_ptr<Compliance> compliance(bool rows_over_ranks) const;
  [[nodiscard]] const CholeskySolver& factor() const { return factor_; }
  [[nodiscard]] PetscInt size() const { return n_; }
  /// The constrained dofs, sorted.
  [[nodiscard]] const std::vector<PetscInt>& dofs() const { return dofs_; }

 private:
  // Sorts dofs_ and keeps A(:, D) on the free rows (the lifting).
  void keep_lifting(const core::SparseMatrix& a);

  std::vector<PetscInt> dofs_;
  // A(:, D) on the free rows, column by column (CSC): the lifting b − A·x_D touches only
  // these entries (a full product with A cost 3.6 % of the ch. 7 example, where x_D = 0 on
  // the clamped body and |D| is a face).
  std::vector<PetscInt> lift_start_, lift_row_;
  std::vector<double> lift_value_;
  double diag_ = 1.0;  // of the constrained rows: the mean diagonal keeps the scale uniform
  PetscInt n_ = 0;
  CholeskySolver factor_;
  mutable core::Vector lift_, rhs_;
};

}  // namespace tc::linalg
