#include "tc/dual/dof_compliance.hpp"

#include <algorithm>

#include "tc/core/error.hpp"
#include "tc/core/threads.hpp"
#include "tc/core/verify.hpp"

namespace tc::physics {

namespace dense {

Dense zero_dense(PetscInt n, PetscInt k) {
  Dense a;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, a.out()));
  PetscScalar* v = nullptr;
  TC_PETSC(MatDenseGetArray(a.get(), &v));
  PetscInt ld = n;
  TC_PETSC(MatDenseGetLDA(a.get(), &ld));
  for (PetscInt c = 0; c < k; ++c) std::fill(v + c * ld, v + c * ld + n, 0.0);
  TC_PETSC(MatDenseRestoreArray(a.get(), &v));
  return a;
}

void assemble(::Mat a) {
  TC_PETSC(MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY));
}

}  // namespace dense

using dense::assemble;
using dense::Dense;
using dense::zero_dense;

DofCompliance::DofCompliance(const ConstrainedSolver& solver, PetscInt n_dofs, bool rows_over_ranks)
    : solver_(solver), index_(static_cast<size_t>(n_dofs), -1) {
  // The factor spread over PETSC_COMM_WORLD's ranks gives every rank every new column at once
  // (the selected inverse): each keeps its rows of them.
  if (rows_over_ranks && solver.unit_rows_at_once()) {
    ranks_ = core::PetscSession::size();
    rank_ = core::PetscSession::rank();
  }
}

template <class Column>
void DofCompliance::store(Eigen::Index first, Eigen::Index k, Eigen::Index old, Column&& column) {
  // Row j of this rank holds T-position rows_[j] = rank_ + ranks_·j. An entry of two new dofs
  // comes from both their columns (equal up to the solver's round-off): it is their mean,
  // summed as a/2 + b/2 into the zeroed block (the bits of (a + b)/2), so that S is exactly
  // symmetric.
  const auto t = static_cast<Eigen::Index>(dofs_.size());
  const auto n_rows = static_cast<Eigen::Index>(rows_.size());
  for (Eigen::Index c = 0; c < k; ++c) {
    const Eigen::Index at = first + c;
    for (Eigen::Index j = 0; j < n_rows; ++j) {
      const auto q = static_cast<Eigen::Index>(rows_[static_cast<size_t>(j)]);
      if (q < old)
        s_(j, at) = column(q, c);
      else
        s_(j, at) += 0.5 * column(q, c);
    }
    if (at % ranks_ != rank_) continue;
    const Eigen::Index row = at / ranks_;  // the new column's own row, by symmetry
    for (Eigen::Index q = 0; q < t; ++q)
      if (q < old)
        s_(row, q) = column(q, c);
      else
        s_(row, q) += 0.5 * column(q, c);
  }
}

PetscInt DofCompliance::missing(std::span<const PetscInt> dofs) const {
  std::vector<PetscInt> fresh;
  for (const PetscInt d : dofs)
    if (index_[d] < 0) fresh.push_back(d);
  std::sort(fresh.begin(), fresh.end());
  return static_cast<PetscInt>(std::unique(fresh.begin(), fresh.end()) - fresh.begin());
}

bool DofCompliance::on_t(const core::Vector& w, double scale, std::vector<double>& wt) const {
  wt.resize(dofs_.size());
  const auto wv = w.read();
  const auto n = static_cast<PetscInt>(index_.size());
  for (PetscInt i = 0; i < n; ++i)
    if (wv[i] != 0.0 && index_[i] < 0) return false;
  for (size_t q = 0; q < dofs_.size(); ++q) wt[q] = scale * wv[dofs_[q]];
  return true;
}

bool DofCompliance::solve(const core::Vector& w, core::Vector& x) const {
  std::vector<double> wt;
  return keeps_forward() && on_t(w, 1.0, wt) && solver_.solve_from_forward(*forward_, wt, x);
}

bool DofCompliance::solve_forward_half(const core::Vector& b, core::Vector& x,
                                       std::vector<double>& z) const {
  return keeps_forward() && solver_.solve_forward_half(*forward_, dofs_, b, x, z);
}

bool DofCompliance::solve_backward_half(std::span<const double> z, const core::Vector& w,
                                        core::Vector& x) const {
  std::vector<double> wt;
  return keeps_forward() && on_t(w, -1.0, wt) && solver_.solve_from_forward(*forward_, wt, x, z);
}

