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
//   build/bin/bench_feti contact H S [steps [S_min]]
//                                        two blocks in frictional contact through Simulation,
//                                        H/h = H cells per subdomain edge, each body cut into
//                                        s³ subdomains for s = S_min (2) … S, `steps` quasistatic
//                                        steps (default 3: pressed, then sliding): FETI iterations
//                                        per solve, contact QP iterations, time per
//                                        subdomain·iteration (TC_BENCH_DYNAMIC=1 in the
//                                        environment: dynamic steps, the deflated FETI)
//   build/bin/bench_feti combined H S [S_min [lumped]]
//                                        one quasistatic contact solve of the two blocks
//                                        (bench/support/two_block_feti.hpp), each cut into s³
//                                        subdomains of H/h = H for s = S_min (2) … S, by the
//                                        nested form (contact dual on each body's FETI) and the
//                                        combined one (feti::ContactFeti, SMALBE): iterations,
//                                        applications, time, and the difference of the results
//   build/bin/bench_feti block N S K     one quasistatic block solve of K right-hand sides on N³
//                                        cells, S subdomains (solve_homogeneous_many): time;
//                                        PETSC_OPTIONS=-tc_feti_sf_row_major moves the block
//                                        through the star forest as rows of k doubles
//   build/bin/bench_feti transfer M K    the star forest of Feti's dual rows alone: M rows split
//                                        evenly, each rank also touching 5 % of the next
//                                        rank's rows; 200 bcast + reduce of K columns, one SF
//                                        call per column against one with k doubles per row
//   mpirun -n 2 build/bin/bench_feti ... the subdomains dealt to two ranks
#include <fmt/format.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <string>

#include "../../tests/support/problems.hpp"
#include "../support/sliding_blocks.hpp"
#include "../support/two_block_feti.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/feti/dual_distribution.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/mesh/box.hpp"
#include "tc/physics/body/body_system.hpp"
#include "tc/run/simulation.hpp"

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
  size_t owned = 0;  // the multipliers this rank stores
  int coarse = 0;
};

Run feti_solve(const physics::BodySystem& sys, physics::Scheme scheme, feti::Preconditioner pc) {
  const bool dynamic = scheme == physics::Scheme::dynamic;
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
  r.owned = f.owned_multipliers().size();
  r.coarse = f.coarse_dimension();
  return r;
}

double direct_solve_seconds(const physics::BodySystem& sys) {
  linalg::CholeskySolver c(
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
    const auto p = cube(n, s * s * s, physics::Scheme::quasistatic);
    const physics::BodySystem sys(p, 0);
    const double direct = direct_solve_seconds(sys);
    for (const auto pc : {feti::Preconditioner::dirichlet, feti::Preconditioner::lumped,
                          feti::Preconditioner::none}) {
      const auto q = feti_solve(sys, physics::Scheme::quasistatic, pc);
      const auto d = feti_solve(sys, physics::Scheme::dynamic, pc);
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
  const auto p = cube(n, subdomains, physics::Scheme::quasistatic);
  const physics::BodySystem sys(p, 0);
  const double assembly = since(t0);
  const auto r = feti_solve(sys, physics::Scheme::quasistatic, feti::Preconditioner::dirichlet);
  if (core::PetscSession::rank() == 0)
    fmt::print(
        "| {}³ cells | {} dofs | {} subdomains | {} multipliers ({} on rank 0) | "
        "assembly+partition "
        "{:.1f} s | FETI set-up {:.1f} s | solve {:.2f} s | {} iterations | peak RSS {:.2f} GiB "
        "(rank 0) |\n",
        n, sys.n_u(), subdomains, r.multipliers, r.owned, assembly, r.setup, r.solve, r.iterations,
        peak_rss_gib());
}

void block(int n, int subdomains, int k) {
  const auto p = cube(n, subdomains, physics::Scheme::quasistatic);
  const physics::BodySystem sys(p, 0);
  feti::FetiOptions o;
  o.tolerance = 1e-8;
  const feti::Feti f(
      sys.subdomains(), sys.body().mesh.n_nodes(), 3, sys.u_dirichlet_dofs(), feti::Kernel::rigid,
      feti::Singular::yes, [&](int s) { return sys.subdomain_matrices(s).stiffness_u.copy(); }, o);
  core::Vector load(sys.n_u());
  sys.mechanical_load(0.0, load);
  const auto lv = load.to_std();
  const PetscInt nu = sys.n_u();
  std::vector<double> rhs(static_cast<size_t>(nu * k));
  for (int j = 0; j < k; ++j)  // k different loads of the size of the body's
    for (PetscInt i = 0; i < nu; ++i)
      rhs[static_cast<size_t>(j * nu + i)] = lv[static_cast<size_t>(i)] * std::cos(0.01 * j * i);
  core::Handle<::Mat, MatDestroy> b, x;
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, nu, k, rhs.data(), b.out()));
  TC_PETSC(MatCreateSeqDense(PETSC_COMM_SELF, nu, k, nullptr, x.out()));
  const auto t0 = Clock::now();
  f.solve_homogeneous_many(b.get(), x.get());
  const double t = since(t0);
  if (core::PetscSession::rank() == 0)
    fmt::print(
        "| {}³ cells | {} subdomains | {} multipliers | {} columns | block solve {:.2f} s | "
        "{} iterations |\n",
        n, subdomains, f.n_multipliers(), k, t, f.statistics().last_iterations);
}

