#include "tc/physics/constrained_solver.hpp"

namespace tc::physics {

ConstrainedSolver::ConstrainedSolver(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                                     const std::string& package)
    : a_(a.share()), dofs_(std::move(dofs)), diag_(core::mean_diagonal(a)), reduced_(a.copy()) {
  reduced_.zero_rows_columns(dofs_, diag_);
  factor_ = core::CholeskySolver(reduced_, package);
  lift_ = core::Vector(a.rows());
  rhs_ = core::Vector(a.rows());
}

ConstrainedSolver::ConstrainedSolver(std::unique_ptr<feti::Feti> feti) : feti_(std::move(feti)) {}
ConstrainedSolver::~ConstrainedSolver() = default;
ConstrainedSolver::ConstrainedSolver(ConstrainedSolver&&) noexcept = default;

void ConstrainedSolver::solve_homogeneous_many(::Mat b, ::Mat x) const {
  if (feti_) {
    feti_->solve_homogeneous_many(b, x);
    return;
  }
  if (!dofs_.empty())
    TC_PETSC(
        MatZeroRows(b, static_cast<PetscInt>(dofs_.size()), dofs_.data(), 0.0, nullptr, nullptr));
  factor_.solve_many(b, x);
}

void ConstrainedSolver::solve(const core::Vector& b, core::Vector& x) const {
  if (feti_) {
    feti_->solve(b, x);
    return;
  }
  if (dofs_.empty()) {
    factor_.solve(b, x);
    return;
  }
  lift_.zero();
  {
    auto xv = x.view();
    auto lv = lift_.view();
    for (const PetscInt d : dofs_) lv[d] = xv[d];
  }
  a_.mult(lift_, rhs_);  // rhs = b − A·lift on the free rows
  rhs_.scale(-1.0);
  rhs_.axpy(1.0, b);
  {
    auto rv = rhs_.view();
    auto lv = lift_.view();
    for (const PetscInt d : dofs_) rv[d] = diag_ * lv[d];
  }
  factor_.solve(rhs_, x);
}

}  // namespace tc::physics
