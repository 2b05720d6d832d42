// bench/feti: numerical and parallel scalability of Total FETI (6.2) on one elastic cube
// [0,1]³ (steel, clamped at zmin, pulled at zmax, body force), H/h fixed at 8 elements per
// subdomain edge: 2³ → 3³ → 4³ → 5³ subdomains on (8s)³ Hex8 cells. Per size and
// preconditioner: projected-CG iterations of one quasistatic solve (TFETI, rigid-body coarse
// space), of one dynamic solve (τ = 1 ms, the same space as deflation), the time of a solve
// per subdomain per iteration, set-up time, and the ratio of a FETI solve to the direct
// Cholesky solve of the whole body (same run). Prints Markdown tables.
//
//   build/bin/bench_feti                 scalability table (s = 2 … 5)
//   build/bin/bench_feti size N S        one quasistatic solve on N³ cells, S subdomains:
//                                        time and peak memory (the largest size that fits)
//   mpirun -n 2 build/bin/bench_feti ... the subdomains dealt to two ranks
#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <string>

#include "../../tests/support/problems.hpp"
#include "tc/core/petsc.hpp"
#include "tc/physics/body_system.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using namespace tc;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double peak_rss_gib() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / (1024.0 * 1024.0);  // ru_maxrss is in KiB
}

physics::Problem cube(int n, int subdomains, physics::Scheme scheme) {
  auto p = test::box_problem(3, {1, 1, 1}, {n, n, n}, test::steel(), scheme, 1e-3, 1);
  p.bodies[0].subdomains = subdomains;
  p.bodies[0].body_force[2] = core::TimeTable(-7.7e4);
  p.boundaries.push_back(test::hold("zmin", {0, 1, 2}));
  physics::BoundaryCondition pull;
  pull.where = "zmax";
  pull.traction[0] = core::TimeTable(1e6);
  pull.traction[2] = core::TimeTable(2e6);
  p.boundaries.push_back(pull);
  return p;
}

struct Run {
  int iterations = 0;
  double setup = 0, solve = 0;
  PetscInt multipliers = 0;
  int coarse = 0;
};

Run feti_solve(const physics::BodySystem& sys, physics::Scheme scheme, feti::Preconditioner pc) {
  const bool dynamic = scheme == physics::Scheme::Dynamic;
  feti::FetiOptions o;
  o.preconditioner = pc;
  o.tolerance = 1e-8;
  o.max_iterations = 5000;
  Run r;
  auto t0 = Clock::now();
  const feti::Feti f(
      sys.subdomains(), sys.body().mesh.n_nodes(), 3, sys.u_dirichlet_dofs(), feti::Kernel::rigid,
      dynamic ? feti::Singular::no : feti::Singular::yes,
      [&](int s) {
        auto m = sys.subdomain_matrices(s);
        auto a = m.stiffness_u.copy();
        if (dynamic) a.axpy(4.0 / 1e-6, m.mass_u);
        return a;
      },
      o);
  r.setup = since(t0);
  core::Vector b(sys.n_u()), x(sys.n_u());
  sys.mechanical_load(0.0, b);
  t0 = Clock::now();
  f.solve(b, x);
  r.solve = since(t0);
  r.iterations = f.statistics().last_iterations;
  r.multipliers = f.n_multipliers();
  r.coarse = f.coarse_dimension();
  return r;
}

double direct_solve_seconds(const physics::BodySystem& sys) {
  core::CholeskySolver c(
      [&] {
        auto a = sys.matrices().stiffness_u.copy();
        a.zero_rows_columns(sys.u_dirichlet_dofs(), 1.0);
        return a;
      }(),
      "");
  core::Vector b(sys.n_u()), x(sys.n_u());
  sys.mechanical_load(0.0, b);
  const auto t0 = Clock::now();
  c.solve(b, x);
  return since(t0);
}

void scalability() {
  const bool root = core::PetscSession::rank() == 0;
  if (root)
    fmt::print(
        "| subdomains | cells | dofs | multipliers | coarse dim | preconditioner | "
        "quasistatic its | dynamic its | set-up (s) | solve (s) | ms per subdomain·iteration | "
        "solve / direct solve |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int s = 2; s <= 5; ++s) {
    const int n = 8 * s;
    const auto p = cube(n, s * s * s, physics::Scheme::Quasistatic);
    const physics::BodySystem sys(p, 0);
    const double direct = direct_solve_seconds(sys);
    for (const auto pc : {feti::Preconditioner::dirichlet, feti::Preconditioner::lumped,
                          feti::Preconditioner::none}) {
      const auto q = feti_solve(sys, physics::Scheme::Quasistatic, pc);
      const auto d = feti_solve(sys, physics::Scheme::Dynamic, pc);
      if (root)
        fmt::print(
            "| {} | {}³ | {} | {} | {} | {} | {} | {} | {:.2f} | {:.3f} | {:.3f} | {:.1f} |\n",
            s * s * s, n, sys.n_u(), q.multipliers, q.coarse, feti::name(pc), q.iterations,
            d.iterations, q.setup, q.solve, 1e3 * q.solve / (s * s * s * std::max(1, q.iterations)),
            q.solve / direct);
    }
  }
}

void size(int n, int subdomains) {
  const auto t0 = Clock::now();
  const auto p = cube(n, subdomains, physics::Scheme::Quasistatic);
  const physics::BodySystem sys(p, 0);
  const double assembly = since(t0);
  const auto r = feti_solve(sys, physics::Scheme::Quasistatic, feti::Preconditioner::dirichlet);
  if (core::PetscSession::rank() == 0)
    fmt::print(
        "| {}³ cells | {} dofs | {} subdomains | {} multipliers | assembly+partition {:.1f} s | "
        "FETI set-up {:.1f} s | solve {:.1f} s | {} iterations | peak RSS {:.2f} GiB (rank 0) |\n",
        n, sys.n_u(), subdomains, r.multipliers, assembly, r.setup, r.solve, r.iterations,
        peak_rss_gib());
}

}  // namespace

int main(int argc, char** argv) {
  int pargc = 1;
  char** pargv = argv;
  core::PetscSession session(&pargc, &pargv);
  if (argc >= 4 && std::string(argv[1]) == "size")
    size(std::stoi(argv[2]), std::stoi(argv[3]));
  else
    scalability();
  return 0;
}
