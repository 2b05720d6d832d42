// The modified mass matrix of fem::singular_mass_u (docs/choices.md, "dynamic contact
// scheme") against what defines it: zero rows and columns on the massless nodes, symmetric
// and positive semi-definite, the same mass for a translation as the consistent M_u (the
// momentum of rigid sliding is kept), and M_u itself away from the boundary's cells. Every
// entry is a sum of a few O(ρh^d) products: 1e-12 relative is round-off with margin, and a
// wrong P_e changes the translation mass or the symmetry at O(1).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "tc/fem/assembler.hpp"
#include "tc/mesh/box.hpp"

namespace {

using tc::core::SparseMatrix;

Eigen::MatrixXd dense(const SparseMatrix& m) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(m.rows(), m.rows());
  for (PetscInt i = 0; i < m.rows(); ++i) {
    PetscInt nz = 0;
    const PetscInt* cols = nullptr;
    const PetscScalar* vals = nullptr;
    MatGetRow(m.get(), i, &nz, &cols, &vals);
    for (PetscInt q = 0; q < nz; ++q) out(i, cols[q]) = vals[q];
    MatRestoreRow(m.get(), i, &nz, &cols, &vals);
  }
  return out;
}

class SingularMass : public ::testing::TestWithParam<int> {};

TEST_P(SingularMass, MasslessFaceTranslationMassAndInteriorKept) {
  const int dim = GetParam();
  const auto mesh = tc::mesh::make_box(dim, {0, 0, 0}, {0.3, 0.2, 0.1}, {3, 2, 2});
  tc::fem::Material mat;
  mat.density = 7850;
  mat.young_modulus = 2e11;
  mat.poisson_ratio = 0.3;
  std::vector<char> massless(static_cast<size_t>(mesh.n_nodes()), 0);
  const char* face = dim == 2 ? "ymin" : "zmin";
  for (const int a : mesh.boundary_nodes(face)) massless[static_cast<size_t>(a)] = 1;

  const auto m = dense(tc::fem::assemble_body(mesh, mat).mass_u);
  const auto mt = dense(tc::fem::singular_mass_u(mesh, mat, massless));
  const double scale = m.cwiseAbs().maxCoeff();
  EXPECT_LE((mt - mt.transpose()).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(mt);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12 * scale);

  const double volume = 0.3 * 0.2 * (dim == 3 ? 0.1 : 1.0);
  for (int k = 0; k < dim; ++k) {
    Eigen::VectorXd t = Eigen::VectorXd::Zero(m.rows());
    for (int a = 0; a < mesh.n_nodes(); ++a) t(dim * a + k) = 1.0;
    EXPECT_NEAR(t.dot(mt * t), mat.density * volume, 1e-12 * mat.density * volume);
    EXPECT_NEAR(t.dot(m * t), mat.density * volume, 1e-12 * mat.density * volume);
  }
  // Zero rows on the face's dofs; the rest of the face's cells' rows changed, the other rows
  // (nodes two layers above the face) as in M_u.
  const double h = dim == 2 ? 0.1 : 0.05;  // the cells' height
  for (int a = 0; a < mesh.n_nodes(); ++a)
    for (int k = 0; k < dim; ++k) {
      const Eigen::Index i = dim * a + k;
      const double height = mesh.point(a)[dim - 1];
      if (massless[static_cast<size_t>(a)]) {
        EXPECT_EQ(mt.row(i).cwiseAbs().maxCoeff(), 0.0) << "node " << a;
      } else if (height > 1.5 * h) {
        EXPECT_LE((mt.row(i) - m.row(i)).cwiseAbs().maxCoeff(), 1e-12 * scale) << "node " << a;
      }
    }
}

INSTANTIATE_TEST_SUITE_P(Dims, SingularMass, ::testing::Values(2, 3));

}  // namespace
