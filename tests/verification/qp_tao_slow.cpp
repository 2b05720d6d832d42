// MPRGP against PETSc TAO on the large bound-constrained QPs (2000 and 3000 unknowns, and
// GPCG on the 1000-unknown κ = 1e4 box): the same checks as qp_tao_test.cpp
// (qp_tao_agreement.hpp), label slow: TAO's GPCG alone took 43–179 s on one of them on the
// 2-core machine. Run by scripts/test-slow.sh.
#include "qp_tao_agreement.hpp"

namespace tc::test {
namespace {

std::vector<Param> large_instances() {
  auto out = with_every_solver({
      {2000, QpKind::lower, 1e3, 0.1},
      {3000, QpKind::box, 1e3, 0.5},
      {3000, QpKind::lower, 1e2, 0.9},
  });
  out.push_back({{1000, QpKind::box, 1e4, 0.9}, TAOGPCG});  // 43 s; the others on it are quick
  return out;
}

INSTANTIATE_TEST_SUITE_P(Qp, AgreesWithTao, ::testing::ValuesIn(large_instances()), instance_name);

}  // namespace
}  // namespace tc::test
