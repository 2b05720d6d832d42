#pragma once
// Solves A x = b with x prescribed on a fixed set of dofs (Dirichlet data, 2.2 and 2.9): by
// symmetric elimination and a factorisation done once (linalg::EliminatedCholesky), or, for a
// body cut into subdomains, by Total FETI (feti::Feti, 6.2) with the same contract: callers do
// not know which one they have.
#include <memory>
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/feti/feti.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/linalg/eliminated_cholesky.hpp"

namespace tc::physics {

class ConstrainedSolver {
 public:
  /// `ranks`: linalg::FactorRanks::all_ranks spreads the factor over the ranks (MUMPS; every
  /// method is then collective), as linalg::CholeskySolver says.
  ConstrainedSolver(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                    const std::string& package,
                    linalg::FactorRanks ranks = linalg::FactorRanks::this_rank);
  /// The same consuming `a` (linalg::CholeskySolver's consuming constructor): the factor's peak
  /// holds no copy of the operator.
  ConstrainedSolver(core::SparseMatrix&& a, std::vector<PetscInt> dofs, const std::string& package,
                    linalg::FactorRanks ranks = linalg::FactorRanks::this_rank);
  /// The same system solved by FETI over subdomains (the FETI object owns the Dirichlet dofs).
  explicit ConstrainedSolver(std::unique_ptr<feti::Feti> feti);
  ~ConstrainedSolver();
  ConstrainedSolver(ConstrainedSolver&&) noexcept;

  /// Replaces the direct factor by one of `a` (same constrained dofs, package and ranks):
  /// A_u after E(θ), ν(θ) moved K_u. Every compliance of this solver is then stale
  /// (DualContactSolver::refactorised). Not for FETI (refused by `check`).
  void refactorise(core::SparseMatrix&& a);
  /// On entry x holds the prescribed values at the constrained dofs (other entries are
  /// ignored); on exit x solves the equations of the free dofs.
  void solve(const core::Vector& b, core::Vector& x) const;
  /// X = A⁻¹B with zero prescribed values, for k right-hand sides at once (dense n × k; the
  /// constrained rows of B are zeroed in place).
  void solve_homogeneous_many(::Mat b, ::Mat x) const;
  /// The compliance (A⁻¹)_TT of this system on `n_dofs` dofs (linalg/compliance.hpp): the
  /// direct factor's best path, or FETI's block solves (all columns in one block PCG). With
  /// `rows_over_ranks` and a factor spread over the ranks (unit_rows_at_once), S's rows are
  /// dealt over the ranks. It must not outlive this solver.
  [[nodiscard]] std::unique_ptr<linalg::Compliance> compliance(PetscInt n_dofs,
                                                               bool rows_over_ranks = false) const;
  [[nodiscard]] const std::string& package() const {
    return feti_ ? feti_->package() : direct_->factor().package();
  }
  /// Whether the compliance's columns come from MUMPS's selected inverse over the ranks, which
  /// prunes its solves by itself and can deal S's rows over the ranks.
  [[nodiscard]] bool unit_rows_at_once() const { return !feti_ && direct_->factor().distributed(); }
  /// The FETI solver when the body is decomposed, else null.
  [[nodiscard]] const feti::Feti* feti() const { return feti_.get(); }

 private:
  std::unique_ptr<linalg::EliminatedCholesky> direct_;
  linalg::FactorRanks ranks_ = linalg::FactorRanks::this_rank;  // of direct_
  std::unique_ptr<feti::Feti> feti_;
};

/// The compliance of a body cut into subdomains: its columns by FETI's block solves (each block
/// of 64 unit columns in one block PCG, to FETI's tolerance, not to round-off).
class FetiCompliance final : public linalg::BlockCompliance {
 public:
  FetiCompliance(const feti::Feti& feti, PetscInt n_dofs);
};

}  // namespace tc::physics
