#include "tc/feti/dual_distribution.hpp"

#include <algorithm>

#include "tc/core/error.hpp"

namespace tc::feti {

namespace {

/// A committed contiguous MPI datatype of k doubles: one row of a row-major block of k columns.
class RowType {
 public:
  explicit RowType(Eigen::Index k) {
    if (MPI_Type_contiguous(static_cast<int>(k), MPI_DOUBLE, &type_) != MPI_SUCCESS ||
        MPI_Type_commit(&type_) != MPI_SUCCESS)
      throw Error("FETI: MPI_Type_contiguous/MPI_Type_commit failed");
  }
  ~RowType() { (void)MPI_Type_free(&type_); }
  RowType(const RowType&) = delete;
  RowType& operator=(const RowType&) = delete;
  [[nodiscard]] MPI_Datatype get() const { return type_; }

 private:
  MPI_Datatype type_ = MPI_DATATYPE_NULL;
};

}  // namespace

DualDistribution::DualDistribution(MPI_Comm comm, const std::vector<int>& row_rank,
                                   const std::vector<Eigen::Index>& leaf_rows)
    : n_leaves_(static_cast<Eigen::Index>(leaf_rows.size())) {
  int rank = 0, size = 1;
  if (MPI_Comm_rank(comm, &rank) != MPI_SUCCESS || MPI_Comm_size(comm, &size) != MPI_SUCCESS)
    throw Error("FETI: MPI_Comm_rank/MPI_Comm_size failed");
  // A row's place among its owner's rows: the owners keep their rows in the order of B, so
  // every rank finds any row's root from the replicated row_rank alone, without messages.
  std::vector<PetscInt> index(row_rank.size());
  std::vector<PetscInt> count(static_cast<size_t>(size), 0);
  for (size_t r = 0; r < row_rank.size(); ++r) {
    const auto p = static_cast<size_t>(row_rank[r]);
    index[r] = count[p]++;
    if (row_rank[r] == rank) owned_.push_back(static_cast<Eigen::Index>(r));
  }
  std::vector<PetscSFNode> remote(leaf_rows.size());
  for (size_t l = 0; l < leaf_rows.size(); ++l) {
    const auto r = static_cast<size_t>(leaf_rows[l]);
    remote[l] = {row_rank[r], index[r]};
  }
  TC_PETSC(PetscSFCreate(comm, sf_.out()));
  TC_PETSC(PetscSFSetGraph(sf_.get(), static_cast<PetscInt>(owned_.size()),
                           static_cast<PetscInt>(remote.size()), nullptr, PETSC_COPY_VALUES,
                           remote.data(), PETSC_COPY_VALUES));
  TC_PETSC(PetscSFSetUp(sf_.get()));
}

void DualDistribution::bcast(const Block& owned, Block& leaves) const {
  const Eigen::Index k = owned.cols();
  if (transfer_ == Transfer::row_major && k > 1) {
    bcast_rows(owned, leaves);
    return;
  }
  // The k columns are in flight together: every Begin before the first End.
  leaves.resize(n_leaves_, k);
  for (Eigen::Index j = 0; j < k; ++j)
    TC_PETSC(PetscSFBcastBegin(sf_.get(), MPI_DOUBLE, owned.col(j).data(), leaves.col(j).data(),
                               MPI_REPLACE));
  for (Eigen::Index j = 0; j < k; ++j)
    TC_PETSC(PetscSFBcastEnd(sf_.get(), MPI_DOUBLE, owned.col(j).data(), leaves.col(j).data(),
                             MPI_REPLACE));
}

void DualDistribution::reduce(const Block& leaves, Block& owned) const {
  const Eigen::Index k = leaves.cols();
  if (transfer_ == Transfer::row_major && k > 1) {
    reduce_rows(leaves, owned);
    return;
  }
  owned.setZero(n_owned(), k);  // the reduction adds the leaves to the roots
  for (Eigen::Index j = 0; j < k; ++j)
    TC_PETSC(PetscSFReduceBegin(sf_.get(), MPI_DOUBLE, leaves.col(j).data(), owned.col(j).data(),
                                MPI_SUM));
  for (Eigen::Index j = 0; j < k; ++j)
    TC_PETSC(PetscSFReduceEnd(sf_.get(), MPI_DOUBLE, leaves.col(j).data(), owned.col(j).data(),
                              MPI_SUM));
}

void DualDistribution::bcast_rows(const Block& owned, Block& leaves) const {
  const RowType row(owned.cols());
  const RowBlock from = owned;
  RowBlock to(n_leaves_, owned.cols());
  TC_PETSC(PetscSFBcastBegin(sf_.get(), row.get(), from.data(), to.data(), MPI_REPLACE));
  TC_PETSC(PetscSFBcastEnd(sf_.get(), row.get(), from.data(), to.data(), MPI_REPLACE));
  leaves = to;
}

void DualDistribution::reduce_rows(const Block& leaves, Block& owned) const {
  const RowType row(leaves.cols());
  const RowBlock from = leaves;
  RowBlock to = RowBlock::Zero(n_owned(), leaves.cols());
  TC_PETSC(PetscSFReduceBegin(sf_.get(), row.get(), from.data(), to.data(), MPI_SUM));
  TC_PETSC(PetscSFReduceEnd(sf_.get(), row.get(), from.data(), to.data(), MPI_SUM));
  owned = to;
}

}  // namespace tc::feti
