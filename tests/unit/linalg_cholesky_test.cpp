// linalg::CholeskySolver on one rank with each package this build offers: solves, the A⁻¹0
// shortcut, and, with CHOLMOD's supernodal factor, the restricted unit-column solves and the
// compliance by forward solves (linalg/cholmod/cholmod_columns.cpp, cholmod_forward.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "support/grid_laplacian.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/linalg/cholesky_solver.hpp"

TEST(Petsc, CholeskySolvesAnSpdSystem) {
  // 1D Laplacian with Dirichlet ends: tridiag(-1, 2, -1), solution of A x = A·1 is 1.
  const PetscInt n = 50;
  const auto a = tc::test::tridiagonal(n, 2.0);
  for (const auto& package : tc::linalg::available_cholesky_packages()) {
    tc::linalg::CholeskySolver solver(a, package);
    tc::core::Vector one(n), b(n), x(n);
    one.fill(1.0);
    a.mult(one, b);
    solver.solve(b, x);
    x.axpy(-1.0, one);
    // cond(A) ~ 1e3 for n = 50, so a backward-stable solve is accurate to ~1e-13.
    EXPECT_LT(x.norm(), 1e-11) << package;
  }
}

using tc::test::shifted_laplacian;

TEST(Petsc, CholeskyZeroRightHandSideIsTheSolvesOwnZeros) {
  // solve() takes A⁻¹0 = 0 without the factor (a body at rest before a touch): the result must
  // be the factor's own for b = 0, +0 in every entry, whatever x held before.
  const auto a = tc::test::shifted_laplacian(12);  // supernodal in CHOLMOD
  const PetscInt n = a.rows();
  for (const auto& package : tc::linalg::available_cholesky_packages()) {
    tc::linalg::CholeskySolver solver(a, package);
    tc::core::Vector zero(n), x(n), by_factor(n);
    x.fill(7.0);
    by_factor.fill(7.0);
    solver.solve(zero, x);
    solver.solve_raw(zero.get(), by_factor.get());
    {
      const auto xv = x.read();
      const auto fv = by_factor.read();
      for (PetscInt i = 0; i < n; ++i) {
        EXPECT_EQ(xv[i], 0.0) << package << " entry " << i;
        EXPECT_FALSE(std::signbit(xv[i])) << package << " entry " << i;
        EXPECT_EQ(std::signbit(xv[i]), std::signbit(fv[i])) << package << " entry " << i;
        EXPECT_EQ(xv[i], fv[i]) << package << " entry " << i;
      }
    }
    // A NaN is not a zero: the solve runs and hands it on (require_finite reports it).
    tc::core::Vector with_nan(n);
    with_nan.view()[n / 2] = std::numeric_limits<double>::quiet_NaN();
    solver.solve(with_nan, x);
    bool any_nan = false;
    const auto nv = x.read();
    for (const double e : nv.span()) any_nan = any_nan || std::isnan(e);
    EXPECT_TRUE(any_nan) << package;
  }
}

TEST(Petsc, CholeskyUnitColumnsAreTheBlockSolveBitForBit) {
  // A 3D Laplacian (7 points, shifted) large enough for CHOLMOD's supernodal factor: the rows
  // of A⁻¹[e_c] from unit_solve_rows, which visits only the supernodes they need, against the
  // dense block solve: the same bits (CHOLMOD), or false and nothing written (other packages).
  const PetscInt g = 14, n = g * g * g;
  const auto a = shifted_laplacian(g);
  const auto id = [&](PetscInt x, PetscInt y, PetscInt z) { return x + g * (y + g * z); };
  std::vector<PetscInt> rows;  // a face, as the contact dofs are
  for (PetscInt y = 0; y < g; ++y)
    for (PetscInt x = 0; x < g; ++x) rows.push_back(id(x, y, g - 1));
  for (const auto& package : tc::linalg::available_cholesky_packages()) {
    tc::linalg::CholeskySolver solver(a, package);
    for (const PetscInt k : {1, 5, 64}) {
      std::vector<PetscInt> cols(rows.begin(), rows.begin() + k);
      if (k == 5) cols[2] = -1;  // a zero right-hand side
      std::vector<double> out(rows.size() * static_cast<size_t>(k), -7.0);
      const bool done =
          (solver.cholmod() && solver.cholmod()->unit_solve_rows(cols, rows, out.data()));
      const bool expected = package == MATSOLVERCHOLMOD;  // CHOLMOD's own supernodal solves
      if (!expected) {
        EXPECT_FALSE(done) << package;
        EXPECT_EQ(out[0], -7.0) << package;
        continue;
      }
      ASSERT_TRUE(done) << "CHOLMOD's supernodal factor was not reached, k = " << k;
      ::Mat b = nullptr, x = nullptr;
      TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, &b));
      TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, &x));
      for (PetscInt c = 0; c < k; ++c)
        if (cols[static_cast<size_t>(c)] >= 0)
          TC_PETSC(MatSetValue(b, cols[static_cast<size_t>(c)], c, 1.0, INSERT_VALUES));
      for (::Mat m : {b, x}) {
        TC_PETSC(MatAssemblyBegin(m, MAT_FINAL_ASSEMBLY));
        TC_PETSC(MatAssemblyEnd(m, MAT_FINAL_ASSEMBLY));
      }
      solver.solve_many(b, x);
      const PetscScalar* xv = nullptr;
      TC_PETSC(MatDenseGetArrayRead(x, &xv));
      for (PetscInt c = 0; c < k; ++c)
        for (size_t r = 0; r < rows.size(); ++r)
          ASSERT_EQ(out[r + static_cast<size_t>(c) * rows.size()],
                    xv[static_cast<size_t>(rows[r] + c * n)])
              << "k = " << k << ", column " << c << ", row " << rows[r];
      TC_PETSC(MatDenseRestoreArrayRead(x, &xv));
      TC_PETSC(MatDestroy(&b));
      TC_PETSC(MatDestroy(&x));
    }
  }
}

