// The test runner: GoogleTest with one PETSc session around all tests.
#include <gtest/gtest.h>

#include "tc/core/petsc.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  tc::core::PetscSession session(&argc, &argv);
  return RUN_ALL_TESTS();
}
