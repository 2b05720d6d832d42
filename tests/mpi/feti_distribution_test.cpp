// The distribution of Feti's dual rows over the ranks (issue 8): every multiplier is owned by
// exactly one rank, and a solve with the rows split over all ranks gives the displacement of
// the solve with every row on one rank (PETSC_COMM_SELF). A row whose contribution were
// dropped or summed twice by the star forest would change F, d or the dots, and u with it.
// Run at 1 and 2 ranks (label mpi).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>

#include "support/problems.hpp"
#include "tc/feti/feti.hpp"
#include "tc/physics/body/body_system.hpp"

namespace tc::test {
namespace {

using physics::Scheme;

/// A clamped 3D block pulled on its far end, cut into 8 subdomains.
physics::Problem pulled_block() {
  auto p = box_problem(3, {0.2, 0.1, 0.1}, {8, 4, 4}, steel(), Scheme::quasistatic, 1e-3, 1);
  p.bodies[0].subdomains = 8;
  p.boundaries.push_back(hold("xmin", {0, 1, 2}));
  physics::BoundaryCondition pull;
  pull.where = "xmax";
  pull.traction[0] = core::TimeTable(2e7);
  pull.traction[1] = core::TimeTable(-1e7);
  p.boundaries.push_back(pull);
  return p;
}

struct Fixture {
  physics::Problem problem = pulled_block();
  physics::BodySystem sys{problem, 0};

  /// Quasistatic: TFETI with the projector; dynamic: A = K + 4/τ²M, deflation.
  [[nodiscard]] feti::Feti feti(MPI_Comm comm, bool dynamic) const {
    feti::FetiOptions o;
    o.comm = comm;
    o.tolerance = 1e-13;
    return {sys.subdomains(),
            sys.body().mesh.n_nodes(),
            3,
            sys.u_dirichlet_dofs(),
            feti::Kernel::rigid,
            dynamic ? feti::Singular::no : feti::Singular::yes,
            [&, dynamic](int s) {
              const auto m = sys.subdomain_matrices(s);
              auto a = m.stiffness_u.copy();
              if (dynamic) a.axpy(4 / (1e-3 * 1e-3), m.mass_u);
              return a;
            },
            o};
  }
};

double relative_difference(const std::vector<double>& a, const std::vector<double>& ref) {
  double diff = 0, norm = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    diff += (a[i] - ref[i]) * (a[i] - ref[i]);
    norm += ref[i] * ref[i];
  }
  return std::sqrt(diff / norm);
}

TEST(FetiDistribution, EveryMultiplierHasExactlyOneOwner) {
  const Fixture fx;
  const auto f = fx.feti(PETSC_COMM_WORLD, false);
  const int size = core::PetscSession::size();
  std::vector<long long> mine(f.owned_multipliers().begin(), f.owned_multipliers().end());
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(static_cast<size_t>(size)), offsets(static_cast<size_t>(size), 0);
  ASSERT_EQ(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, PETSC_COMM_WORLD),
            MPI_SUCCESS);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  std::vector<long long> all(static_cast<size_t>(offsets.back() + counts.back()));
  ASSERT_EQ(MPI_Allgatherv(mine.data(), n, MPI_LONG_LONG, all.data(), counts.data(), offsets.data(),
                           MPI_LONG_LONG, PETSC_COMM_WORLD),
            MPI_SUCCESS);
  // Σ local sizes = m, and the rows are 0 … m − 1 once each.
  EXPECT_EQ(static_cast<PetscInt>(all.size()), f.n_multipliers());
  std::sort(all.begin(), all.end());
  std::vector<long long> rows(static_cast<size_t>(f.n_multipliers()));
  std::iota(rows.begin(), rows.end(), 0LL);
  EXPECT_EQ(all, rows);
  // With more than one rank the rows are really split: every rank owns some (8 subdomains).
  for (const int c : counts) EXPECT_GT(c, 0);
  if (size > 1) {
    EXPECT_LT(n, f.n_multipliers());
  }
}

TEST(FetiDistribution, SplitRowsGiveTheReplicatedDisplacement) {
  const Fixture fx;
  for (const bool dynamic : {false, true}) {
    std::vector<double> u[2];
    for (const int i : {0, 1}) {
      const auto f = fx.feti(i == 0 ? PETSC_COMM_SELF : PETSC_COMM_WORLD, dynamic);
      core::Vector b(fx.sys.n_u()), x(fx.sys.n_u());
      fx.sys.mechanical_load(0.0, b);
      f.solve(b, x);
      u[i] = x.to_std();
    }
    EXPECT_LT(relative_difference(u[1], u[0]), 1e-10) << (dynamic ? "deflated" : "projected");
  }
}

// Several right-hand sides travel through the star forest together (a block of k columns).
TEST(FetiDistribution, SplitRowsGiveTheReplicatedBlockSolve) {
  const Fixture fx;
  const PetscInt n = fx.sys.n_u(), k = 3;
  std::vector<double> rhs(static_cast<size_t>(n * k));
  for (PetscInt j = 0; j < k; ++j)
    for (PetscInt i = 0; i < n; ++i)
      rhs[static_cast<size_t>(j * n + i)] = std::sin(0.37 * static_cast<double>(i) + j);
  std::vector<double> u[2];
  for (const int i : {0, 1}) {
    const auto f = fx.feti(i == 0 ? PETSC_COMM_SELF : PETSC_COMM_WORLD, false);
    core::Handle<::Mat, MatDestroy> b, x;
    ASSERT_EQ(MatCreateSeqDense(PETSC_COMM_SELF, n, k, rhs.data(), b.out()), 0);
    ASSERT_EQ(MatCreateSeqDense(PETSC_COMM_SELF, n, k, nullptr, x.out()), 0);
    f.solve_homogeneous_many(b.get(), x.get());
    const double* xv = nullptr;
    ASSERT_EQ(MatDenseGetArrayRead(x.get(), &xv), 0);
    u[i].assign(xv, xv + n * k);
    ASSERT_EQ(MatDenseRestoreArrayRead(x.get(), &xv), 0);
  }
  EXPECT_LT(relative_difference(u[1], u[0]), 1e-10);
}

}  // namespace
}  // namespace tc::test
