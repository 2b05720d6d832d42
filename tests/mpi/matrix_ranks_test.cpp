// Matrices with their rows spread over the ranks (core::SparseMatrix::over_ranks, assembled by
// fem::assemble with RowBlocks: M_u, K_u, the rectangular K_uθ, M_θ, K_θ, a film's boundary
// mass, a lumped M_θ) against the same matrices assembled whole on each rank: every
// product the time loop takes, the operations forming and constraining an operator, CG on the
// mass matrix, and the constrained solver on a spread operator. Run at 1 and 2 ranks (label
// mpi): at 1 rank the spread matrix is an MPIAIJ holding every row, at 2 each holds half.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <vector>

#include "support/problems.hpp"
#include "support/vectors.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/dual/constrained_solver.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/mesh/box.hpp"

namespace tc::test {
namespace {

// A slanted box (uneven cells) so that no two rows are alike and a row taken from the wrong
// rank or place shows.
mesh::Mesh some_mesh() {
  return mesh::make_box(3, {0.0, 0.0, 0.0}, {1.0, 0.7, 0.4}, {5, 4, 3});
}

bool same_on_every_rank(const core::Vector& x) {
  const double here = x.norm();
  double low = 0, high = 0;
  MPI_Allreduce(&here, &low, 1, MPI_DOUBLE, MPI_MIN, PETSC_COMM_WORLD);
  MPI_Allreduce(&here, &high, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  return low == high;
}

// Products summed in another order (PETSc's MPIAIJ: this rank's columns, then the others):
// round-off of the row sums, some 1e-16 of the largest term; 1e-13 of the result's size is a
// margin of 100s and fails for any misplaced row or block (errors of order the result).
constexpr double kProduct = 1e-13;

struct Pair {
  fem::BodyMatrices whole, spread;
};

Pair both() {
  const auto m = some_mesh();
  const auto mat = steel();
  const auto blocks = core::RowBlocks::over(PETSC_COMM_WORLD, 3 * m.n_nodes());
  const auto theta = core::RowBlocks::over(PETSC_COMM_WORLD, m.n_nodes());
  return {fem::assemble_body(m, mat), fem::assemble_body(m, mat, &blocks, &theta)};
}

// y = A x, y += A x and y = Aᵀx of the spread b against the whole a (square or not).
void expect_products_agree(const core::SparseMatrix& a, const core::SparseMatrix& b) {
  const PetscInt rows = a.rows(), cols = a.cols();
  const auto x = some_vector(cols, 0.3);
  core::Vector y(rows), z(rows);
  a.mult(x, y);
  b.mult(x, z);
  EXPECT_LT(max_abs_diff(y, z), kProduct * y.max_abs());
  EXPECT_TRUE(same_on_every_rank(z));
  y = some_vector(rows, 2.0);
  z = y.clone();
  a.mult_add(x, y);
  b.mult_add(x, z);
  EXPECT_LT(max_abs_diff(y, z), kProduct * y.max_abs());
  EXPECT_TRUE(same_on_every_rank(z));
  const auto u = some_vector(rows, 1.7);
  core::Vector s(cols), t(cols);
  a.mult_transpose(u, s);
  b.mult_transpose(u, t);
  EXPECT_LT(max_abs_diff(s, t), kProduct * s.max_abs());
  EXPECT_TRUE(same_on_every_rank(t));
}

TEST(MatrixOverRanks, ProductsAreTheWholeMatrixsGatheredOnEveryRank) {
  const auto [whole, spread] = both();
  int size = 1;
  MPI_Comm_size(PETSC_COMM_WORLD, &size);
  ASSERT_TRUE(spread.stiffness_u.distributed());
  ASSERT_TRUE(spread.coupling_u_theta.distributed());
  ASSERT_TRUE(spread.mass_theta.distributed());
  ASSERT_TRUE(spread.stiffness_theta.distributed());
  EXPECT_EQ(spread.stiffness_u.row_blocks().here() == spread.stiffness_u.rows(), size == 1);
  // K_uθ is rectangular: its columns are dealt as the temperature dofs (u ← θ and θ ← u).
  expect_products_agree(whole.coupling_u_theta, spread.coupling_u_theta);
  for (const auto& [a, b] : {std::pair{&whole.stiffness_u, &spread.stiffness_u},
                             {&whole.mass_u, &spread.mass_u},
                             {&whole.mass_theta, &spread.mass_theta},
                             {&whole.stiffness_theta, &spread.stiffness_theta}}) {
    expect_products_agree(*a, *b);
    const auto x = some_vector(a->rows(), 0.3);
    core::Vector w(a->rows());
    const double qa = a->quadratic_form(x, w), qb = b->quadratic_form(x, w);
    EXPECT_NEAR(qa, qb, kProduct * std::abs(qa));
    EXPECT_NEAR(core::mean_diagonal(*a), core::mean_diagonal(*b), 1e-14 * core::mean_diagonal(*a));
  }
}

TEST(MatrixOverRanks, OperatorsFormedAndConstrainedAsTheWholeOnes) {
  const auto [whole, spread] = both();
  const PetscInt n = whole.stiffness_u.rows();
  // 4/τ² M + K (combine's copy, scale and axpy), then the face z = 0 clamped.
  auto a = whole.mass_u.copy(), b = spread.mass_u.copy();
  a.scale(4e4);
  b.scale(4e4);
  a.axpy(1.0, whole.stiffness_u);
  b.axpy(1.0, spread.stiffness_u);
  std::vector<PetscInt> fixed;
  for (PetscInt r = 0; r < 3 * 30; ++r) fixed.push_back(r);  // the 6 × 5 nodes of z = 0
  auto ca = a.copy(), cb = b.copy();
  ca.zero_rows_columns(fixed, 7.0);
  cb.zero_rows_columns(fixed, 7.0);
  const auto x = some_vector(n, 1.1);
  core::Vector y(n), z(n);
  ca.mult(x, y);
  cb.mult(x, z);
  EXPECT_LT(max_abs_diff(y, z), kProduct * y.max_abs());
  EXPECT_EQ(z.read()[fixed.back()], 7.0 * x.read()[fixed.back()]);

  // The constrained solver on the spread operator, its Dirichlet data lifted on each rank's
  // rows: direct solves, each exact to a backward error of a few ε of an operator with κ
  // ≈ 1e4 here, so 1e-10 of the solution is a margin of ~50.
  const physics::ConstrainedSolver sa(a, fixed, "", linalg::FactorRanks::this_rank);
  const physics::ConstrainedSolver sb(b, fixed, "", linalg::FactorRanks::all_ranks);
  auto ua = some_vector(n, 0.0), ub = ua.clone();
  sa.solve(x, ua);
  sb.solve(x, ub);
  EXPECT_LT(max_abs_diff(ua, ub), 1e-10 * ua.max_abs());
  EXPECT_TRUE(same_on_every_rank(ub));
}

TEST(MatrixOverRanks, ConjugateGradientsOnTheSpreadMassMatrix) {
  const auto [whole, spread] = both();
  const PetscInt n = whole.mass_u.rows();
  const auto b = some_vector(n, 0.7);
  core::Vector xa(n), xb(n);
  int ia = 0, ib = 0;
  const double ra = core::jacobi_cg(whole.mass_u, b, xa, 1e-12, 500, ia);
  const double rb = core::jacobi_cg(spread.mass_u, b, xb, 1e-12, 500, ib);
  EXPECT_LE(ra, 1e-12);
  EXPECT_LE(rb, 1e-12);
  // Both within 1e-12 of the residual of a mass matrix of κ ≤ 27 once Jacobi-scaled
  // (Wathen): the solutions agree to ~1e-11 of their size.
  EXPECT_LT(max_abs_diff(xa, xb), 1e-10 * xa.max_abs());
  EXPECT_TRUE(same_on_every_rank(xb));
  EXPECT_NEAR(ia, ib, 2);
}

TEST(MatrixOverRanks, LumpedMassAndFilmMatrixAsTheWholeOnes) {
  // Row sums and a film's h∫N_aN_b dS on the face z = 0: the same rows as the whole ones',
  // which the products show (a misplaced sum or facet changes entries by their own size).
  const auto m = some_mesh();
  const auto theta = core::RowBlocks::over(PETSC_COMM_WORLD, m.n_nodes());
  auto [whole, spread] = both();
  core::Vector ones(m.n_nodes()), work(m.n_nodes());
  ones.fill(1.0);
  const double total = whole.mass_theta.quadratic_form(ones, work);  // ∫ρc dx, kept by lumping
  fem::lump_rows(whole.mass_theta);
  fem::lump_rows(spread.mass_theta);
  expect_products_agree(whole.mass_theta, spread.mass_theta);
  EXPECT_NEAR(spread.mass_theta.quadratic_form(ones, work), total, 1e-13 * total);
  // diagonal alone: a unit vector's product is its row sum on that row, nothing elsewhere
  core::Vector e(m.n_nodes()), y(m.n_nodes());
  e.view()[7] = 1.0;
  spread.mass_theta.mult(e, y);
  EXPECT_GT(y.read()[7], 0.0);
  EXPECT_EQ(y.max_abs(), y.read()[7]);
  EXPECT_EQ(y.sum(), y.read()[7]);
  std::vector<fem::WeightedFacet> film;
  for (const auto& f : m.boundary("zmin")) film.push_back({f, 25.0});
  const auto a = fem::boundary_mass(m, film), b = fem::boundary_mass(m, film, &theta);
  ASSERT_TRUE(b.distributed());
  expect_products_agree(a, b);
  auto sum = whole.mass_theta.copy();
  sum.axpy(1.0, a);
  auto spread_sum = spread.mass_theta.copy();
  spread_sum.axpy(1.0, b);  // A_θ + H: the patterns shared over the ranks too
  expect_products_agree(sum, spread_sum);
}

TEST(MatrixOverRanks, AKernelThrowingOnOneRanksCellsStopsEveryRank) {
  // The last cell's rows belong to the last rank only: its kernel throws there alone. Every
  // rank must throw (collective_check), none wait in the assembly's communication: without
  // it the other ranks hang there and ctest's timeout (120 s, tests/CMakeLists.txt) fails the
  // test.
  const auto m = some_mesh();
  const auto theta = core::RowBlocks::over(PETSC_COMM_WORLD, m.n_nodes());
  const auto g = fem::node_graph(m);
  const int bad = m.n_cells() - 1;
  const fem::CellKernel kernel = [&](int c, auto, const auto&) -> Eigen::MatrixXd {
    if (c == bad) throw Error("a bad cell");
    return Eigen::MatrixXd::Identity(8, 8);
  };
  EXPECT_THROW((void)fem::assemble(m, g, 1, 1, kernel, &theta), Error);
}

}  // namespace
}  // namespace tc::test
