#pragma once
// The compliance of one body on the dofs the contact rows touch, (A⁻¹)_TT: the explicit dual
// operator F = Σ_i B_i A_i⁻¹ B_iᵀ of DualContactSolver is formed from it without solves for rows
// on dofs seen before.
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "tc/core/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"

namespace tc::physics {

namespace dense {
using Dense = core::Handle<::Mat, MatDestroy>;
/// A dense n × k PETSc matrix (MATSEQDENSE), zero.
[[nodiscard]] Dense zero_dense(PetscInt n, PetscInt k);
void assemble(::Mat a);
}  // namespace dense

/// S = (A⁻¹)_TT of one body on a growing set T of its dofs (A factorised, homogeneous
/// Dirichlet data: constrained dofs have zero rows and columns). A row b of B vanishes off T,
/// so bᵀA⁻¹c = b_Tᵀ S c_T exactly (up to the direct solver's round-off): with S, F = B A⁻¹Bᵀ
/// costs sparse-dense products and no solve for rows on dofs seen before. A new dof costs one
/// solve (in blocks of right-hand sides, restricted to the supernodes they reach when the
/// factor allows: ConstrainedSolver::solve_unit_rows); its column's entries on the old T give
/// the new row too, by the symmetry of A. When those solves would cost more flops than the
/// forward solves alone (ConstrainedSolver::forward_compliance_pays, at the first cover), S is
/// grown by them instead (S = YᵀY, ConstrainedSolver::forward_compliance), keeping Y: the same
/// S to round-off but not to the bit.
///
/// With `rows_over_ranks` and a factor spread over the ranks (ConstrainedSolver::
/// unit_rows_at_once, more than one rank), each rank holds the rows of S at the T-positions
/// q ≡ rank (mod ranks) only, S(T_rank, T): S is not replicated. Otherwise every rank holds S.
class DofCompliance {
 public:
  DofCompliance(const ConstrainedSolver& solver, PetscInt n_dofs, bool rows_over_ranks = false);
  /// The dofs of `dofs` not yet in T (each counted once).
  [[nodiscard]] PetscInt missing(std::span<const PetscInt> dofs) const;
  /// Adds the dofs not yet in T; returns the number of solves spent.
  PetscInt cover(std::span<const PetscInt> dofs);
  /// Position of `dof` in T, or −1.
  [[nodiscard]] PetscInt index(PetscInt dof) const { return index_[dof]; }
  [[nodiscard]] PetscInt size() const { return static_cast<PetscInt>(dofs_.size()); }
  /// The body's dofs (the range of T).
  [[nodiscard]] PetscInt n_dofs() const { return static_cast<PetscInt>(index_.size()); }
  /// S, or this rank's rows of it (rows_over_ranks): |rows()| × |T|, column-major; S is
  /// symmetric, so column q holds S(q, ·) on this rank's rows.
  [[nodiscard]] const Eigen::MatrixXd& matrix() const { return s_; }
  /// Whether the rows are dealt over the ranks, and the T-position of each row this rank holds
  /// (all of T, in order, when not).
  [[nodiscard]] bool rows_spread() const { return ranks_ > 1; }
  [[nodiscard]] const std::vector<PetscInt>& rows() const { return rows_; }
  /// The row of matrix() holding T-position q, or −1 when another rank holds it.
  [[nodiscard]] PetscInt row_of(PetscInt q) const { return q % ranks_ == rank_ ? q / ranks_ : -1; }
  /// T in the order added, and the number of dofs each cover() added: enough to rebuild S
  /// with the same solves in the same blocks, hence the same bits (restart).
  [[nodiscard]] const std::vector<PetscInt>& dofs() const { return dofs_; }
  [[nodiscard]] const std::vector<PetscInt>& chunks() const { return chunks_; }
  /// x = A⁻¹w (zero prescribed values) for w that vanishes off T, by the forward columns Y kept
  /// when S is grown by forward solves: x = PᵀL⁻ᵀ(Y w_T), half a solve and a pass over Y
  /// (ConstrainedSolver::solve_from_forward). False, x untouched, otherwise (S grown by
  /// restricted solves, or w nonzero off T).
  bool solve(const core::Vector& w, core::Vector& x) const;
  /// Whether S is grown by forward solves and their Y kept (solve() and the halves can work).
  [[nodiscard]] bool keeps_forward() const { return by_forward_ && forward_ != nullptr; }
  /// The body's solve A x = b (Dirichlet data in x) in two halves by the kept Y
  /// (ConstrainedSolver::solve_forward_half, then solve_from_forward with z): x on T, with z, now;
  /// all of x = A⁻¹(b − w), w vanishing off T, later. False, x untouched, as solve().
  bool solve_forward_half(const core::Vector& b, core::Vector& x, std::vector<double>& z) const;
  bool solve_backward_half(std::span<const double> z, const core::Vector& w, core::Vector& x) const;
  /// Rebuilds S from scratch by replaying the recorded cover() calls (nothing to do when the
  /// record is already this one's).
  void replay(std::span<const PetscInt> dofs, std::span<const PetscInt> chunks);

 private:
  // scale · w on T, in T's order; false if w is nonzero off T.
  bool on_t(const core::Vector& w, double scale, std::vector<double>& wt) const;
  // The new columns S(T, fresh) given by `column(a, c)` (row a of T, column c of the fresh
  // ones, from `first` on) into this rank's rows, and their rows on the old columns by symmetry.
  template <class Column>
  void store(Eigen::Index first, Eigen::Index k, Eigen::Index old, Column&& column);

  const ConstrainedSolver& solver_;
  int ranks_ = 1, rank_ = 0;    // over which rows are dealt (1: S whole here)
  std::vector<PetscInt> rows_;  // T-positions of this rank's rows of S
  // Whether S is grown by forward solves alone (decided at the first cover, by its cost), and
  // their Y for the columns added later.
  bool by_forward_ = false;
  core::ForwardColumnsPtr forward_;
  std::vector<PetscInt> chunks_;
  std::vector<PetscInt> index_;  // dof → position in T, or −1
  std::vector<PetscInt> dofs_;   // T in the order added
  Eigen::MatrixXd s_;
};

}  // namespace tc::physics
