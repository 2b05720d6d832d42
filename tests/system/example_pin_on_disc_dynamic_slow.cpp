// Example 09's dynamic case (examples/09-pin-on-disc/case-dynamic.toml: the pin-on-disc
// tribometer with inertia, the 200 N load through the rigid coupling, the collet accelerating
// the pin to 1 m/s over 4 ms) against the quasistatic run of the same data
// (`--set time.scheme=quasistatic`), as issue 41 asks: "the same case dynamic runs to the end
// and agrees with the quasistatic one within the inertia effects you state". The inertia here:
// the pin (2.2 g) accelerated at 250 m/s² for 4 ms needs 0.55 N from the collet, and its natural
// periods (~10 µs) are far below τ = 1 ms, so the rest is quasistatic. What is checked:
// - the friction law at every step of both runs: contact_tangential_force ≤ 𝔉 N (to the cone's
//   bound, 1e-6 relative); before issue 41's fix of the release floor the dynamic pin-on-disc
//   wrote T/N = 5.8 and a 1.1 kN tangential force;
// - the dynamic run's forces within the inertia of the pin of the quasistatic ones: N, T and
//   the collet's drag within 2 N (4 × the 0.55 N of the acceleration, which the trapezoidal
//   rule shows as ±m·2a step to step; measured: 1.0 N), the heat generated and conducted to
//   1e-4 relative (measured: equal to 7 digits);
// - the heat of Coulomb friction: heat_generated = 𝔉 × 200 N × 0.2 m within 0.5 %.
// Slow: 2 × 206 steps, ~40 s each on the shared 2-core VM.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "support/cli.hpp"
#include "support/history.hpp"

namespace tc::test {
namespace {

History run(const std::string& dir, const std::string& extra) {
  const auto out = fresh_dir(dir);
  const auto c = std::filesystem::path(TC_SOURCE_DIR) / "examples/09-pin-on-disc/case-dynamic.toml";
  const auto r =
      thermocontact(fmt::format("run {} --output {} {}", c.string(), out.string(), extra));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return read_history(out / "history.csv");
}

TEST(ExamplePinOnDiscDynamic, AgreesWithTheQuasistaticRunWithinThePinsInertia) {
  const auto dyn = run("example09-dynamic", "");
  const auto qs = run("example09-quasistatic", "--set time.scheme=quasistatic");
  ASSERT_TRUE(dyn.whole && qs.whole);
  ASSERT_EQ(dyn.rows.size(), 207u);  // t = 0 and 206 steps
  ASSERT_EQ(qs.rows.size(), dyn.rows.size());
  const double friction = 0.4, force = 200.0, slide = 0.2;
  for (const auto* h : {&dyn, &qs}) {
    const auto n = column(*h, "contact_normal_force");
    const auto t = column(*h, "contact_tangential_force");
    for (size_t k = 1; k < h->rows.size(); ++k)
      EXPECT_LE(t[k], friction * n[k] * (1 + 1e-6)) << "step " << k;
    EXPECT_NEAR(column(*h, "heat_generated").back(), friction * force * slide,
                0.005 * friction * force * slide);
  }
  for (const auto* name :
       {"contact_normal_force", "contact_tangential_force", "reaction_pin_collet_x"}) {
    const auto a = column(dyn, name), b = column(qs, name);
    for (size_t k = 1; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 2.0) << name << ", step " << k;
  }
  for (const auto* name : {"heat_generated", "heat_conducted"}) {
    const auto a = column(dyn, name), b = column(qs, name);
    EXPECT_NEAR(a.back(), b.back(), 1e-4 * std::abs(b.back())) << name;
  }
}

}  // namespace
}  // namespace tc::test