PetscInt DofCompliance::cover(std::span<const PetscInt> dofs) {
  const auto old = static_cast<Eigen::Index>(dofs_.size());
  for (const PetscInt d : dofs)
    if (index_[d] < 0) {
      index_[d] = static_cast<PetscInt>(dofs_.size());
      dofs_.push_back(d);
    }
  const auto t = static_cast<Eigen::Index>(dofs_.size());
  if (t == old) return 0;
  // A solve per new column, ~4 nnz(L) flops each, nnz(L) some tens of n for a 3D body: the
  // level-3 solves of many columns are a kernel that gains from threads (core/threads.hpp).
  const core::KernelThreads threads(40.0 * static_cast<double>(index_.size()) *
                                    static_cast<double>(t - old));
  chunks_.push_back(static_cast<PetscInt>(t - old));
  const auto old_rows = static_cast<Eigen::Index>(rows_.size());
  for (Eigen::Index q = old; q < t; ++q)
    if (q % ranks_ == rank_) rows_.push_back(static_cast<PetscInt>(q));
  const auto n_rows = static_cast<Eigen::Index>(rows_.size());
  s_.conservativeResize(n_rows, t);
  s_.bottomRows(n_rows - old_rows).setZero();
  s_.rightCols(t - old).setZero();
  constexpr Eigen::Index block = 64;  // bounds the dense work space to n × block
  std::vector<double> part;           // the new columns on T, when the factor gives them directly
  // The restricted solves' backward pass visits every supernode of T for each block of new
  // columns; when that costs more flops than the forward solve alone (decided once, at the
  // first cover), S is grown by the latter, S = YᵀY, for this and every later cover.
  if (old == 0) {
    forward_.reset();
    by_forward_ = solver_.forward_compliance_pays(dofs_, static_cast<int>(block));
  }
  if (by_forward_) {  // CHOLMOD's factor, on this rank alone: S whole
    TC_VERIFY(ranks_ == 1, "the forward solves need the factor on this rank alone");
    const auto fresh = std::span(dofs_).subspan(static_cast<size_t>(old));
    if (old == 0 && solver_.forward_compliance(forward_, fresh, s_.data()))
      return static_cast<PetscInt>(t);  // S(T, T), exactly symmetric
    part.resize(static_cast<size_t>(t * (t - old)));
    if (old > 0 && solver_.forward_compliance(forward_, fresh, part.data())) {
      // the fresh block exactly symmetric already: its means are its entries
      store(old, t - old, old,
            [&](Eigen::Index a, Eigen::Index c) { return part[static_cast<size_t>(a + c * t)]; });
      return static_cast<PetscInt>(t - old);
    }
    by_forward_ = false;  // the factor cannot (not expected after a first success)
    forward_.reset();
  }
  const auto n = static_cast<PetscInt>(index_.size());
  // Unit rows at once (MUMPS's selected inverse over the ranks, asked 1024 columns at a time
  // by the factor): as many here, so that `part` is |T| × 1024, not a second S.
  constexpr Eigen::Index at_once = 1024;
  const Eigen::Index step = solver_.unit_rows_at_once() ? std::min(t - old, at_once) : block;
  for (Eigen::Index j0 = old; j0 < t; j0 += step) {
    const auto k = std::min(step, t - j0);
    part.resize(static_cast<size_t>(t * k));
    if (solver_.solve_unit_rows(
            std::span(dofs_).subspan(static_cast<size_t>(j0), static_cast<size_t>(k)),
            std::span(dofs_).first(static_cast<size_t>(t)), part.data())) {
      store(j0, k, old,
            [&](Eigen::Index a, Eigen::Index c) { return part[static_cast<size_t>(a + c * t)]; });
      continue;
    }
    Dense rhs = zero_dense(n, k), sol = zero_dense(n, k);
    {
      PetscScalar* r = nullptr;
      TC_PETSC(MatDenseGetArray(rhs.get(), &r));
      PetscInt ld = n;
      TC_PETSC(MatDenseGetLDA(rhs.get(), &ld));
      for (Eigen::Index c = 0; c < k; ++c) r[c * ld + dofs_[j0 + c]] = 1.0;
      TC_PETSC(MatDenseRestoreArray(rhs.get(), &r));
    }
    assemble(rhs.get());
    assemble(sol.get());
    solver_.solve_homogeneous_many(rhs.get(), sol.get());
    const PetscScalar* x = nullptr;
    TC_PETSC(MatDenseGetArrayRead(sol.get(), &x));
    PetscInt ld = n;
    TC_PETSC(MatDenseGetLDA(sol.get(), &ld));
    store(j0, k, old, [&](Eigen::Index a, Eigen::Index c) { return x[c * ld + dofs_[a]]; });
    TC_PETSC(MatDenseRestoreArrayRead(sol.get(), &x));
  }
  return static_cast<PetscInt>(t - old);
}

void DofCompliance::replay(std::span<const PetscInt> dofs, std::span<const PetscInt> chunks) {
  if (std::equal(dofs.begin(), dofs.end(), dofs_.begin(), dofs_.end()) &&
      std::equal(chunks.begin(), chunks.end(), chunks_.begin(), chunks_.end()))
    return;  // already this record (a restore into the run that wrote it)
  for (const PetscInt d : dofs_) index_[d] = -1;
  dofs_.clear();
  chunks_.clear();
  rows_.clear();
  s_.resize(0, 0);
  size_t at = 0;
  for (const PetscInt k : chunks) {
    if (at + static_cast<size_t>(k) > dofs.size()) throw Error("DofCompliance: bad replay record");
    cover(dofs.subspan(at, static_cast<size_t>(k)));
    at += static_cast<size_t>(k);
  }
}

}  // namespace tc::physics
