#include "tc/dual/constrained_solver.hpp"

#include <algorithm>

namespace tc::physics {

namespace {

/// `dofs` with the constrained ones (sorted `constrained`) replaced by −1: the elimination
/// decouples them, their rows and columns of A⁻¹ are zero.
std::vector<PetscInt> free_or_none(std::span<const PetscInt> dofs,
                                   const std::vector<PetscInt>& constrained) {
  std::vector<PetscInt> out(dofs.begin(), dofs.end());
  for (auto& d : out)
    if (std::binary_search(constrained.begin(), constrained.end(), d)) d = -1;
  return out;
}

}  // namespace

ConstrainedSolver::ConstrainedSolver(const core::SparseMatrix& a, std::vector<PetscInt> dofs,
                                     const std::string& package, core::FactorRanks ranks)
    : dofs_(std::move(dofs)), diag_(core::mean_diagonal(a)) {
  keep_lifting(a);
  factor_ = core::CholeskySolver(a, dofs_, diag_, package, ranks);
  lift_ = core::Vector(a.rows());
  rhs_ = core::Vector(a.rows());
}

ConstrainedSolver::ConstrainedSolver(core::SparseMatrix&& a, std::vector<PetscInt> dofs,
                                     const std::string& package, core::FactorRanks ranks)
    : dofs_(std::move(dofs)), diag_(core::mean_diagonal(a)) {
  keep_lifting(a);
  const PetscInt n = a.rows();
  factor_ = core::CholeskySolver(std::move(a), dofs_, diag_, package, ranks);
  lift_ = core::Vector(n);
  rhs_ = core::Vector(n);
}

void ConstrainedSolver::keep_lifting(const core::SparseMatrix& a) {
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

bool ConstrainedSolver::solve_unit_rows(std::span<const PetscInt> cols,
                                        std::span<const PetscInt> rows, double* out) const {
  if (feti_) return false;
  // The block solve zeroes the constrained rows of its right-hand side.
  return factor_.unit_solve_rows(free_or_none(cols, dofs_), rows, out);
}

bool ConstrainedSolver::forward_compliance_pays(std::span<const PetscInt> dofs, int block) const {
  return !feti_ && factor_.forward_compliance_pays(free_or_none(dofs, dofs_), block);
}

bool ConstrainedSolver::forward_compliance(core::ForwardColumnsPtr& kept,
                                           std::span<const PetscInt> fresh, double* out) const {
  return !feti_ && factor_.forward_compliance(kept, free_or_none(fresh, dofs_), out);
}

bool ConstrainedSolver::solve_from_forward(const core::ForwardColumns& kept,
                                           std::span<const double> w, core::Vector& x,
                                           std::span<const double> z) const {
  if (feti_) return false;
  // Every entry of x: a constrained dof has no column in Y, so its x is 0 without z and
  // z's (= x_D to round-off, as solve) with it.
  auto xv = x.view();
  return factor_.solve_from_forward(kept, w, xv.span().data(), z);
}

void ConstrainedSolver::solve(const core::Vector& b, core::Vector& x) const {
  if (feti_) {
    feti_->solve(b, x);
    return;
  }
  factor_.solve(lifted(b, x), x);
}

const core::Vector& ConstrainedSolver::lifted(const core::Vector& b, const core::Vector& x) const {
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

bool ConstrainedSolver::solve_forward_half(const core::ForwardColumns& kept,
                                           std::span<const PetscInt> t, const core::Vector& b,
                                           core::Vector& x, std::vector<double>& z) const {
  if (feti_) return false;
  {
    const auto rv = lifted(b, x).read();
    if (!factor_.forward_half(rv.span(), z)) return false;
  }
  std::vector<double> on_t(t.size());
  if (!factor_.forward_values(kept, z, on_t)) return false;
  auto xv = x.view();  // a constrained dof of T keeps its prescribed value
  const auto free = free_or_none(t, dofs_);
  for (size_t q = 0; q < t.size(); ++q)
    if (free[q] >= 0) xv[free[q]] = on_t[q];
  return true;
}

}  // namespace tc::physics
