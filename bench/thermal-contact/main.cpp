// bench/thermal-contact: the thesis' chapter 7 examples (examples/05-thesis-heat-transfer,
// 06-thesis-frictional-heating) run without output: wall time in total and per phase,
// coupling iterations, QP iterations and applications of F per step. The goal of issue 7 is
// each example under 2 s on 2 cores. Prints a Markdown table. "CPU" is the process' CPU time
// of the case (the shared machine's load inflates the wall times; run with
// OPENBLAS_NUM_THREADS=1: the solves' BLAS threads spin against the other processes).
//
//   build/bin/bench_thermal-contact [--ab] [--loops] [case.toml ...]   (default: the examples)
//
// --ab runs each case twice in turn, as committed and with the explicit F formed by 2m solves
// every step and the QP unscaled (the state before issue 7's speed work), for a comparison
// under the same load. --loops adds a run with the Tresca → Coulomb updates staggered with
// the heat step (FrictionLoop::staggered) instead of nested in the mechanical half.
#include <fmt/format.h>

#include <chrono>
#include <ctime>
#include <string>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/run/simulation.hpp"

namespace {

using Clock = std::chrono::steady_clock;

struct Counts : tc::physics::Observer {
  long qp = 0, applications = 0, coupling = 0, friction = 0;
  int max_coupling = 0;
  void step(const tc::physics::Simulation& sim) override {
    if (sim.step() == 0) return;
    qp += static_cast<long>(sim.history("qp_iterations"));
    applications += static_cast<long>(sim.history("operator_applications"));
    const int c = static_cast<int>(sim.history("coupling_iterations"));
    coupling += c;
    friction += static_cast<long>(sim.history("friction_iterations"));
    max_coupling = std::max(max_coupling, c);
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> cases;
  bool ab = false, loops = false;
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]) == "--ab")
      ab = true;
    else if (std::string(argv[i]) == "--loops")
      loops = true;
    else
      cases.emplace_back(argv[i]);
  }
  if (cases.empty())
    cases = {TC_SOURCE_DIR "/examples/05-thesis-heat-transfer/case.toml",
             TC_SOURCE_DIR "/examples/06-thesis-frictional-heating/case.toml"};
  int pargc = 1;
  tc::core::PetscSession session(&pargc, &argv);
  fmt::print(
      "| case | dofs | steps | total [s] | CPU [s] | assembly + factorisation | mortar | dual "
      "set-up | QP | "
      "heat | mechanics | coupling it./step (max) | γ updates/step | QP it./step | F appl./step |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  enum class Variant { committed, before, staggered };
  std::vector<std::pair<std::string, Variant>> runs;
  for (const auto& file : cases) {
    runs.emplace_back(file, Variant::committed);
    if (ab) runs.emplace_back(file, Variant::before);
    if (loops) runs.emplace_back(file, Variant::staggered);
  }
  for (const auto& [file, variant] : runs) {
    const bool before = variant == Variant::before;
    auto problem = tc::io::read_case(file);
    if (variant == Variant::staggered)
      problem.solver.friction_loop = tc::physics::FrictionLoop::staggered;
    const auto t0 = Clock::now();
    const std::clock_t c0 = std::clock();
    tc::physics::Simulation sim(problem);
    tc::physics::DualContactSettings settings;
    if (before) {
      settings.compliance_limit = 0;
      settings.scale = false;
    }
    if (!problem.contacts.empty()) sim.enable_mortar_contact(settings);
    Counts counts;
    const auto status = sim.run(counts);
    const double total = std::chrono::duration<double>(Clock::now() - t0).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    if (!status.completed) fmt::print("stopped: {}\n", status.message);
    const auto& t = sim.timers();
    const double n = std::max(1, status.steps_done);
    const auto name =
        file.substr(file.find("examples/") == std::string::npos ? 0 : file.find("examples/") + 9) +
        (before                          ? " (F by solves, unscaled)"
         : variant == Variant::staggered ? " (γ updates staggered with the heat step)"
                                         : "");
    fmt::print(
        "| {} | {} | {} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | {:.2f} | "
        "{:.1f} "
        "({}) | {:.1f} | {:.0f} | {:.0f} |\n",
        name, sim.n_dofs(), status.steps_done, total, cpu, t["assembly"] + t["factorization"],
        t["mortar"], t["dual_setup"], t["qp"], t["heat_solve"], t["mechanical_solve"],
        static_cast<double>(counts.coupling) / n, counts.max_coupling,
        static_cast<double>(counts.friction) / n, static_cast<double>(counts.qp) / n,
        static_cast<double>(counts.applications) / n);
    std::fflush(stdout);
  }
  return 0;
}
