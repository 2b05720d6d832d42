// The default dynamic contact scheme under refinement of τ on the 2D plane-strain section of
// the ch. 7.2.2 example (what is checked and why: contact_scheme_convergence.hpp). The 3D
// example itself is contact_scheme_convergence_slow.cpp (label slow: 150 s on the 2-core
// machine).
#include "contact_scheme_convergence.hpp"

namespace tc::test {
namespace {

TEST(ContactSchemeConvergence, Section2dSettlesUnderTauAndAgreesWithPlainNewmark) {
  // Slave 0.2 × 0.2 m of steel per metre of depth, dragged 0.05 m in 0.8 s.
  const double v = 0.05 / 0.8, rigid = 0.5 * 7859 * 0.2 * 0.2 * v * v;
  check(kSource / "tests/cases/verification/section-2d.toml", {0.01, 0.005, 0.0025}, rigid, "2d");
}

}  // namespace
}  // namespace tc::test
