#pragma once
// Assembly stage of the mortar pair: entries gathered face by face are summed into compressed
// rows and handed to PETSc with exact preallocation.
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::contact {

/// Compressed sparse rows: row i holds cols/vals[offsets[i], offsets[i + 1]), columns sorted
/// and unique.
struct Csr {
  std::vector<int> offsets{0}, cols;
  std::vector<double> vals;
  [[nodiscard]] int n_rows() const { return static_cast<int>(offsets.size()) - 1; }
};

/// Entries (row, column, value), summed on compression. Compression is a counting sort by row
/// followed by short per-row sorts, O(entries) for the bounded row lengths of a surface mesh.
class Triplets {
 public:
  explicit Triplets(int n_rows) : n_rows_(n_rows) {}
  void add(int row, int col, double value) { entries_.push_back({row, col, value}); }
  void clear() { entries_.clear(); }
  [[nodiscard]] Csr compress() const;

 private:
  struct Entry {
    int row, col;
    double value;
  };
  int n_rows_;
  std::vector<Entry> entries_;
};

/// The matrix whose row i is row rows[i] of `csr`, with n_cols columns.
[[nodiscard]] core::SparseMatrix to_matrix(const Csr& csr, std::span<const int> rows,
                                           PetscInt n_cols);
/// The matrix of all rows of `csr`, with n_cols columns.
[[nodiscard]] core::SparseMatrix to_matrix(const Csr& csr, PetscInt n_cols);

}  // namespace tc::contact
