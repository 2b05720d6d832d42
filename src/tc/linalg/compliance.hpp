#pragma once
// The compliance of one body on a growing set T of its dofs, S = (A⁻¹)_TT (A factorised,
// homogeneous Dirichlet data: constrained dofs have zero rows and columns). A row b of the
// contact rows B vanishes off T, so bᵀA⁻¹c = b_Tᵀ S c_T exactly (up to the solver's
// round-off): with S, the dual operator F = B A⁻¹Bᵀ costs sparse-dense products and no solve for
// rows on dofs seen before (dual::DualContactSolver), and the interface heat step its Woodbury
// system (physics::InterfaceHeatSolver).
//
// One interface, one implementation per way of growing S (docs/choices.md, "One compliance
// interface over the direct solvers"):
//   CholmodCompliance  CHOLMOD's supernodal factor: restricted solves, or forward solves alone
//                      (S = YᵀY, Y = L⁻¹P E_T kept) when those cost fewer flops;
//   MumpsCompliance    a factor spread over the ranks: MUMPS's selected inverse, S's rows
//                      dealt over the ranks on request;
//   BlockCompliance    any other solver: multi-right-hand-side block solves (and FETI's,
//                      dual::ConstrainedSolver).
#include <Eigen/Dense>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::linalg {

class EliminatedCholesky;

/// What a compliance keeps between the two calls of a corrected solve (Compliance::
/// begin_corrected, finish_corrected); nothing the caller reads.
class CorrectedSolve {
 public:
  [[nodiscard]] bool pending() const { return pending_; }
  /// Drops a begun solve (its work space is kept for the next).
  void cancel() { pending_ = false; }

 private:
  friend class CholmodCompliance;
  bool pending_ = false;
  std::vector<double> z_;
};

class Compliance {
 public:
  virtual ~Compliance();
  Compliance(const Compliance&) = delete;
  Compliance& operator=(const Compliance&) = delete;

  /// The dofs of `dofs` not yet in T (each counted once).
  [[nodiscard]] PetscInt missing(std::span<const PetscInt> dofs) const;
  /// Adds the dofs not yet in T; returns the number of solves spent.
  PetscInt cover(std::span<const PetscInt> dofs);
  /// Position of `dof` in T, or −1.
  [[nodiscard]] PetscInt index(PetscInt dof) const { return index_[dof]; }
  [[nodiscard]] PetscInt size() const { return static_cast<PetscInt>(dofs_.size()); }
  /// The body's dofs (the range of T).
  [[nodiscard]] PetscInt n_dofs() const { return static_cast<PetscInt>(index_.size()); }
  /// S, or this rank's rows of it (rows_spread): |rows()| × |T|, column-major; S is symmetric,
  /// so column q holds S(q, ·) on this rank's rows.
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
  /// Rebuilds S from scratch by replaying the recorded cover() calls (nothing to do when the
  /// record is already this one's).
  void replay(std::span<const PetscInt> dofs, std::span<const PetscInt> chunks);

  /// How S is grown, for `thermocontact info` and summary.json ("cholmod-supernodal (forward
  /// solves)", "cholmod-supernodal (restricted solves)", "mumps selected inverse", "block
  /// solves", "feti"); for CHOLMOD decided at the first cover.
  [[nodiscard]] virtual std::string path() const = 0;
  /// x = A⁻¹w (zero prescribed values) for w that vanishes off T, where the implementation has
  /// a cheaper way than a solve (CHOLMOD's kept forward columns: half a solve). False, x
  /// untouched, otherwise: the caller solves.
  virtual bool apply(const core::Vector& w, core::Vector& x) const;
  /// x = A⁻¹(b − E_T w) (Dirichlet data in x, as the body's solve) for a w on T that is known
  /// only once (A⁻¹b)_T has been read, in two calls: begin_corrected writes (A⁻¹b)_T into x,
  /// finish_corrected all of x once w is known. With CHOLMOD's kept forward columns that is
  /// one forward and one backward solve for both A⁻¹b and A⁻¹E_T w, not one forward and two
  /// backward. Both return false, x untouched, where the implementation has no such sharing
  /// (and finish_corrected where begin_corrected returned false): the caller then solves
  /// A x = b itself, and corrects x by its own plain path.
  virtual bool begin_corrected(const core::Vector& b, core::Vector& x, CorrectedSolve& s) const;
  virtual bool finish_corrected(CorrectedSolve& s, const core::Vector& w, core::Vector& x) const;

 protected:
  /// A compliance on n_dofs dofs; with ranks > 1, this rank holds the rows of S at the
  /// T-positions q ≡ rank (mod ranks) only.
  explicit Compliance(PetscInt n_dofs, int ranks = 1, int rank = 0);
  /// The columns S(T, new) for the T-positions [old, size()) just added, stored by store().
  virtual void grow(Eigen::Index old) = 0;
  /// The new columns S(T, ·) given by `column(a, c)` (row a of T, column c of the new ones,
  /// from T-position `first` on, k of them) into this rank's rows, and their rows on the old
  /// columns by symmetry.
  template <class Column>
  void store(Eigen::Index first, Eigen::Index k, Eigen::Index old, Column&& column);
  /// store() from a column-major |T| × k block.
  void store_block(Eigen::Index first, Eigen::Index k, Eigen::Index old, const double* part);
  /// scale · w on T, in T's order; false if w is nonzero off T.
  bool on_t(const core::Vector& w, double scale, std::vector<double>& wt) const;
  [[nodiscard]] Eigen::MatrixXd& s() { return s_; }

 private:
  int ranks_ = 1, rank_ = 0;    // over which rows are dealt (1: S whole here)
  std::vector<PetscInt> rows_;  // T-positions of this rank's rows of S
  std::vector<PetscInt> chunks_;
  std::vector<PetscInt> index_;  // dof → position in T, or −1
  std::vector<PetscInt> dofs_;   // T in the order added
  Eigen::MatrixXd s_;
};

template <class Column>
void Compliance::store(Eigen::Index first, Eigen::Index k, Eigen::Index old, Column&& column) {
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

/// The checkpoint's part of some compliances: per compliance its dofs and chunks, appended to
/// `record` (two entries each), and the compliances rebuilt from such a record with the same
/// bits. `owner` names them in the error of a record that does not match.
void save_compliances(std::span<const std::unique_ptr<Compliance>> compliances,
                      std::vector<std::vector<int>>& record);
void replay_compliances(std::span<const std::unique_ptr<Compliance>> compliances,
                        std::span<const std::vector<int>> record, const char* owner);

/// S by multi-right-hand-side solves X = A⁻¹E (E the unit columns of the new dofs, in blocks of
/// 64: the dense work space is n × 64) with any solver that has them.
class BlockCompliance : public Compliance {
 public:
  /// `solve_many(B, X)`: X = A⁻¹B with zero prescribed values (dense n × k; it may zero B's
  /// constrained rows).
  using BlockSolve = std::function<void(::Mat, ::Mat)>;
  BlockCompliance(PetscInt n_dofs, BlockSolve solve_many, std::string path = "block solves");
  [[nodiscard]] std::string path() const override { return path_; }

 protected:
  void grow(Eigen::Index old) override;
  /// The block solves of T-positions [first, first + k).
  void solve_block(Eigen::Index first, Eigen::Index k, Eigen::Index old);

 private:
  BlockSolve solve_many_;
  std::string path_;
};

/// The paths this build can take (`thermocontact info`): CHOLMOD's two, MUMPS's selected
/// inverse when PETSc has MUMPS, block solves and FETI.
[[nodiscard]] std::vector<std::string> compliance_paths();

}  // namespace tc::linalg
