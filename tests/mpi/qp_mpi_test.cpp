// The QP solvers on a distributed vector: the same problem solved on all ranks of
// PETSC_COMM_WORLD and, redundantly, on each rank alone (PETSC_COMM_SELF) must give the same
// solution to the tolerance and iteration counts within ±2. Run at 1 and 2 ranks (label mpi).
#include <gtest/gtest.h>

#include "support/qp_problems.hpp"
#include "tc/qp/mpgp.hpp"

namespace tc::test {
namespace {

struct Solved {
  qp::QpResult result;
  core::Vector x;
};

Solved solve(MPI_Comm comm, QpKind kind, PetscInt blocks, qp::QpOptions opt = {}) {
  auto p = random_qp(comm, blocks, kind, 1e3, 0.5, 0.1, 2024);
  qp::MatrixOperator f(p.f.get());
  opt.rtol = 1e-10;
  opt.max_iterations = 20000;
  Solved s{{}, p.x_star.duplicate()};
  s.result = qp::Mpgp(f, p.set, opt).solve(p.d, s.x);
  return s;
}

/// The default strategy, or (second parameter true) the longest-stepping alternatives:
/// Barzilai–Borwein lengths with projected CG expansions, whose accept/fall-back decisions
/// compare reductions (Δf) that must agree across ranks to round-off.
class Distributed : public ::testing::TestWithParam<std::tuple<QpKind, bool>> {};

TEST_P(Distributed, MatchesTheSingleRankSolve) {
  const auto [kind, alternative] = GetParam();
  const PetscInt blocks = 3000 / block_size(kind);
  qp::QpOptions opt;
  if (alternative) {
    opt.expansion = qp::Expansion::projected_cg;
    opt.expansion_step = qp::ExpansionStep::barzilai_borwein;
    opt.arc_step = qp::ExpansionStep::barzilai_borwein;
  }
  const auto world = solve(PETSC_COMM_WORLD, kind, blocks, opt);
  const auto self = solve(PETSC_COMM_SELF, kind, blocks, opt);
  ASSERT_TRUE(world.result.converged()) << world.result.message;
  ASSERT_TRUE(self.result.converged()) << self.result.message;

  PetscInt begin = 0, end = 0;
  TC_PETSC(VecGetOwnershipRange(world.x.get(), &begin, &end));
  const auto mine = world.x.to_std();
  const auto all = self.x.to_std();
  double diff = 0;
  for (PetscInt i = begin; i < end; ++i) diff = std::max(diff, std::abs(mine[i - begin] - all[i]));
  double global = diff;
  MPI_Allreduce(&diff, &global, 1, MPI_DOUBLE, MPI_MAX, PETSC_COMM_WORLD);
  // Both stop at ‖g^P‖ ≤ 1e-10‖d‖ with κ ≤ 1e3: each is within ~1e-7 of x* (qp_mprgp_test),
  // so they are within 2e-7 of each other; reductions in another order change only round-off.
  EXPECT_LT(global, 2e-7);
  EXPECT_LE(std::abs(world.result.iterations - self.result.iterations), 2)
      << "world " << world.result.iterations << ", self " << self.result.iterations;
  if (core::PetscSession::rank() == 0)
    std::printf("ranks %d: %d iterations (%d applications), one rank alone %d\n",
                core::PetscSession::size(), world.result.iterations,
                world.result.operator_applications, self.result.iterations);
}

std::string kind_name(const ::testing::TestParamInfo<std::tuple<QpKind, bool>>& info) {
  static const char* const names[] = {"free", "lower", "box", "disc", "contact3d"};
  return std::string(names[static_cast<int>(std::get<0>(info.param))]) +
         (std::get<1>(info.param) ? "_bb_projected_cg" : "");
}

INSTANTIATE_TEST_SUITE_P(Qp, Distributed,
                         ::testing::Combine(::testing::Values(QpKind::lower, QpKind::box,
                                                              QpKind::disc, QpKind::contact3d),
                                            ::testing::Bool()),
                         kind_name);

}  // namespace
}  // namespace tc::test
