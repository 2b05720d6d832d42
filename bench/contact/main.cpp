// bench/contact: the 3D sliding block (examples/04-sliding-block-3d, built in code) at three
// mesh sizes, with the dual operator F formed explicitly and applied matrix-free. Per mesh and
// kind: time per step and its phases, QP iterations and operator applications per step, and
// the ratio of the time per step to one forward/backward solve with the factorised master
// matrix (the floor: a contact step cannot cost less than one solve). Growth exponents by
// least squares of log(time per step) against log(dofs). Prints Markdown tables.
//
//   build/bin/bench_contact [steps]      (default 6: 2 pressing, 4 sliding)
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "../../tests/support/problems.hpp"  // steel(): the constants the tests use
#include "../support/growth.hpp"
#include "../support/sliding_blocks.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/mesh/box.hpp"
#include "tc/run/simulation.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace tc;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// The example's bodies and loads with the given cells; `steps` of 0.1 s: pressed by 0.1 mm
/// over the first two, then dragged along y by 8.6 mm per step (the example's speed).
physics::Problem sliding_block(std::array<int, 3> master, std::array<int, 3> slave, int steps) {
  auto p =
      bench::two_steel_blocks(mesh::make_box(3, {-0.15, -0.15, -0.2}, {0.15, 0.85, 0.0}, master),
                              mesh::make_box(3, {-0.1, -0.1, 0.0}, {0.1, 0.1, 0.2}, slave), steps);
  const double end = 0.1 * steps;
  bench::clamp_and_drag(p, 0.2, 1e-4, end, 0.3 / 35 * (steps - 2));
  auto c = test::contact_pair(1, "zmin", 0, "zmax", 0.3);
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  return p;
}

struct Counts : physics::Observer {
  long qp = 0, applications = 0, coupling = 0;
  void step(const physics::Simulation& sim) override {
    if (sim.step() == 0) return;
    qp += static_cast<long>(sim.history("qp_iterations"));
    applications += static_cast<long>(sim.history("operator_applications"));
    coupling += static_cast<long>(sim.history("coupling_iterations"));
  }
};

struct Row {
  PetscInt dofs = 0, multipliers = 0;
  double per_step = 0, solve = 0, mortar = 0, setup = 0, qp_time = 0, heat = 0, mech = 0;
  double qp = 0, applications = 0, coupling = 0;
};

/// The floor: one forward/backward solve with the master's factorised K_u (Dirichlet
/// eliminated), the largest matrix of the step, timed over repeated solves.
double one_solve(const physics::Problem& p) {
  const physics::BodySystem sys(p, 0);
  const physics::ConstrainedSolver s(sys.matrices().stiffness_u, sys.u_dirichlet_dofs(), "");
  core::Vector b(sys.n_u()), x(sys.n_u());
  b.fill(1.0);
  s.solve(b, x);
  const int reps = 20;
  const auto t0 = Clock::now();
  for (int i = 0; i < reps; ++i) s.solve(b, x);
  return since(t0) / reps;
}

Row run(const physics::Problem& p, PetscInt explicit_limit, int steps) {
  physics::Simulation sim(p);
  physics::DualContactSettings settings;
  settings.explicit_limit = explicit_limit;
  sim.enable_mortar_contact(settings);
  Counts counts;
  const auto t0 = Clock::now();
  const auto status = sim.run(counts);
  const double total = since(t0);
  if (!status.completed) fmt::print("  stopped: {}\n", status.message);
  const auto& t = sim.timers();
  Row r;
  r.dofs = sim.n_dofs();
  r.multipliers = sim.dual_solver()->rows().n_rows();
  r.per_step = total / steps;
  r.mortar = t["mortar"] / steps;
  r.setup = t["dual_setup"] / steps;
  r.qp_time = t["qp"] / steps;
  r.heat = t["heat_solve"] / steps;
  r.mech = t["mechanical_solve"] / steps;
  r.qp = static_cast<double>(counts.qp) / steps;
  r.applications = static_cast<double>(counts.applications) / steps;
  r.coupling = static_cast<double>(counts.coupling) / steps;
  r.solve = one_solve(p);
  return r;
}

double slope(const std::vector<Row>& rows) {
  std::vector<double> dofs, time;
  for (const auto& r : rows) {
    dofs.push_back(static_cast<double>(r.dofs));
    time.push_back(r.per_step);
  }
  return bench::growth_exponent(dofs, time);
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::stoi(argv[1]) : 6;
  int pargc = 1;
  core::PetscSession session(&pargc, &argv);
  const std::vector<std::pair<std::array<int, 3>, std::array<int, 3>>> meshes = {
      {{6, 20, 4}, {5, 5, 4}}, {{9, 30, 6}, {8, 8, 6}}, {{12, 40, 8}, {10, 10, 8}}};
  for (const auto& [kind, limit] :
       {std::pair{"explicit", PetscInt{100000}}, std::pair{"matrix-free", PetscInt{0}}}) {
    std::vector<Row> rows;
    fmt::print("\n### F {} ({} steps: 2 pressing, {} sliding)\n\n", kind, steps, steps - 2);
    fmt::print(
        "| dofs | multipliers | s/step | / one solve | mortar | dual setup | QP | heat + mech | "
        "QP it./step | F appl./step | coupling it./step |\n|---|---|---|---|---|---|---|---|---|"
        "---|---|\n");
    for (const auto& [master, slave] : meshes) {
      const auto p = sliding_block(master, slave, steps);
      const auto r = run(p, limit, steps);
      rows.push_back(r);
      fmt::print(
          "| {} | {} | {:.3f} | {:.0f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} | {:.0f} | {:.0f} | "
          "{:.1f} |\n",
          r.dofs, r.multipliers, r.per_step, r.per_step / r.solve, r.mortar, r.setup, r.qp_time,
          r.heat + r.mech, r.qp, r.applications, r.coupling);
      std::fflush(stdout);
    }
    fmt::print("\ngrowth exponent of the time per step in the dofs: {:.2f}\n", slope(rows));
  }
  return 0;
}
