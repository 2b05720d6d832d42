#include "tc/contact/assembly.hpp"

#include <algorithm>
#include <numeric>

namespace tc::contact {

Csr Triplets::compress() const {
  std::vector<int> start(n_rows_ + 1, 0);
  for (const auto& e : entries_) ++start[e.row + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::pair<int, double>> sorted(entries_.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const auto& e : entries_) sorted[fill[e.row]++] = {e.col, e.value};
  Csr out;
  out.offsets.reserve(n_rows_ + 1);
  out.cols.reserve(entries_.size());
  out.vals.reserve(entries_.size());
  for (int r = 0; r < n_rows_; ++r) {
    const auto first = sorted.begin() + start[r], last = sorted.begin() + start[r + 1];
    std::sort(first, last, [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto it = first; it != last; ++it) {
      if (static_cast<int>(out.cols.size()) > out.offsets.back() && out.cols.back() == it->first)
        out.vals.back() += it->second;
      else {
        out.cols.push_back(it->first);
        out.vals.push_back(it->second);
      }
    }
    out.offsets.push_back(static_cast<int>(out.cols.size()));
  }
  return out;
}

core::SparseMatrix to_matrix(const Csr& csr, std::span<const int> rows, PetscInt n_cols) {
  const PetscInt n = static_cast<PetscInt>(rows.size());
  auto source = [&](PetscInt i) { return rows[i]; };
  std::vector<PetscInt> nnz(n);
  for (PetscInt i = 0; i < n; ++i) nnz[i] = csr.offsets[source(i) + 1] - csr.offsets[source(i)];
  core::SparseMatrix m(n, n_cols, nnz);
  std::vector<PetscInt> cols;
  for (PetscInt i = 0; i < n; ++i) {
    const int r = source(i), b = csr.offsets[r], e = csr.offsets[r + 1];
    if (b == e) continue;
    cols.assign(csr.cols.begin() + b, csr.cols.begin() + e);
    m.add_values({&i, 1}, cols, csr.vals.data() + b);
  }
  m.assemble();
  return m;
}

core::SparseMatrix to_matrix(const Csr& csr, PetscInt n_cols) {
  std::vector<int> all(csr.n_rows());
  std::iota(all.begin(), all.end(), 0);
  return to_matrix(csr, all, n_cols);
}

}  // namespace tc::contact
