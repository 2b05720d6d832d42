#pragma once
// The compliances of a direct factorisation (linalg/compliance.hpp) that use more of the
// factor than its block solves: CHOLMOD's supernodal solves and MUMPS's selected inverse.
// EliminatedCholesky::compliance chooses among them and BlockCompliance.
#include "tc/linalg/cholmod/cholmod_factor.hpp"
#include "tc/linalg/compliance.hpp"
#include "tc/linalg/eliminated_cholesky.hpp"

namespace tc::linalg {

/// S on CHOLMOD's supernodal factor. A new dof costs one solve, in blocks of 64 right-hand
/// sides restricted to the supernodes they reach (CholmodFactor::unit_solve_rows: the bits of
/// the block solve); its column's entries on the old T give the new row too, by the symmetry of
/// A. When those solves would cost more flops than the forward solves alone
/// (CholmodFactor::forward_compliance_pays, at the first cover), S is grown by them instead
/// (S = YᵀY, CholmodFactor::forward_compliance), keeping Y: the same S to round-off but not to
/// the bit. With Y kept, apply() and the corrected solve (Compliance::begin_corrected) share
/// its forward solves; that protocol (forward half, kept Y, solve from the forward half) stays
/// in this class.
class CholmodCompliance final : public BlockCompliance {
 public:
  CholmodCompliance(const EliminatedCholesky& solver, const CholmodFactor& factor);
  [[nodiscard]] std::string path() const override;
  bool apply(const core::Vector& w, core::Vector& x) const override;
  bool begin_corrected(const core::Vector& b, core::Vector& x, CorrectedSolve& s) const override;
  bool finish_corrected(CorrectedSolve& s, const core::Vector& w, core::Vector& x) const override;

 private:
  void grow(Eigen::Index old) override;
  // Whether S is grown by forward solves and their Y kept.
  [[nodiscard]] bool keeps_forward() const { return by_forward_ && forward_ != nullptr; }

  const EliminatedCholesky& solver_;
  const CholmodFactor& factor_;
  // Whether S is grown by forward solves alone (decided at the first cover, by its cost), and
  // their Y for the columns added later.
  bool by_forward_ = false;
  ForwardColumnsPtr forward_;
};

/// S on a factor spread over the ranks by MUMPS's selected inverse: every rank gets every new
/// column at once (asked 1024 columns at a time: the work space is |T| × 1024, not a second S).
/// With rows_over_ranks, each rank keeps the rows of S at the T-positions q ≡ rank (mod ranks)
/// only: S is not replicated. Every call is collective.
class MumpsCompliance final : public Compliance {
 public:
  MumpsCompliance(const EliminatedCholesky& solver, bool rows_over_ranks);
  [[nodiscard]] std::string path() const override { return "mumps selected inverse"; }

 private:
  void grow(Eigen::Index old) override;
  const EliminatedCholesky& solver_;
};

}  // namespace tc::linalg
