// The default dynamic contact scheme under refinement of τ on the ch. 7.2.2 example itself
// (examples/06, all couplings on) at τ/2 and τ/4, against plain Newmark (what is checked and
// why: contact_scheme_convergence.hpp). Label slow: about 150 s on the 2-core machine; the 2D
// section, the same checks at τ, τ/2, τ/4, stays in the default suite
// (contact_scheme_convergence_test.cpp). Run by scripts/test-slow.sh.
#include "contact_scheme_convergence.hpp"

namespace tc::test {
namespace {

TEST(ContactSchemeConvergence, Example06SettlesUnderTauAndAgreesWithPlainNewmark) {
  const double v = 0.05 / 0.8, rigid = 0.5 * 7859 * 0.2 * 0.2 * 0.2 * v * v;
  check(kSource / "examples/06-thesis-frictional-heating/case.toml", {0.005, 0.0025}, rigid, "3d");
}

}  // namespace
}  // namespace tc::test
