// core/numeric/matrix_views.hpp against the copies they replace: CG on M_u with fixed dofs masked
// gives the bits of CG on a copy with those rows and columns eliminated (zero_rows_columns), and a
// matrix moved onto another's index arrays keeps its every product to the bit, and so does a
// matrix without its zeros (drop_zeros), put back into the pattern it came from (in_pattern_of)
// to its every entry. The claims are of equal arithmetic, so the comparisons are exact (a sign of
// zero aside: == holds for ±0).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/numeric/matrix_views.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/mesh/box.hpp"

namespace {

using tc::core::SparseMatrix;
using tc::core::Vector;

tc::fem::Material steel() {
  tc::fem::Material mat;
  mat.density = 7850;
  mat.young_modulus = 2e11;
  mat.poisson_ratio = 0.3;
  return mat;
}

Vector ramp(PetscInt n) {  // entries of varied magnitude and sign, none zero
  Vector v(n);
  auto w = v.view();
  for (PetscInt i = 0; i < n; ++i) w[i] = 1.0 + 0.37 * static_cast<double>(i % 11) - 0.05 * i;
  return v;
}

TEST(MatrixViews, MaskedCgIsCgOnTheEliminatedCopy) {
  const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {5, 4, 3});
  const auto m = tc::fem::assemble_body(mesh, steel()).mass_u;
  std::vector<PetscInt> fixed;  // a clamped face and a few scattered dofs
  for (const int a : mesh.boundary_nodes("xmin"))
    for (int k = 0; k < 3; ++k) fixed.push_back(3 * a + k);
  for (PetscInt d = 7; d < m.rows(); d += 29) fixed.push_back(d);
  std::sort(fixed.begin(), fixed.end());
  fixed.erase(std::unique(fixed.begin(), fixed.end()), fixed.end());
  const double diag = tc::core::mean_diagonal(m);

  auto b = ramp(m.rows());
  {
    auto v = b.view();
    for (const PetscInt d : fixed) v[d] = 0.0;
  }
  auto copy = m.copy();
  copy.zero_rows_columns(fixed, diag);
  Vector on_copy(m.rows()), masked(m.rows());
  int its_copy = 0, its_masked = 0;
  const double r_copy = tc::core::jacobi_cg(copy, b, on_copy, 1e-12, 1000, its_copy);
  const double r_masked = tc::core::jacobi_cg(m, fixed, diag, b, masked, 1e-12, 1000, its_masked);
  EXPECT_LE(r_masked, 1e-12);
  EXPECT_GT(its_masked, 3);  // a real iteration, not a trivial solve
  EXPECT_EQ(its_masked, its_copy);
  EXPECT_EQ(r_masked, r_copy);
  const auto x = masked.to_std(), y = on_copy.to_std();
  for (size_t i = 0; i < x.size(); ++i) EXPECT_EQ(x[i], y[i]) << "dof " << i;
  for (const PetscInt d : fixed) EXPECT_EQ(x[static_cast<size_t>(d)], 0.0);
}

TEST(MatrixViews, ASharedPatternKeepsEveryProductAndOutlivesItsOwner) {
  const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {4, 3, 2});
  auto body = tc::fem::assemble_body(mesh, steel());
  const auto original = body.mass_u.copy();
  auto mass = body.mass_u.share();  // a second owner sees the new storage too
  tc::core::share_pattern(body.mass_u, body.stiffness_u);
  {  // the index arrays are the stiffness's own, not a copy of them
    PetscInt n = 0, nk = 0;
    const PetscInt *ia = nullptr, *ja = nullptr, *ik = nullptr, *jk = nullptr;
    PetscBool done = PETSC_FALSE;
    MatGetRowIJ(mass.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done);
    MatGetRowIJ(body.stiffness_u.get(), 0, PETSC_FALSE, PETSC_FALSE, &nk, &ik, &jk, &done);
    EXPECT_EQ(ja, jk);
    EXPECT_EQ(ia, ik);
    MatRestoreRowIJ(body.stiffness_u.get(), 0, PETSC_FALSE, PETSC_FALSE, &nk, &ik, &jk, &done);
    MatRestoreRowIJ(mass.get(), 0, PETSC_FALSE, PETSC_FALSE, &n, &ia, &ja, &done);
  }
  body.stiffness_u = SparseMatrix{};  // the pattern's owner gone: the reference keeps it
  const auto x = ramp(original.rows());
  Vector y(original.rows()), z(original.rows());
  original.mult(x, y);
  mass.mult(x, z);
  const auto yv = y.to_std(), zv = z.to_std();
  for (size_t i = 0; i < yv.size(); ++i) EXPECT_EQ(zv[i], yv[i]) << "row " << i;
  // Its pattern is fixed now: an entry outside it is refused, not added.
  const PetscInt far[] = {0, original.rows() - 1};
  const double one[] = {1.0};
  EXPECT_ANY_THROW(mass.add_values(std::span(far, 1), std::span(far + 1, 1), one));
}

