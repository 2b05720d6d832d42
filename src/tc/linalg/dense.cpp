#include "tc/linalg/dense.hpp"

#include <algorithm>

namespace tc::linalg::dense {

Dense zero_dense(PetscInt n, PetscInt k) {
  Dense a;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, a.out()));
  PetscScalar* v = nullptr;
  TC_PETSC(MatDenseGetArray(a.get(), &v));
  PetscInt ld = n;
  TC_PETSC(MatDenseGetLDA(a.get(), &ld));
  for (PetscInt c = 0; c < k; ++c) std::fill(v + c * ld, v + c * ld + n, 0.0);
  TC_PETSC(MatDenseRestoreArray(a.get(), &v));
  return a;
}

void assemble(::Mat a) {
  TC_PETSC(MatAssemblyBegin(a, MAT_FINAL_ASSEMBLY));
  TC_PETSC(MatAssemblyEnd(a, MAT_FINAL_ASSEMBLY));
}

}  // namespace tc::linalg::dense
