// MPRGP against PETSc TAO on bound-constrained QPs with a known solution: the instances up to
// 1000 unknowns, every kind (lower bounds and boxes, κ 1e2–1e4, 10–90 % active) with each of
// BQPIP, GPCG and BLMVM (but GPCG on the κ = 1e4 box). The error bound and the checks:
// qp_tao_agreement.hpp. The 2000- and 3000-unknown instances and GPCG on the 1000-unknown
// κ = 1e4 box (GPCG alone 43–179 s on one instance on the 2-core machine) are in
// qp_tao_slow.cpp (label slow, scripts/test-slow.sh).
#include "qp_tao_agreement.hpp"

namespace tc::test {
namespace {

std::vector<Param> small_instances() {
  auto out = with_every_solver({
      {10, QpKind::lower, 1e2, 0.5},
      {100, QpKind::lower, 1e2, 0.1},
      {100, QpKind::box, 1e2, 0.5},
      {1000, QpKind::lower, 1e4, 0.5},
      {1000, QpKind::lower, 1e2, 0.9},
      {1000, QpKind::box, 1e4, 0.9},
  });
  // GPCG on the κ = 1e4 box: 43 s (BQPIP and BLMVM on it 0.1 s): in qp_tao_slow.cpp.
  std::erase_if(out, [](const Param& p) {
    return std::string(p.solver) == TAOGPCG && p.c.kind == QpKind::box && p.c.kappa == 1e4;
  });
  return out;
}

INSTANTIATE_TEST_SUITE_P(Qp, AgreesWithTao, ::testing::ValuesIn(small_instances()), instance_name);

}  // namespace
}  // namespace tc::test
