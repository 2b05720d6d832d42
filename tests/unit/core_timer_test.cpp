// PhaseTimers: the time and the rise of the peak resident memory inside each phase
// (summary.json's wall_seconds and peak_memory_gib).
#include <gtest/gtest.h>

#include <chrono>
#include <thread>
#include <vector>

#include "tc/core/timer.hpp"

using namespace tc;

namespace {

constexpr double mib = 1024.0 * 1024.0;
volatile int g_sink = 0;  // the touched pages are read into it, so the allocation stays

// Touches every page of `bytes` so that they are resident, and returns something read from
// them so that the compiler keeps the allocation.
int touch(size_t bytes) {
  std::vector<char> v(bytes);
  for (size_t i = 0; i < v.size(); i += 4096) v[i] = static_cast<char>(i / 4096);
  return v[v.size() / 2];
}

TEST(PhaseTimers, AttributeTheRiseOfThePeakResidentMemoryToItsPhase) {
  core::PhaseTimers t;
  {
    auto s = t.scope("large");
    g_sink = g_sink + touch(static_cast<size_t>(256 * mib));
  }
  // 256 MiB made resident raise the high-water mark by at least 256 MiB less the slack the
  // process had under its earlier peak (its start-up, a few tens of MiB).
  EXPECT_GE(t.peak_growth("large"), 200 * mib);
  EXPECT_LE(t.peak_growth("large"), 300 * mib);  // plus at most the vector's own bookkeeping
  {
    auto s = t.scope("smaller");
    g_sink = g_sink + touch(static_cast<size_t>(128 * mib));
  }
  // Freed memory is reused: a phase below the earlier peak adds nothing to it.
  EXPECT_LT(t.peak_growth("smaller"), 16 * mib);
  EXPECT_EQ(t.peak_growth("never entered"), 0.0);
  EXPECT_GT(t["large"], 0.0);
  EXPECT_GE(core::peak_resident_bytes(), 256 * mib);
}

}  // namespace

TEST(PhaseTimers, ANestedPhasePausesTheOuterOneSoEachSecondCountsOnce) {
  // summary.json's phases add up to the run's wall time (issue 39): the time inside an inner
  // scope is the inner phase's only.
  core::PhaseTimers t;
  const auto wait = [](int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); };
  {
    auto outer = t.scope("outer");
    wait(20);
    {
      auto inner = t.scope("inner");
      wait(300);
    }
    wait(20);
  }
  // Sleeps last at least as asked; the outer's own 40 ms plus the scheduler's slack (260 ms
  // allowed, for a loaded machine) stays below the inner's 300 ms, which it counted too
  // before (≥ 340 ms).
  EXPECT_GE(t["inner"], 0.300);
  EXPECT_GE(t["outer"], 0.040);
  EXPECT_LT(t["outer"], 0.300);
}
