// The progress line of a run (ProgressLine, output.hpp): step, time, iterations, elapsed and
// ETA on standard error in a terminal (rewritten in place), else ~20 lines on standard output.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "tc/core/numeric/petsc.hpp"
#include "tc/io/output/output.hpp"

namespace tc::io {

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace

ProgressLine::ProgressLine(bool terminal)
    : terminal_(terminal), root_(core::PetscSession::rank() == 0), start_(now_seconds()) {}

void ProgressLine::step(const physics::Simulation& sim) {
  if (!root_) return;
  const int n = sim.problem().time.n_steps();
  const int k = sim.step();
  if (k == 0) {
    start_ = now_seconds();
    return;
  }
  const double elapsed = now_seconds() - start_;
  const double eta = elapsed / k * (n - k);
  const auto text =
      fmt::format("step {}/{}  t = {:.4g} s  coupling {}  qp {}  elapsed {:.1f} s  ETA {:.1f} s", k,
                  n, sim.time(), static_cast<int>(sim.history("coupling_iterations")),
                  static_cast<int>(sim.history("qp_iterations")), elapsed, eta);
  if (terminal_) {
    fmt::print(stderr, "\r{:<100}", text);
    std::fflush(stderr);
  } else if (k == n || k % std::max(1, n / 20) == 0) {
    fmt::print("{}\n", text);
    std::fflush(stdout);
  }
}

void ProgressLine::warning(const physics::Simulation&, const std::string& message) {
  if (!root_) return;
  fmt::print(stderr, "{}warning: {}\n", terminal_ ? "\n" : "", message);
  std::fflush(stderr);
}

void ProgressLine::finish(const physics::Simulation&, const physics::RunStatus&) {
  if (root_ && terminal_) fmt::print(stderr, "\n");
}

}  // namespace tc::io
