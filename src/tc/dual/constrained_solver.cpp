#include "tc/dual/constrained_solver.hpp"

#include "tc/core/verify.hpp"

namespace tc::physics {

ConstrainedSolver::ConstrainedSolver(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                                     const std::string& package, linalg::FactorRanks ranks)
    : direct_(std::make_unique<linalg::EliminatedCholesky>(a, std::move(dofs), package, ranks)),
      ranks_(ranks) {}

ConstrainedSolver::ConstrainedSolver(core::SparseMatrix&& a, std::vector<PetscInt> dofs,
                                     const std::string& package, linalg::FactorRanks ranks)
    : direct_(std::make_unique<linalg::EliminatedCholesky>(std::move(a), std::move(dofs), package,
                                                           ranks)),
      ranks_(ranks) {}

ConstrainedSolver::ConstrainedSolver(std::unique_ptr<feti::Feti> feti) : feti_(std::move(feti)) {}
ConstrainedSolver::~ConstrainedSolver() = default;
ConstrainedSolver::ConstrainedSolver(ConstrainedSolver&&) noexcept = default;

void ConstrainedSolver::refactorise(core::SparseMatrix&& a) {
  TC_VERIFY(!feti_, "refactorise: a direct factor (FETI bodies keep constant moduli)");
  auto dofs = direct_->dofs();
  const auto package = direct_->factor().package();
  direct_.reset();  // the old factor freed before the new one is computed: one at the peak
  direct_ =
      std::make_unique<linalg::EliminatedCholesky>(std::move(a), std::move(dofs), package, ranks_);
}

void ConstrainedSolver::solve_homogeneous_many(::Mat b, ::Mat x) const {
  if (feti_)
    feti_->solve_homogeneous_many(b, x);
  else
    direct_->solve_homogeneous_many(b, x);
}

void ConstrainedSolver::solve(const core::Vector& b, core::Vector& x) const {
  if (feti_)
    feti_->solve(b, x);
  else
    direct_->solve(b, x);
}

std::unique_ptr<linalg::Compliance> ConstrainedSolver::compliance(PetscInt n_dofs,
                                                                  bool rows_over_ranks) const {
  if (!feti_) {
    TC_VERIFY(n_dofs == direct_->size(), "a compliance on the factor's dofs");
    return direct_->compliance(rows_over_ranks);
  }
  return std::make_unique<FetiCompliance>(*feti_, n_dofs);
}

FetiCompliance::FetiCompliance(const feti::Feti& feti, PetscInt n_dofs)
    : BlockCompliance(
          n_dofs, [&feti](::Mat b, ::Mat x) { feti.solve_homogeneous_many(b, x); }, "feti") {}

}  // namespace tc::physics
