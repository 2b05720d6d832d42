// The matrices of matrix_views.hpp held without a copy or without their zeros.
#include "tc/core/numeric/matrix_views.hpp"

#include <algorithm>
#include <vector>

#include "tc/core/verify.hpp"

namespace tc::core {

void share_pattern(SparseMatrix& m, const SparseMatrix& like) {
  TC_VERIFY(
      !m.distributed() && !like.distributed() && m.rows() == like.rows() && m.cols() == like.cols(),
      "share_pattern: two whole matrices of one size");
  PetscInt n = 0, nl = 0;
  const PetscInt *ia = nullptr, *ja = nullptr, *il = nullptr, *jl = nullptr;
  PetscBool done = PETSC_FALSE, done_like = PETSC_FALSE;
  TC_PETSC(MatGetRowIJ(m.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  TC_PETSC(MatGetRowIJ(like.get(), 0, PETSC_FALSE, PETSC_FALSE, &nl, &il, &jl, &done_like));
  TC_VERIFY(done && done_like, "share_pattern: sequential AIJ matrices");
  const bool same = std::equal(ia, ia + n + 1, il) && std::equal(ja, ja + ia[n], jl);
  const PetscInt entries = ia[n];
  auto* ip = const_cast<PetscInt*>(il);  // PETSc's type has no const; `like` keeps them
  auto* jp = const_cast<PetscInt*>(jl);
  TC_PETSC(MatRestoreRowIJ(like.get(), 0, PETSC_FALSE, PETSC_FALSE, &nl, &il, &jl, &done_like));
  TC_PETSC(MatRestoreRowIJ(m.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  TC_VERIFY(same, "share_pattern: the two matrices have one nonzero pattern");
  // m's values in an array of their own (its index arrays share one allocation with them),
  // owned by a container composed with the matrix: freed with it.
  PetscScalar* v = nullptr;
  TC_PETSC(PetscMalloc1(std::max<PetscInt>(entries, 1), &v));
  {
    const PetscScalar* from = nullptr;
    TC_PETSC(MatSeqAIJGetArrayRead(m.get(), &from));
    std::copy(from, from + entries, v);
    TC_PETSC(MatSeqAIJRestoreArrayRead(m.get(), &from));
  }
  Handle<PetscContainer, PetscContainerDestroy> values;
  TC_PETSC(PetscContainerCreate(PETSC_COMM_SELF, values.out()));
  TC_PETSC(PetscContainerSetPointer(values.get(), v));
  TC_PETSC(PetscContainerSetUserDestroy(values.get(), PetscContainerUserDestroyDefault));
  ::Mat shared = nullptr;
  TC_PETSC(MatCreateSeqAIJWithArrays(PETSC_COMM_SELF, m.rows(), m.cols(), ip, jp, v, &shared));
  // m's PETSc object takes the new storage (its old arrays are freed), so every owner of it
  // sees the change.
  TC_PETSC(MatHeaderReplace(m.get(), &shared));
  auto* obj = reinterpret_cast<PetscObject>(m.get());
  TC_PETSC(PetscObjectCompose(obj, "tc_values", reinterpret_cast<PetscObject>(values.get())));
  TC_PETSC(PetscObjectCompose(obj, "tc_pattern", reinterpret_cast<PetscObject>(like.get())));
  // A new entry would reallocate arrays this matrix does not own.
  TC_PETSC(MatSetOption(m.get(), MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
}

namespace {

/// Calls f(row, columns, values, count) for each row of the whole AIJ matrix m.
template <class F>
void for_each_row(const SparseMatrix& m, F f) {
  PetscInt n = 0;
  const PetscInt *ia = nullptr, *ja = nullptr;
  PetscBool done = PETSC_FALSE;
  TC_PETSC(MatGetRowIJ(m.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
  TC_VERIFY(done, "a sequential AIJ matrix");
  const PetscScalar* v = nullptr;
  TC_PETSC(MatSeqAIJGetArrayRead(m.get(), &v));
  for (PetscInt i = 0; i < n; ++i) f(i, ja + ia[i], v + ia[i], ia[i + 1] - ia[i]);
  TC_PETSC(MatSeqAIJRestoreArrayRead(m.get(), &v));
  TC_PETSC(MatRestoreRowIJ(m.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done));
}

}  // namespace

void drop_zeros(SparseMatrix& m) {
  TC_VERIFY(!m.distributed(), "drop_zeros: a whole matrix");
  std::vector<PetscInt> kept(static_cast<size_t>(m.rows()), 0);
  const auto keep = [](PetscInt i, PetscInt j, PetscScalar v) { return v != 0.0 || i == j; };
  for_each_row(m, [&](PetscInt i, const PetscInt* j, const PetscScalar* v, PetscInt n) {
    for (PetscInt k = 0; k < n; ++k) kept[static_cast<size_t>(i)] += keep(i, j[k], v[k]);
  });
  ::Mat out = nullptr;
  TC_PETSC(MatCreateSeqAIJ(PETSC_COMM_SELF, m.rows(), m.cols(), 0, kept.data(), &out));
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  for_each_row(m, [&](PetscInt i, const PetscInt* j, const PetscScalar* v, PetscInt n) {
    columns.clear();
    values.clear();
    for (PetscInt k = 0; k < n; ++k)
      if (keep(i, j[k], v[k])) {
        columns.push_back(j[k]);
        values.push_back(v[k]);
      }
    TC_PETSC(MatSetValues(out, 1, &i, static_cast<PetscInt>(columns.size()), columns.data(),
                          values.data(), INSERT_VALUES));
  });
  TC_PETSC(MatAssemblyBegin(out, MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(out, MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatHeaderReplace(m.get(), &out));  // every owner of m's PETSc object sees the change
  TC_PETSC(MatSetOption(m.get(), MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
}

SparseMatrix in_pattern_of(const SparseMatrix& m, const SparseMatrix& like) {
  if (m.distributed()) return m.copy();
  TC_VERIFY(m.rows() == like.rows() && m.cols() == like.cols(), "in_pattern_of: one size");
  auto out = like.copy();
  TC_PETSC(MatZeroEntries(out.get()));
  TC_PETSC(MatSetOption(out.get(), MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE));
  for_each_row(m, [&](PetscInt i, const PetscInt* j, const PetscScalar* v, PetscInt n) {
    TC_PETSC(MatSetValues(out.get(), 1, &i, n, j, v, INSERT_VALUES));
  });
  TC_PETSC(MatAssemblyBegin(out.get(), MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(out.get(), MAT_FINAL_ASSEMBLY));
  return out;
}

}  // namespace tc::core