TEST(Petsc, CholeskyForwardComplianceIsTheRestrictedSolveToRoundOff) {
  // S = (A⁻¹)_TT by forward solves alone (S = YᵀY, kept Y for later columns) against
  // unit_solve_rows (forward and backward): the same to round-off, exactly symmetric, zero on a
  // constrained (−1) dof; grown by a second set of dofs, the new columns on all of T.
  const PetscInt g = 14;
  const auto a = shifted_laplacian(g);
  const auto id = [&](PetscInt x, PetscInt y, PetscInt z) { return x + g * (y + g * z); };
  std::vector<PetscInt> first, more;  // a face patch, then a strip beside it (the slide)
  for (PetscInt y = 0; y < g; ++y)
    for (PetscInt x = 0; x < g; ++x) (x < 9 ? first : more).push_back(id(x, y, g - 1));
  first[5] = -1;  // constrained
  std::vector<PetscInt> all(first);
  all.insert(all.end(), more.begin(), more.end());
  for (const auto& package : tc::linalg::available_cholesky_packages()) {
    tc::linalg::CholeskySolver solver(a, package);
    EXPECT_FALSE((solver.cholmod() && solver.cholmod()->forward_compliance_pays(first, 64)))
        << "below the floor: " << package;
    tc::linalg::ForwardColumnsPtr kept;
    const auto nf = first.size(), na = all.size(), nm = more.size();
    std::vector<double> s1(nf * nf, -7.0), s2(na * nm, -7.0);
    const bool done =
        (solver.cholmod() && solver.cholmod()->forward_compliance(kept, first, s1.data()));
    const bool expected = package == MATSOLVERCHOLMOD;  // CHOLMOD's own supernodal solves
    ASSERT_EQ(done, expected) << package;
    if (!expected) {
      EXPECT_EQ(s1[0], -7.0) << package;
      continue;
    }
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->forward_compliance(kept, more, s2.data())));
    std::vector<double> r1(nf * nf), r2(na * nm);
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->unit_solve_rows(first, first, r1.data())));
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->unit_solve_rows(more, all, r2.data())));
    double scale = 0;
    for (const double v : r1) scale = std::max(scale, std::abs(v));
    for (size_t j = 0; j < nf; ++j)
      for (size_t i = 0; i < nf; ++i) {
        ASSERT_EQ(s1[i + j * nf], s1[j + i * nf]) << "not symmetric at " << i << ", " << j;
        if (first[i] < 0 || first[j] < 0) {
          ASSERT_EQ(s1[i + j * nf], 0.0);
        } else {
          EXPECT_NEAR(s1[i + j * nf], r1[i + j * nf], 1e-13 * scale) << i << ", " << j;
        }
      }
    for (size_t j = 0; j < nm; ++j)
      for (size_t i = 0; i < na; ++i)
        if (all[i] < 0) {
          ASSERT_EQ(s2[i + j * na], 0.0);
        } else {
          EXPECT_NEAR(s2[i + j * na], r2[i + j * na], 1e-13 * scale) << i << ", " << j;
        }
    // x = A⁻¹E_T w from Y and the backward solve alone, against the full solve of the same
    // right-hand side (the entry of the −1 dof ignored, as a constrained one): round-off of
    // n-term sums, 1e-13 of x's scale (κ of the shifted Laplacian is O(10)).
    std::vector<double> w(na);
    tc::core::Vector b(a.rows());
    {
      auto bv = b.view();
      for (size_t q = 0; q < na; ++q) {
        w[q] = std::sin(1.0 + static_cast<double>(q));
        if (all[q] >= 0) bv[all[q]] = w[q];
      }
    }
    std::vector<double> x(static_cast<size_t>(a.rows()), -7.0);
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->solve_from_forward(*kept, w, x.data())));
    tc::core::Vector reference(a.rows());
    solver.solve(b, reference);
    const auto rv = reference.read();
    double xs = 0;
    for (PetscInt i = 0; i < a.rows(); ++i) xs = std::max(xs, std::abs(rv[i]));
    ASSERT_GT(xs, 0.0);
    for (PetscInt i = 0; i < a.rows(); ++i)
      EXPECT_NEAR(x[static_cast<size_t>(i)], rv[i], 1e-13 * xs) << i;
    // A solve in halves: z = L⁻¹P c for a c nonzero everywhere, (A⁻¹c)_T = Yᵀz without the
    // backward solve, then A⁻¹(c + E_T w) from z and Y, each against the full solve (the same
    // round-off bound; 0 at the −1 dof, which has no column in Y).
    tc::core::Vector c(a.rows()), cw(a.rows());
    {
      auto cv = c.view();
      for (PetscInt i = 0; i < a.rows(); ++i) cv[i] = std::cos(0.3 * static_cast<double>(i));
    }
    cw.copy_from(c);
    cw.axpy(1.0, b);
    std::vector<double> z, on_t(na, -7.0);
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->forward_half(c.read().span(), z)));
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->forward_values(*kept, z, on_t)));
    tc::core::Vector xc(a.rows()), xcw(a.rows());
    solver.solve(c, xc);
    solver.solve(cw, xcw);
    const auto xcv = xc.read();
    const auto xcwv = xcw.read();
    double cs = 0;
    for (PetscInt i = 0; i < a.rows(); ++i)
      cs = std::max({cs, std::abs(xcv[i]), std::abs(xcwv[i])});
    for (size_t q = 0; q < na; ++q)
      if (all[q] < 0)
        EXPECT_EQ(on_t[q], 0.0);
      else
        EXPECT_NEAR(on_t[q], xcv[all[q]], 1e-13 * cs) << q;
    ASSERT_TRUE((solver.cholmod() && solver.cholmod()->solve_from_forward(*kept, w, x.data(), z)));
    for (PetscInt i = 0; i < a.rows(); ++i)
      EXPECT_NEAR(x[static_cast<size_t>(i)], xcwv[i], 1e-13 * cs) << i;
  }
}

