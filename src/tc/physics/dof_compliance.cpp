#include "tc/physics/dof_compliance.hpp"

#include <algorithm>

#include "tc/core/error.hpp"

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

DofCompliance::DofCompliance(const ConstrainedSolver& solver, PetscInt n_dofs)
    : solver_(solver), index_(static_cast<size_t>(n_dofs), -1) {}

PetscInt DofCompliance::missing(std::span<const PetscInt> dofs) const {
  std::vector<PetscInt> fresh;
  for (const PetscInt d : dofs)
    if (index_[d] < 0) fresh.push_back(d);
  std::sort(fresh.begin(), fresh.end());
  return static_cast<PetscInt>(std::unique(fresh.begin(), fresh.end()) - fresh.begin());
}

bool DofCompliance::solve(const core::Vector& w, core::Vector& x) const {
  if (!by_forward_ || !forward_) return false;
  std::vector<double> wt(dofs_.size());
  {
    const auto wv = w.read();
    const auto n = static_cast<PetscInt>(index_.size());
    for (PetscInt i = 0; i < n; ++i)
      if (wv[i] != 0.0 && index_[i] < 0) return false;
    for (size_t q = 0; q < dofs_.size(); ++q) wt[q] = wv[dofs_[q]];
  }
  return solver_.solve_from_forward(*forward_, wt, x);
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
  chunks_.push_back(static_cast<PetscInt>(t - old));
  s_.conservativeResize(t, t);
  constexpr Eigen::Index block = 64;  // bounds the dense work space to n × block
  std::vector<double> part;           // the new columns on T, when the factor gives them directly
  // The restricted solves' backward pass visits every supernode of T for each block of new
  // columns; when that would cost more than the factorisation (decided once, at the first
  // cover), S is grown by the forward solve alone, S = YᵀY, for this and every later cover.
  if (old == 0) {
    forward_.reset();
    by_forward_ = solver_.forward_compliance_pays(dofs_, static_cast<int>(block));
  }
  if (by_forward_) {
    const auto fresh = std::span(dofs_).subspan(static_cast<size_t>(old));
    if (old == 0 && solver_.forward_compliance(forward_, fresh, s_.data()))
      return static_cast<PetscInt>(t);  // S(T, T), exactly symmetric
    part.resize(static_cast<size_t>(t * (t - old)));
    if (old > 0 && solver_.forward_compliance(forward_, fresh, part.data())) {
      for (Eigen::Index c = 0; c < t - old; ++c)
        for (Eigen::Index a = 0; a < t; ++a) {
          const double v = part[static_cast<size_t>(a + c * t)];
          s_(a, old + c) = v;
          if (a < old) s_(old + c, a) = v;
        }
      return static_cast<PetscInt>(t - old);  // the fresh block exactly symmetric already
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
      for (Eigen::Index c = 0; c < k; ++c)
        for (Eigen::Index a = 0; a < t; ++a) {
          const double v = part[static_cast<size_t>(a + c * t)];
          s_(a, j0 + c) = v;
          if (a < old) s_(j0 + c, a) = v;
        }
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
    for (Eigen::Index c = 0; c < k; ++c)
      for (Eigen::Index a = 0; a < t; ++a) {
        const double v = x[c * ld + dofs_[a]];
        s_(a, j0 + c) = v;
        if (a < old) s_(j0 + c, a) = v;  // the new row of the old dofs: S symmetric
      }
    TC_PETSC(MatDenseRestoreArrayRead(sol.get(), &x));
  }
  // The block of new dofs with itself was filled from both sides; make it exactly symmetric
  // (its two halves differ by the solver's round-off only), in place: a copy would be as large
  // as S on the first cover.
  for (Eigen::Index j = old; j < t; ++j)
    for (Eigen::Index i = old; i < j; ++i) {
      const double v = 0.5 * (s_(i, j) + s_(j, i));  // the same bits as 0.5 (F + Fᵀ)
      s_(i, j) = v;
      s_(j, i) = v;
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
  s_.resize(0, 0);
  size_t at = 0;
  for (const PetscInt k : chunks) {
    if (at + static_cast<size_t>(k) > dofs.size()) throw Error("DofCompliance: bad replay record");
    cover(dofs.subspan(at, static_cast<size_t>(k)));
    at += static_cast<size_t>(k);
  }
}

}  // namespace tc::physics
