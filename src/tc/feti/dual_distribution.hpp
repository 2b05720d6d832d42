#pragma once
// Internal to tc/feti: the distribution of the rows of B (the multipliers) over the ranks of
// Feti's communicator. Every row has one owner rank, which stores it in every dual block; the
// ranks whose subdomains the row touches (its users, the owner among them) see it as a leaf.
// A PetscSF (star forest: roots = the owned rows, leaves = the rows the rank's own subdomains
// touch) moves a block of k dual vectors from the owners to the users before the subdomain
// products (bcast) and sums the users' contributions into the owners after them (reduce), so
// only interface rows between two ranks' subdomains travel. Collective on the communicator.
#include <petscsf.h>

#include <Eigen/Dense>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::feti {

class DualDistribution {
 public:
  using Block = Eigen::MatrixXd;  // k dual vectors, one per column

  /// How a block of k columns goes through the star forest: one SF call per column of the
  /// column-major block, or one call with a contiguous MPI datatype of k doubles on row-major
  /// copies of the block.
  enum class Transfer { per_column, row_major };

  DualDistribution() = default;
  /// `row_rank`: the owner of every row of B (the same on every rank); `leaf_rows`: the rows
  /// this rank's subdomains touch, in the order of the leaf blocks. Collective on `comm`.
  DualDistribution(MPI_Comm comm, const std::vector<int>& row_rank,
                   const std::vector<Eigen::Index>& leaf_rows);

  [[nodiscard]] Eigen::Index n_owned() const { return static_cast<Eigen::Index>(owned_.size()); }
  [[nodiscard]] Eigen::Index n_leaves() const { return n_leaves_; }
  /// The rows of B this rank owns, in the order of the owned blocks (row numbers of B).
  [[nodiscard]] const std::vector<Eigen::Index>& owned_rows() const { return owned_; }

  void set_transfer(Transfer t) { transfer_ = t; }
  /// leaves (n_leaves × k) = the owners' values of owned (n_owned × k). Collective.
  void bcast(const Block& owned, Block& leaves) const;
  /// owned (n_owned × k) = Σ over the users of their leaves' values. Collective.
  void reduce(const Block& leaves, Block& owned) const;

 private:
  using RowBlock = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  void bcast_rows(const Block& owned, Block& leaves) const;
  void reduce_rows(const Block& leaves, Block& owned) const;

  core::Handle<PetscSF, PetscSFDestroy> sf_;
  std::vector<Eigen::Index> owned_;
  Eigen::Index n_leaves_ = 0;
  Transfer transfer_ = Transfer::per_column;
};

}  // namespace tc::feti