TEST(Petsc, CholeskyForwardCompliancePaysWhereItsFlopsAreFewer) {
  // The gate of S = YᵀY (forward_compliance_pays): a 44³ shifted Laplacian (85 184 unknowns)
  // and a 24 × 24 patch of its top face. Estimated from CHOLMOD's supernodes here, the
  // restricted solves cost 2.5·10¹⁰ flops, above the 10¹⁰ floor, the forward solves 1.05·10¹⁰
  // and the factorisation 3.1·10¹⁰: the forward path must be taken although the restricted
  // solves stay below the factorisation (the first gate asked for both and kept them, as it kept
  // them on the 10⁶-dof plate at 3.5× the time). The margins (2.4× and 2.5×) leave room for
  // another ordering of the same matrix. A 8 × 8 patch (2.2·10⁹ flops) stays below the floor.
  const PetscInt g = 44;
  const auto a = shifted_laplacian(g);
  const auto id = [&](PetscInt x, PetscInt y, PetscInt z) { return x + g * (y + g * z); };
  const auto patch = [&](PetscInt p) {
    std::vector<PetscInt> t;
    for (PetscInt y = 0; y < p; ++y)
      for (PetscInt x = 0; x < p; ++x) t.push_back(id(x, y, g - 1));
    return t;
  };
  // CHOLMOD only: the other packages' false is checked above, and PETSc's own Cholesky of this
  // size would take half a minute.
  const auto packages = tc::linalg::available_cholesky_packages();
  if (std::find(packages.begin(), packages.end(), MATSOLVERCHOLMOD) == packages.end())
    GTEST_SKIP() << "no CHOLMOD";
  tc::linalg::CholeskySolver solver(a, MATSOLVERCHOLMOD);
#if PETSC_VERSION_GE(3, 14, 0) && PETSC_VERSION_LT(3, 19, 0)  // where the path is compiled
  EXPECT_TRUE((solver.cholmod() && solver.cholmod()->forward_compliance_pays(patch(24), 64)));
#else
  EXPECT_FALSE((solver.cholmod() && solver.cholmod()->forward_compliance_pays(patch(24), 64)));
#endif
  EXPECT_FALSE((solver.cholmod() && solver.cholmod()->forward_compliance_pays(patch(8), 64)));
}
