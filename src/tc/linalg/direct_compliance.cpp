#include "tc/linalg/direct_compliance.hpp"

#include <algorithm>

#include "tc/core/verify.hpp"

namespace tc::linalg {

namespace {
constexpr Eigen::Index kBlock = 64;  // columns per restricted or block solve: n × 64 of work
}  // namespace

CholmodCompliance::CholmodCompliance(const EliminatedCholesky& solver, const CholmodFactor& factor)
    : BlockCompliance(solver.size(),
                      [&solver](::Mat b, ::Mat x) { solver.solve_homogeneous_many(b, x); }),
      solver_(solver),
      factor_(factor) {}

std::string CholmodCompliance::path() const {
  return by_forward_ ? "cholmod-supernodal (forward solves)"
                     : "cholmod-supernodal (restricted solves)";
}

void CholmodCompliance::grow(Eigen::Index old) {
  const Eigen::Index t = size();
  const std::span<const PetscInt> t_dofs(dofs());
  // The restricted solves' backward pass visits every supernode of T for each block of new
  // columns; when that costs more flops than the forward solve alone (decided once, at the
  // first cover), S is grown by the latter, S = YᵀY, for this and every later cover.
  if (old == 0) {
    forward_.reset();
    by_forward_ =
        factor_.forward_compliance_pays(solver_.free_or_none(t_dofs), static_cast<int>(kBlock));
  }
  std::vector<double> part;  // the new columns on T
  if (by_forward_) {
    const auto fresh = solver_.free_or_none(t_dofs.subspan(static_cast<size_t>(old)));
    if (old == 0 && factor_.forward_compliance(forward_, fresh, s().data()))
      return;  // S(T, T), exactly symmetric
    part.resize(static_cast<size_t>(t * (t - old)));
    if (old > 0 && factor_.forward_compliance(forward_, fresh, part.data())) {
      // the fresh block exactly symmetric already: its means are its entries
      store_block(old, t - old, old, part.data());
      return;
    }
    by_forward_ = false;  // the factor cannot (not expected after a first success)
    forward_.reset();
  }
  for (Eigen::Index j0 = old; j0 < t; j0 += kBlock) {
    const auto k = std::min(kBlock, t - j0);
    part.resize(static_cast<size_t>(t * k));
    // The block solve zeroes the constrained rows of its right-hand side.
    const auto cols =
        solver_.free_or_none(t_dofs.subspan(static_cast<size_t>(j0), static_cast<size_t>(k)));
    if (factor_.unit_solve_rows(cols, t_dofs, part.data()))
      store_block(j0, k, old, part.data());
    else
      solve_block(j0, k, old);  // a simplicial factor
  }
}

bool CholmodCompliance::apply(const core::Vector& w, core::Vector& x) const {
  std::vector<double> wt;
  if (!keeps_forward() || !on_t(w, 1.0, wt)) return false;
  // Every entry of x: a constrained dof has no column in Y, so its x is 0.
  auto xv = x.view();
  return factor_.solve_from_forward(*forward_, wt, xv.span().data());
}

bool CholmodCompliance::begin_corrected(const core::Vector& b, core::Vector& x,
                                        CorrectedSolve& s) const {
  s.pending_ = false;
  if (!keeps_forward()) return false;
  // The lifting and the forward solve z = L⁻¹P b; x on T = Yᵀz, x's other entries as they were.
  {
    const auto rv = solver_.lifted(b, x).read();
    if (!factor_.forward_half(rv.span(), s.z_)) return false;
  }
  std::vector<double> on_t(dofs().size());
  if (!factor_.forward_values(*forward_, s.z_, on_t)) return false;
  auto xv = x.view();  // a constrained dof of T keeps its prescribed value
  const auto free = solver_.free_or_none(dofs());
  for (size_t q = 0; q < free.size(); ++q)
    if (free[q] >= 0) xv[free[q]] = on_t[q];
  s.pending_ = true;
  return true;
}

bool CholmodCompliance::finish_corrected(CorrectedSolve& s, const core::Vector& w,
                                         core::Vector& x) const {
  if (!s.pending_) return false;
  s.pending_ = false;
  // x = PᵀL⁻ᵀ(z − Y w_T): every entry of x (a constrained dof has no column in Y, so its x is
  // z's, = x_D to round-off, as solve).
  std::vector<double> wt;
  TC_VERIFY(keeps_forward() && on_t(w, -1.0, wt), "a corrected solve's w lies on T");
  auto xv = x.view();
  TC_VERIFY(factor_.solve_from_forward(*forward_, wt, xv.span().data(), s.z_),
            "the kept forward columns finish the corrected solve");
  return true;
}

MumpsCompliance::MumpsCompliance(const EliminatedCholesky& solver, bool rows_over_ranks)
    : Compliance(solver.size(), rows_over_ranks ? core::PetscSession::size() : 1,
                 rows_over_ranks ? core::PetscSession::rank() : 0),
      solver_(solver) {
  TC_VERIFY(solver.factor().distributed(), "MUMPS's selected inverse needs the factor spread");
}

void MumpsCompliance::grow(Eigen::Index old) {
  // Unit rows at once (asked 1024 columns at a time by the factor): as many here, so that the
  // block is |T| × 1024, not a second S.
  constexpr Eigen::Index at_once = 1024;
  const Eigen::Index t = size();
  const std::span<const PetscInt> t_dofs(dofs());
  const Eigen::Index step = std::min(t - old, at_once);
  std::vector<double> part;
  for (Eigen::Index j0 = old; j0 < t; j0 += step) {
    const auto k = std::min(step, t - j0);
    part.resize(static_cast<size_t>(t * k));
    const auto cols =
        solver_.free_or_none(t_dofs.subspan(static_cast<size_t>(j0), static_cast<size_t>(k)));
    solver_.factor().selected_inverse(cols, t_dofs, part.data());
    store_block(j0, k, old, part.data());
  }
}

std::unique_ptr<Compliance> EliminatedCholesky::compliance(bool rows_over_ranks) const {
  if (factor_.distributed()) return std::make_unique<MumpsCompliance>(*this, rows_over_ranks);
  if (const CholmodFactor* f = factor_.cholmod(); f && f->supernodal())
    return std::make_unique<CholmodCompliance>(*this, *f);
  return std::make_unique<BlockCompliance>(
      size(), [this](::Mat b, ::Mat x) { solve_homogeneous_many(b, x); });
}

}  // namespace tc::linalg