void transfer(Eigen::Index m, Eigen::Index k) {
  const int rank = core::PetscSession::rank(), size = core::PetscSession::size();
  std::vector<int> row_rank(static_cast<size_t>(m));
  for (Eigen::Index r = 0; r < m; ++r)
    row_rank[static_cast<size_t>(r)] = static_cast<int>(r * size / m);
  std::vector<Eigen::Index> leaves;
  const Eigen::Index first = m * rank / size, last = m * (rank + 1) / size;
  const Eigen::Index halo = size > 1 ? (last - first) / 20 : 0;
  for (Eigen::Index r = first; r < last + halo; ++r) leaves.push_back(r % m);
  feti::DualDistribution d(PETSC_COMM_WORLD, row_rank, leaves);
  for (const auto t : {feti::DualDistribution::Transfer::per_column,
                       feti::DualDistribution::Transfer::row_major}) {
    d.set_transfer(t);
    Eigen::MatrixXd x = Eigen::MatrixXd::Random(d.n_owned(), k), l, y;
    const auto t0 = Clock::now();
    for (int i = 0; i < 200; ++i) {
      d.bcast(x, l);
      d.reduce(l, y);
    }
    const double s = since(t0);
    if (rank == 0)
      fmt::print("| {} rows | {} ranks | {} columns | {} | {:.3f} ms per bcast + reduce |\n", m,
                 size, k,
                 t == feti::DualDistribution::Transfer::per_column ? "per column" : "row-major",
                 s / 200 * 1e3);
  }
}

/// Two blocks of s·H cells per edge, each cut into s³ subdomains: the master [0,1]²×[−1,0]
/// clamped at its base, the slave [0,1]²×[0,1] (its base on the master's top) with its top
/// pressed down 1 mm/m in the first step, then dragged along y by 0.2 mm per step, 𝔉 = 0.3:
/// the whole interface in contact, sticking then sliding. Quasistatic: TFETI with the rigid
/// body kernels, the contact QP on top (explicit F while it has at most 1500 rows).
physics::Problem contact_blocks(int h, int s, int steps) {
  const int n = h * s;
  auto p =
      bench::two_steel_blocks(mesh::make_box(3, {0, 0, -1}, {1, 1, 0}, {n, n, n}),
                              mesh::make_box(3, {0, 0, 0}, {1, 1, 1}, {n, n, n}), steps, s * s * s);
  if (std::getenv("TC_BENCH_DYNAMIC")) p.time.scheme = physics::Scheme::dynamic;
  const double end = 0.1 * steps;
  bench::clamp_and_drag(p, 0.1, 1e-3, end, 2e-4 * (steps - 1));
  p.contacts = {test::contact_pair(1, "zmin", 0, "zmax", 0.3)};
  p.solver.qp_tolerance = 1e-8;
  p.solver.coupling_tolerance = 1e-6;
  p.solver.feti_tolerance = 1e-8;
  p.solver.feti_preconditioner = feti::Preconditioner::dirichlet;
  return p;
}

