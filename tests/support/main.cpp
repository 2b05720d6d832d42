// The test runner: GoogleTest with one PETSc session around all tests.
#include <gtest/gtest.h>

#include <cstdlib>

#include "tc/core/numeric/petsc.hpp"

int main(int argc, char** argv) {
  // ctest runs as many tests at once as there are cores (scripts/test.sh), and a run takes
  // every core for its BLAS by default: one thread each, for this process and the runs it
  // starts, unless the caller chose otherwise. Histories compared to the bit need it too: the
  // threaded kernels sum in another order.
  setenv("OPENBLAS_NUM_THREADS", "1", 0);
  ::testing::InitGoogleTest(&argc, argv);
  tc::core::PetscSession session(&argc, &argv);
  return RUN_ALL_TESTS();
}