TEST(MatrixViews, SharingNeedsTheSamePattern) {
  // 4 × 3 × 2 and 3 × 4 × 2 cells: 60 nodes each, two node graphs.
  const auto a = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {4, 3, 2});
  const auto b = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {3, 4, 2});
  auto body = tc::fem::assemble_body(a, steel());
  const auto other = tc::fem::assemble_body(b, steel());
  EXPECT_ANY_THROW(tc::core::share_pattern(body.mass_u, other.stiffness_u));
  EXPECT_ANY_THROW(tc::core::share_pattern(body.mass_theta, body.stiffness_u));  // N × N, 3N × 3N
  auto mass = body.mass_u.copy();
  mass.zero_rows_columns(std::vector<PetscInt>{0}, 1.0);  // values change, the pattern stays
  EXPECT_NO_THROW(tc::core::share_pattern(mass, body.stiffness_u));
}

PetscInt entries(const SparseMatrix& m) {
  MatInfo info;
  MatGetInfo(m.get(), MAT_LOCAL, &info);
  return static_cast<PetscInt>(info.nz_used);
}

TEST(MatrixViews, AMassWithoutItsZerosKeepsEveryProductAndComesBackWhole) {
  // M_u and the modified mass (a massless face: zero rows, P_eᵀM_eP_e in the cells beside it).
  const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {4, 3, 2});
  const auto body = tc::fem::assemble_body(mesh, steel());
  std::vector<char> massless(static_cast<size_t>(mesh.n_nodes()), 0);
  for (const int a : mesh.boundary_nodes("zmax")) massless[static_cast<size_t>(a)] = 1;
  const SparseMatrix masses[] = {body.mass_u.copy(),
                                 tc::fem::singular_mass_u(mesh, steel(), massless)};
  for (int which = 0; which < 2; ++which) {
    const auto& m = masses[which];
    auto compact = m.copy();
    tc::core::drop_zeros(compact);
    // M_ab·I in each 3 × 3 block: one entry in three stays; fewer where the massless rows are.
    if (which == 0)
      EXPECT_EQ(3 * entries(compact), entries(m));
    else
      EXPECT_LT(3 * entries(compact), entries(m));
    const auto x = ramp(m.rows());
    Vector y(m.rows()), z(m.rows()), yy = ramp(m.rows()), zz = ramp(m.rows());
    m.mult(x, y);
    compact.mult(x, z);
    m.mult_add(x, yy);
    compact.mult_add(x, zz);
    const auto yv = y.to_std(), zv = z.to_std(), yyv = yy.to_std(), zzv = zz.to_std();
    for (size_t i = 0; i < yv.size(); ++i) {
      ASSERT_EQ(zv[i], yv[i]) << "row " << i;
      ASSERT_EQ(zzv[i], yyv[i]) << "row " << i;
    }
    Vector w(m.rows());
    EXPECT_EQ(compact.quadratic_form(x, w), m.quadratic_form(x, w));
    // Back in the stiffness's pattern: the assembled matrix entry for entry.
    const auto back = tc::core::in_pattern_of(compact, body.stiffness_u);
    EXPECT_EQ(entries(back), entries(body.stiffness_u));
    PetscBool equal = PETSC_FALSE;
    MatEqual(back.get(), m.get(), &equal);
    EXPECT_TRUE(equal);
  }
}

TEST(MatrixViews, APatternThatDoesNotHoldTheMatrixIsRefused) {
  const auto a = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {4, 3, 2});
  const auto b = tc::mesh::make_box(3, {0, 0, 0}, {0.3, 0.2, 0.1}, {3, 4, 2});
  auto mass = tc::fem::assemble_body(a, steel()).mass_u;
  tc::core::drop_zeros(mass);
  EXPECT_ANY_THROW(
      (void)tc::core::in_pattern_of(mass, tc::fem::assemble_body(b, steel()).stiffness_u));
}

}  // namespace
