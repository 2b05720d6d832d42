#pragma once
// Replicated test vectors and their comparison, for the tests of matrices and factors spread
// over the ranks (tests/mpi).
#include <cmath>

#include "tc/core/numeric/petsc.hpp"

namespace tc::test {

/// cos(phase + 0.11 i): every entry different, so that a misplaced row shows.
inline core::Vector some_vector(PetscInt n, double phase) {
  core::Vector v(n);
  auto w = v.view();
  for (PetscInt i = 0; i < n; ++i) w[i] = std::cos(phase + 0.11 * static_cast<double>(i));
  return v;
}

inline double max_abs_diff(const core::Vector& a, const core::Vector& b) {
  auto d = a.clone();
  d.axpy(-1.0, b);
  return d.max_abs();
}

}  // namespace tc::test
