#pragma once
// A sparse matrix used without a copy of it, where a copy would stand beside the factors at a
// run's memory peak (issue 39): CG on the matrix with some dofs masked, and a second matrix on
// the index arrays of a first one assembled on the same graph, a matrix without the zeros its
// assembly left in it.
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

/// Removes from the whole (sequential) `m` the entries that are exactly zero, but those on its
/// diagonal: M_u assembled on K_u's dim × dim blocks holds zeros between the displacement
/// components, two thirds of its entries in 3D. Every product with `m` stays the same to the
/// bit (a row's sum meets the same nonzero terms in the same order, and adding a zero product
/// changes no sum), at 12 bytes a kept entry instead of 8 for every entry on K_u's indices.
void drop_zeros(SparseMatrix& m);

/// `m`'s values in the pattern of `like`, which holds m's (checked), zeros elsewhere: what m
/// was before drop_zeros, for the operators formed by adding it to `like` entry by entry
/// (4/τ² M_u + K_u), so that they are formed by the same arithmetic. A spread `m` is on
/// like's pattern already (never compacted) and is copied.
[[nodiscard]] SparseMatrix in_pattern_of(const SparseMatrix& m, const SparseMatrix& like);

}  // namespace tc::core
