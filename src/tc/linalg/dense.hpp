#pragma once
// Dense PETSc matrices (MATSEQDENSE) as the block solves and the explicit dual operator use
// them: RAII, zeroed on creation, assembled.
#include <petscmat.h>

#include "tc/core/numeric/petsc.hpp"

namespace tc::linalg::dense {

using Dense = core::Handle<::Mat, MatDestroy>;
/// A dense n × k PETSc matrix (MATSEQDENSE), zero.
[[nodiscard]] Dense zero_dense(PetscInt n, PetscInt k);
void assemble(::Mat a);

}  // namespace tc::linalg::dense
