#include "tc/linalg/eliminated_cholesky.hpp"

#include <algorithm>

namespace tc::linalg {

EliminatedCholesky::EliminatedCholesky(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                                       const std::string& package, FactorRanks ranks)
    : dofs_(std::move(dofs)), diag_(core::mean_diagonal(a)), n_(a.rows()) {
  keep_lifting(a);
  factor_ = CholeskySolver(a, dofs_, diag_, package, ranks);
  lift_ = core::Vector(n_);
  rhs_ = core::Vector(n_);
}

EliminatedCholesky::EliminatedCholesky(core::SparseMatrix&& a, std::vector<PetscInt> dofs,
                                       const std::string& package, FactorRanks ranks)
    : dofs_(std::move(dofs)), diag_(core::mean_diagonal(a)), n_(a.rows()) {
  keep_lifting(a);
  factor_ = CholeskySolver(std::move(a), dofs_, diag_, package, ranks);
  lift_ = core::Vector(n_);
  rhs_ = core::Vector(n_);
}

std::vector<PetscInt> EliminatedCholesky::free_or_none(std::span<const PetscInt> dofs) const {
  std::vector<PetscInt> out(dofs.begin(), dofs.end());
  for (auto& d : out)
    if (std::binary_search(dofs_.begin(), dofs_.end(), d)) d = -1;
  return out;
}

void EliminatedCholesky::keep_lifting(const core::SparseMatrix& a) {
  std::sort(dofs_.begin(), dofs_.end());  // the lifting sums in column order, as MatMult
  dofs_.erase(std::unique(dofs_.begin(), dofs_.end()), dofs_.end());
  std::vector<PetscInt> position(static_cast<size_t>(a.rows()), -1);
  for (size_t k = 0; k < dofs_.size(); ++k)
    position[static_cast<size_t>(dofs_[k])] = static_cast<PetscInt>(k);
  std::vector<std::vector<std::pair<PetscInt, double>>> columns(dofs_.size());
  for (PetscInt r = 0; r < a.rows(); ++r) {
    // Over the ranks, this rank's rows: the factor reads no other rows of the right-hand side.
    if (position[static_cast<size_t>(r)] >= 0 || !a.owns_row(r)) continue;  // diag · x_D
    PetscInt n = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    TC_PETSC(MatGetRow(a.get(), r, &n, &cols, &vals));
    for (PetscInt k = 0; k < n; ++k)
      if (const PetscInt d = position[static_cast<size_t>(cols[k])]; d >= 0 && vals[k] != 0.0)
        columns[static_cast<size_t>(d)].emplace_back(r, vals[k]);
    TC_PETSC(MatRestoreRow(a.get(), r, &n, &cols, &vals));
  }
  lift_start_.assign(1, 0);
  for (const auto& col : columns) {
    for (const auto& [r, v] : col) {
      lift_row_.push_back(r);
      lift_value_.push_back(v);
    }
    lift_start_.push_back(static_cast<PetscInt>(lift_row_.size()));
  }
}

void EliminatedCholesky::solve_homogeneous_many(::Mat b, ::Mat x) const {
  if (!dofs_.empty())
    TC_PETSC(
        MatZeroRows(b, static_cast<PetscInt>(dofs_.size()), dofs_.data(), 0.0, nullptr, nullptr));
  factor_.solve_many(b, x);
}

void EliminatedCholesky::solve(const core::Vector& b, core::Vector& x) const {
  factor_.solve(lifted(b, x), x);
}

const core::Vector& EliminatedCholesky::lifted(const core::Vector& b, const core::Vector& x) const {
  if (dofs_.empty()) return b;
  // rhs = b − A(:, D) x_D on the free rows (A x_D summed first, row by row in column order, as
  // a product with A would), diag · x_D on the constrained ones.
  lift_.zero();
  {
    const auto xv = x.read();
    auto lv = lift_.view();
    for (size_t k = 0; k < dofs_.size(); ++k) {
      const double value = xv[dofs_[k]];
      if (value == 0.0) continue;
      for (PetscInt e = lift_start_[k]; e < lift_start_[k + 1]; ++e)
        lv[lift_row_[static_cast<size_t>(e)]] += lift_value_[static_cast<size_t>(e)] * value;
    }
  }
  rhs_.copy_from(b);
  rhs_.axpy(-1.0, lift_);
  {
    const auto xv = x.read();
    auto rv = rhs_.view();
    for (const PetscInt d : dofs_) rv[d] = diag_ * xv[d];
  }
  return rhs_;
}

}  // namespace tc::linalg
