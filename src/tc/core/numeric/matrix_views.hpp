#pragma once
// A sparse matrix used without a copy of it, where a copy would stand beside the factors at a
// run's memory peak (issue 39): CG on the matrix with some dofs masked, and a second matrix on
// the index arrays of a first one assembled on the same graph.
#include <span>

#include "tc/core/numeric/petsc.hpp"

namespace tc::core {

/// jacobi_cg on A with the rows and columns of the sorted `fixed` replaced by diag·I (what
/// zero_rows_columns makes of a copy), applied to A itself through a shell operator. b must be
/// zero on `fixed`; x is then zero there. The iterates are those on the copy.
double jacobi_cg(const SparseMatrix& a, std::span<const PetscInt> fixed, double diag,
                 const Vector& b, Vector& x, double rtol, int max_iterations, int& iterations);

/// Makes the whole (sequential) `m` use the row starts and column indices of `like`, whose
/// pattern it must have (checked), and frees its own: 4 bytes an entry fewer, the values and
/// so every product the same. `m` holds a reference to `like`'s PETSc matrix; a new entry in
/// `m` is an error from then on.
void share_pattern(SparseMatrix& m, const SparseMatrix& like);

}  // namespace tc::core