struct QpCounts : physics::Observer {
  long qp = 0, coupling = 0;
  void step(const physics::Simulation& sim) override {
    if (sim.step() == 0) return;
    qp += static_cast<long>(sim.history("qp_iterations"));
    coupling += static_cast<long>(sim.history("coupling_iterations"));
  }
};

void contact_blocks_bench(int h, int s_max, int steps, int s_min) {
  const bool root = core::PetscSession::rank() == 0;
  const int ranks = core::PetscSession::size();
  if (root)
    fmt::print(
        "H/h = {}, {} quasistatic steps, {} rank(s)\n\n"
        "| subdomains per body | cells per body | dofs | contact rows | dual operator | "
        "FETI solves (1 rhs + blocks) | FETI its per solve | FETI its per 1-rhs solve | "
        "coupling its | QP its | QP its per coupling it | set-up (s) | run (s) | FETI (s) | "
        "ms per subdomain·iteration (1-rhs) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        h, steps, ranks);
  for (int s = s_min; s <= s_max; ++s) {
    const auto p = contact_blocks(h, s, steps);
    auto t0 = Clock::now();
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    const double setup = since(t0);
    QpCounts counts;
    t0 = Clock::now();
    const auto status = sim.run(counts);
    const double run = since(t0);
    if (!status.completed && root) fmt::print("  stopped: {}\n", status.message);
    const auto f = sim.feti_statistics();
    const int subdomains = 2 * s * s * s;  // both bodies
    // A rank works on its own subdomains: time per subdomain·iteration counts those.
    const double per_sub_it = f.single_iterations > 0
                                  ? 1e3 * f.single_seconds * ranks /
                                        (static_cast<double>(subdomains) * f.single_iterations)
                                  : 0.0;
    if (root)
      fmt::print(
          "| {} | {}³ | {} | {} | {} | {} + {} | {:.1f} | {:.1f} | {} | {} | {:.1f} | {:.1f} | "
          "{:.1f} | {:.1f} | {:.3f} |\n",
          s * s * s, h * s, sim.n_dofs(), sim.dual_solver()->rows().n_rows(),
          physics::name(sim.dual_solver()->kind()), f.single_solves, f.solves - f.single_solves,
          static_cast<double>(f.iterations) / std::max(1L, f.solves),
          static_cast<double>(f.single_iterations) / std::max(1L, f.single_solves), counts.coupling,
          counts.qp, static_cast<double>(counts.qp) / std::max(1L, counts.coupling), setup, run,
          f.seconds, per_sub_it);
    std::fflush(stdout);
  }
}

double max_rel_diff(const core::Vector& a, const core::Vector& b) {
  auto d = a.clone();
  d.axpy(-1.0, b);
  return d.max_abs() / std::max(b.max_abs(), 1e-300);
}

/// Nested against combined on one solve with the Tresca bound 0.3 λ_n of the frictionless
/// nested solution (not timed). Both at 1e-8: FETI and the contact QP (nested), SMALBE's
/// gradient and equality (combined, ρ = 100 λ_max(F)). "FETI its": the PCG iterations of the
/// nested form's FETI solves (a block of k columns counts once, though it solves k
/// right-hand sides per subdomain); an application of the combined F solves one right-hand
/// side on every subdomain of both bodies.
void combined_bench(int h, int s_max, int s_min, bool lumped) {
  const bool root = core::PetscSession::rank() == 0;
  if (root)
    fmt::print(
        "H/h = {}, {} rank(s), combined {}preconditioned\n\n"
        "| subdomains per body | cells per body | dofs | contact rows | combined multipliers | "
        "coarse dim | nested: operator | QP its | FETI solves | FETI its | time (s) | combined: "
        "outer its | inner its | F applications | time (s) | max Δu/‖u‖∞ | max Δλ/‖λ‖∞ |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n",
        h, core::PetscSession::size(), lumped ? "lumped-" : "un");
  for (int s = s_min; s <= s_max; ++s) {
    bench::TwoBlockFeti p(h * s, s, PETSC_COMM_WORLD, 1e-8);
    // TC_BENCH_SKIP_NESTED=1: the combined form alone, the bound from its own frictionless
    // solution (for the sizes where the nested one would take hours).
    const bool skip = std::getenv("TC_BENCH_SKIP_NESTED") != nullptr;
    feti::ContactFetiOptions o;
    o.smalbe.rtol = o.smalbe.equality_rtol = 1e-8;
    o.lumped_preconditioner = lumped;
    qp::QpResult rn;
    qp::SmalbeResult rc;
    p.set_friction_bound(std::vector<double>(static_cast<size_t>(p.rows().n_nodes()), 0.0));
    const auto frictionless = skip ? p.combined(o, rc) : p.nested(1e-8, rn);
    {
      const auto l = frictionless.lambda.to_std();
      std::vector<double> bound(l.size() / 3);
      for (size_t k = 0; k < bound.size(); ++k) bound[k] = 0.3 * std::max(l[3 * k], 0.0);
      p.set_friction_bound(bound);
    }
    const auto before = p.slave_feti().statistics();
    auto before_m = p.master_feti().statistics();
    physics::DualContactSettings settings;
    const auto nested = skip ? bench::ContactSolution{} : p.nested(1e-8, rn, settings);
    auto fs = p.slave_feti().statistics(), fm = p.master_feti().statistics();
    const long solves = fs.solves - before.solves + fm.solves - before_m.solves;
    const long its = fs.iterations - before.iterations + fm.iterations - before_m.iterations;
    const char* kind = p.rows().n_rows() <= settings.explicit_limit ? "explicit" : "matrix-free";
    int applications = 0;
    const auto combined = p.combined(o, rc, &applications);
    const feti::ContactFeti shape(p.slave_feti(), p.master_feti(), p.rows().slave, p.rows().master,
                                  3);
    const double du = skip ? 0.0
                           : std::max(max_rel_diff(combined.u_slave, nested.u_slave),
                                      max_rel_diff(combined.u_master, nested.u_master));
    const double dl = skip ? 0.0 : max_rel_diff(combined.lambda, nested.lambda);
    if (!skip && !rn.converged() && root) fmt::print("  nested: {}\n", rn.message);
    if (!rc.converged() && root) fmt::print("  combined: {}\n", rc.message);
    if (root)
      fmt::print(
          "| {} | {}³ | {} | {} | {} | {} | {} | {} | {} | {} | {:.2f} | {} | {} | {} | {:.2f} | "
          "{:.1e} | {:.1e} |\n",
          s * s * s, h * s, p.n_dofs(), p.rows().n_rows(), shape.n_multipliers(),
          shape.coarse_dimension(), kind, rn.iterations, solves, its, nested.seconds,
          rc.outer_iterations, rc.inner_iterations, applications, combined.seconds, du, dl);
    std::fflush(stdout);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int pargc = 1;
  char** pargv = argv;
  core::PetscSession session(&pargc, &pargv);
  if (argc >= 4 && std::string(argv[1]) == "contact")
    contact_blocks_bench(std::stoi(argv[2]), std::stoi(argv[3]), argc >= 5 ? std::stoi(argv[4]) : 3,
                         argc >= 6 ? std::stoi(argv[5]) : 2);
  else if (argc >= 4 && std::string(argv[1]) == "combined")
    combined_bench(std::stoi(argv[2]), std::stoi(argv[3]), argc >= 5 ? std::stoi(argv[4]) : 2,
                   argc >= 6 && std::string(argv[5]) == "lumped");
  else if (argc >= 4 && std::string(argv[1]) == "transfer")
    transfer(std::stol(argv[2]), std::stol(argv[3]));
  else if (argc >= 5 && std::string(argv[1]) == "block")
    block(std::stoi(argv[2]), std::stoi(argv[3]), std::stoi(argv[4]));
  else if (argc >= 4 && std::string(argv[1]) == "size")
    size(std::stoi(argv[2]), std::stoi(argv[3]));
  else
    scalability();
  return 0;
}
