#pragma once
// Test matrices: the 1D Laplacian (tridiagonal) and a 3D Laplacian on a g³ grid (7 points, diagonal
// shifted to 6.5: SPD), large enough at g ≥ 12 for CHOLMOD's supernodal factor, which the
// restricted and forward-solve paths of the compliance need
// (linalg::CholmodFactor::unit_solve_rows, forward_compliance).
#include <span>
#include <vector>

#include "tc/core/numeric/petsc.hpp"

namespace tc::test {

/// tridiag(−1, diagonal, −1) of order n: the 1D Laplacian with Dirichlet ends at diagonal = 2
/// (small: CHOLMOD factors it simplicially).
inline core::SparseMatrix tridiagonal(PetscInt n, double diagonal) {
  std::vector<PetscInt> nnz(static_cast<size_t>(n), 3);
  core::SparseMatrix a(n, n, nnz);
  for (PetscInt i = 0; i < n; ++i) {
    a.add_values(std::span(&i, 1), std::span(&i, 1), &diagonal);
    if (i + 1 < n) {
      const PetscInt j = i + 1;
      const double o = -1.0;
      a.add_values(std::span(&i, 1), std::span(&j, 1), &o);
      a.add_values(std::span(&j, 1), std::span(&i, 1), &o);
    }
  }
  a.assemble();
  return a;
}

inline core::SparseMatrix shifted_laplacian(PetscInt g) {
  const PetscInt n = g * g * g;
  std::vector<PetscInt> nnz(n, 7);
  core::SparseMatrix a(n, n, nnz);
  const auto id = [&](PetscInt x, PetscInt y, PetscInt z) { return x + g * (y + g * z); };
  for (PetscInt z = 0; z < g; ++z)
    for (PetscInt y = 0; y < g; ++y)
      for (PetscInt x = 0; x < g; ++x) {
        const PetscInt i = id(x, y, z);
        const double d = 6.5, o = -1.0;
        a.add_values(std::span(&i, 1), std::span(&i, 1), &d);
        for (const PetscInt j : {x + 1 < g ? id(x + 1, y, z) : -1, y + 1 < g ? id(x, y + 1, z) : -1,
                                 z + 1 < g ? id(x, y, z + 1) : -1})
          if (j >= 0) {
            a.add_values(std::span(&i, 1), std::span(&j, 1), &o);
            a.add_values(std::span(&j, 1), std::span(&i, 1), &o);
          }
      }
  a.assemble();
  return a;
}

}  // namespace tc::test
