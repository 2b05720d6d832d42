#pragma once
// The compliance of one body on the dofs the contact rows touch, (A⁻¹)_TT: the explicit dual
// operator F = Σ_i B_i A_i⁻¹ B_iᵀ of DualContactSolver is formed from it without solves for rows
// on dofs seen before.
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "tc/core/petsc.hpp"
#include "tc/physics/constrained_solver.hpp"

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
/// the new row too, by the symmetry of A. When those solves would cost more than the
/// factorisation (ConstrainedSolver::forward_compliance_pays, at the first cover), S is grown
/// by forward solves alone instead (S = YᵀY, ConstrainedSolver::forward_compliance), keeping
/// Y: fewer flops, the same S to round-off but not to the bit.
class DofCompliance {
 public:
  DofCompliance(const ConstrainedSolver& solver, PetscInt n_dofs);
  /// The dofs of `dofs` not yet in T (each counted once).
  [[nodiscard]] PetscInt missing(std::span<const PetscInt> dofs) const;
  /// Adds the dofs not yet in T; returns the number of solves spent.
  PetscInt cover(std::span<const PetscInt> dofs);
  /// Position of `dof` in T, or −1.
  [[nodiscard]] PetscInt index(PetscInt dof) const { return index_[dof]; }
  [[nodiscard]] PetscInt size() const { return static_cast<PetscInt>(dofs_.size()); }
  /// The body's dofs (the range of T).
  [[nodiscard]] PetscInt n_dofs() const { return static_cast<PetscInt>(index_.size()); }
  [[nodiscard]] const Eigen::MatrixXd& matrix() const { return s_; }
  /// T in the order added, and the number of dofs each cover() added: enough to rebuild S
  /// with the same solves in the same blocks, hence the same bits (restart).
  [[nodiscard]] const std::vector<PetscInt>& dofs() const { return dofs_; }
  [[nodiscard]] const std::vector<PetscInt>& chunks() const { return chunks_; }
  /// x = A⁻¹w (zero prescribed values) for w that vanishes off T, by the forward columns Y kept
  /// when S is grown by forward solves: x = PᵀL⁻ᵀ(Y w_T), half a solve and a pass over Y
  /// (ConstrainedSolver::solve_from_forward). False, x untouched, otherwise (S grown by
  /// restricted solves, or w nonzero off T).
  bool solve(const core::Vector& w, core::Vector& x) const;
  /// Rebuilds S from scratch by replaying the recorded cover() calls (nothing to do when the
  /// record is already this one's).
  void replay(std::span<const PetscInt> dofs, std::span<const PetscInt> chunks);

 private:
  const ConstrainedSolver& solver_;
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
