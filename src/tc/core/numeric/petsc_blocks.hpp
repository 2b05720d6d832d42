#pragma once
// Helpers of core's PETSc wrappers for objects spread over the ranks in RowBlocks, shared by
// core/numeric/petsc.cpp (SparseMatrix, jacobi_cg) and linalg's solvers (linalg/mumps_ranks.cpp: a
// factor over the ranks). For core and linalg only.
#include "tc/core/numeric/collective.hpp"
#include "tc/core/numeric/petsc.hpp"

#define TC_MPI(call) ::tc::core::check_mpi((call), #call)

namespace tc::core::blocks {

// This rank's block of a replicated array as a vector of the spread layout: nothing copied.
inline Handle<::Vec, VecDestroy> block_view(const RowBlocks& r, const double* data) {
  Handle<::Vec, VecDestroy> v;
  TC_PETSC(VecCreateMPIWithArray(r.comm, 1, r.here(), r.n, data + r.first(), v.out()));
  return v;
}

// op(x_block, y_block) on this rank's blocks of the replicated x (dealt in rx) and y (in ry),
// then y gathered: a product, a solve or CG on a matrix or factor spread over the ranks.
template <class Op>
void on_blocks(const RowBlocks& rx, const RowBlocks& ry, ::Vec x, ::Vec y, Op op) {
  const PetscScalar* xp = nullptr;
  PetscScalar* yp = nullptr;
  TC_PETSC(VecGetArrayRead(x, &xp));
  TC_PETSC(VecGetArray(y, &yp));
  {
    const auto xl = block_view(rx, xp);
    const auto yl = block_view(ry, yp);
    op(xl.get(), yl.get());
  }
  ry.gather(yp);
  TC_PETSC(VecRestoreArray(y, &yp));
  TC_PETSC(VecRestoreArrayRead(x, &xp));
}

}  // namespace tc::core::blocks
