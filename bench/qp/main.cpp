// bench/qp: MPRGP (tc::qp::Mprgp) against PETSc TAO's bound-constrained solvers (TAOBQPIP,
// TAOGPCG, TAOBLMVM) and against plain CG on the same F without constraints: applications of
// F and wall time, side by side in one run, per instance. Prints a Markdown table.
//
// Instances: random sparse SPD QPs min ½xᵀFx − xᵀd, x ≥ 0, with a known solution
// (tests/support/qp_problems.hpp with κ ≤ 10, diagonally scaled to κ(F) ≤ kappa, see
// scaled_qp; n variables, a fraction `active` of the bounds active at the solution), and a
// contact-like dual F = B K⁻¹ Bᵀ of an elastic block whose bottom face rests on a curved obstacle
// (K factorised once by CHOLMOD/MUMPS; one application of F = one pair of triangular solves).
//
// Every solver applies F through the same counting MATSHELL (tests/support/tao_qp.hpp), with
// no preconditioner: F is only ever applied in the dual problem. MPRGP counts its own
// applications, including the Lanczos steps of its λ_max estimate (shown apart in brackets:
// in the time loop the estimate is made once and reused). BLMVM's gradient
// evaluations each cost one application; GPCG's and BQPIP's Hessian products and their
// gradient evaluations are all MatMults of the shell. All stop on a projected gradient
// ‖g^P‖ ≤ rtol‖d‖ (BQPIP on its own measure, see tao_qp.hpp); CG on ‖Fx − d‖ ≤ rtol‖d‖.
// A solver that does not converge within the budget (applications or seconds) is reported as
// such, never as a count.
//
//   build/bin/bench_qp [--sizes 1000,10000,100000|none] [--plain-sizes 10000|none]
//                      [--disc-sizes NODES,...|none] [--kappas 1e2,1e4,1e6]
//                      [--active 0.1,0.5,0.9] [--rtol 1e-6] [--contact 24,24,8|none]
//                      [--max-applications N] [--max-seconds S] [--variants] [--mprgp-only]
//                      [--lanczos STEPS] [--lanczos-tolerance T] [--alpha C] [--gamma Γ]
//                      [--full-gradient-expansion] [--projected-cg-expansion]
//                      [--expansion-step fixed|cauchy|bb] [--arc-step fixed|cauchy|bb]
//                      [--proportioning reduced|free] [--lambda-upfront]
//                      [PETSc options]
// (the options from --lanczos on change MPRGP's options from the qp layer's defaults, for
// experiments; --variants adds a second table with every strategy of strategy_variants() on
// every instance; --disc-sizes adds 3D contact nodes with friction discs, MPGP only;
// --mprgp-only skips TAO and CG)
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "../../tests/support/qp_problems.hpp"
#include "../../tests/support/tao_qp.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/fem/assembler.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/mesh/box.hpp"
#include "tc/qp/mpgp.hpp"

namespace {

using Clock = std::chrono::steady_clock;
using tc::core::Vector;

double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> out;
  if (s == "none") return out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::stod(item));
  return out;
}

/// MPRGP/MPGP strategies measured side by side with --variants (docs/choices.md).
struct Variant {
  std::string name;
  tc::qp::QpOptions options;
  /// Needs diag(F) (skipped where it is not at hand): the change of variables
  /// QpOptions::scaling = FeasibleSet::jacobi_scaling(diag F), or the same factors squared as
  /// a preconditioner in face (a per-node Jacobi that treats a disc's pair alike).
  bool jacobi_scaling = false;
  bool node_jacobi_in_face = false;
};

std::vector<Variant> strategy_variants() {
  using tc::qp::Expansion, tc::qp::ExpansionStep, tc::qp::ProportioningTest;
  std::vector<Variant> v;
  auto add = [&](std::string name, auto&& change) {
    tc::qp::QpOptions o;
    change(o);
    v.push_back({std::move(name), o});
  };
  add("ᾱ fixed, Γ = 1 (default)", [](auto&) {});
  add("λ_max deferred (from CG)",
      [](auto& o) { o.eigenvalue_estimate = tc::qp::EigenvalueEstimate::deferred; });
  add("BB length", [](auto& o) {
    o.expansion_step = ExpansionStep::barzilai_borwein;
    o.arc_step = ExpansionStep::barzilai_borwein;
  });
  add("Cauchy length", [](auto& o) {
    o.expansion_step = ExpansionStep::cauchy;
    o.arc_step = ExpansionStep::cauchy;
  });
  add("PERMON test ‖β‖ ≤ Γ‖φ‖", [](auto& o) { o.proportioning_test = ProportioningTest::free; });
  add("Γ = 4", [](auto& o) { o.gamma = 4; });
  add("proj. CG, Γ = 1", [](auto& o) { o.expansion = Expansion::projected_cg; });
  add("proj. CG, Γ = 4", [](auto& o) {
    o.expansion = Expansion::projected_cg;
    o.gamma = 4;
  });
  add("slide on circles", [](auto& o) { o.circle_face = tc::qp::CircleFace::slide; });
  add("slide on circles, BB length", [](auto& o) {
    o.circle_face = tc::qp::CircleFace::slide;
    o.expansion_step = ExpansionStep::barzilai_borwein;
    o.arc_step = ExpansionStep::barzilai_borwein;
  });
  add("per-node Jacobi in face", [](auto&) {});
  v.back().node_jacobi_in_face = true;
  add("Jacobi change of variables", [](auto&) {});
  v.back().jacobi_scaling = true;
  add("Jacobi variables, λ_max deferred",
      [](auto& o) { o.eigenvalue_estimate = tc::qp::EigenvalueEstimate::deferred; });
  v.back().jacobi_scaling = true;
  add("slide + Jacobi in face", [](auto& o) { o.circle_face = tc::qp::CircleFace::slide; });
  v.back().node_jacobi_in_face = true;
  add("slide + Jacobi variables", [](auto& o) { o.circle_face = tc::qp::CircleFace::slide; });
  v.back().jacobi_scaling = true;
  return v;
}

struct Settings {
  std::vector<double> sizes{1e3, 1e4, 1e5}, kappas{1e2, 1e4, 1e6}, active{0.1, 0.5, 0.9};
  std::vector<double> plain_sizes{1e4};    // random_qp unscaled, 50 % active
  std::vector<double> disc_sizes{};        // scaled_disc_qp nodes (MPGP only), 50 % in contact
  std::vector<double> contact{24, 24, 8};  // cells of the block; empty: no contact instance
  double rtol = 1e-6;
  /// --lanczos, --alpha, --gamma, --full-gradient-expansion, --lambda-upfront; λ_max deferred
  /// to the first expansion (from the CG coefficients) unless --lambda-upfront.
  tc::qp::QpOptions mprgp = [] {
    tc::qp::QpOptions o;
    o.eigenvalue_estimate = tc::qp::EigenvalueEstimate::deferred;
    return o;
  }();
  long max_applications = 200000;
  double max_seconds = 60;
  bool mprgp_only = false;        // experiments: skip TAO and CG
  std::vector<Variant> variants;  // --variants: strategy_variants(), a second table
};

/// One solver's outcome on one instance, as printed.
struct Cell {
  bool converged = false;
  bool capped = false;  // stopped by the budget
  long applications = 0;
  double seconds = 0;
  double difference = 0;  // ‖x − x_MPRGP‖∞ / ‖x_MPRGP‖∞ (constrained solvers)

  long estimate = 0;     // of which the λ_max estimate (MPRGP)
  bool skipped = false;  // not run (TAO and CG on the disc instances)

  [[nodiscard]] std::string text() const {
    if (skipped) return "—";
    if (converged && estimate > 0)
      return fmt::format("{} [{}] ({:.2f} s)", applications, applications - estimate, seconds);
    if (converged) return fmt::format("{} ({:.2f} s)", applications, seconds);
    return fmt::format("{} {} ({:.1f} s)", capped ? "cap >" : "fail at", applications, seconds);
  }
};

struct Row {
  std::string name;
  long n = 0;
  std::string kappa, active;
  Cell mprgp, mprgp_pc, bqpip, gpcg, blmvm, cg;  // mprgp_pc: preconditioned in face
  Cell mprgp_jv;     // QpOptions::scaling = Jacobi factors (the physics path's configuration)
  int n_active = 0;  // active bounds at MPRGP's solution
  std::vector<Cell> variants;  // Settings::variants, in order
};

double relative_difference(const Vector& x, const Vector& ref) {
  Vector e = x.clone();
  e.axpy(-1.0, ref);
  return e.max_abs() / std::max(ref.max_abs(), 1e-300);
}

/// Runs all solvers on min ½xᵀFx − xᵀd, x ≥ 0; `preconditioner` (may be null) for the
/// second MPRGP run, applied to the free gradient in the face.
/// A cell of one MPGP solve (its applications with the λ_max estimate's share).
Cell mpgp_cell(const tc::qp::QpResult& r, double seconds) {
  Cell c;
  c.seconds = seconds;
  c.applications = r.operator_applications;
  c.estimate = r.estimate_applications;
  c.converged = r.converged();
  c.capped = r.status == tc::qp::QpStatus::max_iterations;
  return c;
}

void run_instance(Row& row, const tc::qp::LinearOperator& f, const Vector& d,
                  const tc::qp::FeasibleSet& set, const Settings& s,
                  const tc::qp::LinearOperator* preconditioner, const Vector* diagonal) {
  const double eps = s.rtol * d.norm();
  // MPRGP, defaults of the qp layer (ᾱ = 1.9/λ̂_max, Γ = 1, free-gradient expansion).
  tc::qp::QpOptions opt = s.mprgp;
  opt.rtol = s.rtol;
  opt.max_iterations = static_cast<int>(std::min<long>(s.max_applications, 1000000));
  Vector x_m = d.duplicate();
  auto t0 = Clock::now();
  const auto rm = tc::qp::Mpgp(f, set, opt).solve(d, x_m);  // = Mprgp without discs
  // The share of the λ_max estimate, as counted by the solver (0 when ᾱ was never needed).
  row.mprgp = mpgp_cell(rm, since(t0));
  row.n_active = static_cast<int>(set.count_active(x_m));
  fmt::print(stderr,
             "  MPRGP {} ({} cg, {} expansion ({} long, {} fall-backs), {} proportioning, {} "
             "halvings, {} for λ_max{}, {} re-estimates) {:.2f} s\n",
             rm.operator_applications, rm.cg_steps, rm.expansion_steps, rm.long_expansions,
             rm.fallbacks, rm.proportioning_steps, rm.step_halvings, rm.estimate_applications,
             rm.face_eigenvalue ? " of a face" : "", rm.reestimates, row.mprgp.seconds);
  // Per-node Jacobi factors (FeasibleSet::jacobi_scaling) for the variants that need them.
  std::optional<Vector> scaling, squared;
  std::optional<tc::qp::FunctionOperator> node_jacobi;
  if (diagonal) {
    scaling = set.jacobi_scaling(*diagonal);
    squared = scaling->clone();
    TC_PETSC(VecPointwiseMult(squared->get(), squared->get(), squared->get()));
    node_jacobi.emplace(
        [&squared](const Vector& x, Vector& y) {
          TC_PETSC(VecPointwiseMult(y.get(), squared->get(), x.get()));
        },
        d);
  }
  for (const auto& v : s.variants) {
    tc::qp::QpOptions vo = v.options;
    vo.rtol = opt.rtol;
    vo.max_iterations = opt.max_iterations;
    if ((v.jacobi_scaling || v.node_jacobi_in_face) && !diagonal) {
      Cell c;
      c.skipped = true;
      row.variants.push_back(c);
      continue;
    }
    if (v.jacobi_scaling) vo.scaling = &*scaling;
    if (v.node_jacobi_in_face) vo.preconditioner = &*node_jacobi;
    Vector x = d.duplicate();
    t0 = Clock::now();
    const auto rv = tc::qp::Mpgp(f, set, vo).solve(d, x);
    Cell c;
    c.seconds = since(t0);
    c.applications = rv.operator_applications;
    c.converged = rv.converged();
    c.capped = rv.status == tc::qp::QpStatus::max_iterations;
    c.difference = relative_difference(x, x_m);
    row.variants.push_back(c);
    fmt::print(stderr,
               "  variant {}: {} ({} cg, {} expansion, {} proportioning, {} arc Cauchy, {} slides, "
               "{} long, {} fall-backs) {:.2f} s\n",
               v.name, c.applications, rv.cg_steps, rv.expansion_steps, rv.proportioning_steps,
               rv.cauchy_steps, rv.slides, rv.long_expansions, rv.fallbacks, c.seconds);
  }
  if (scaling) {
    tc::qp::QpOptions jv = opt;
    jv.scaling = &*scaling;
    Vector x = d.duplicate();
    t0 = Clock::now();
    const auto rj = tc::qp::Mpgp(f, set, jv).solve(d, x);
    row.mprgp_jv = mpgp_cell(rj, since(t0));
    row.mprgp_jv.difference = relative_difference(x, x_m);
    fmt::print(stderr,
               "  MPRGP, Jacobi variables {} ({} cg, {} expansion, {} proportioning, {} for "
               "λ_max{}, {} re-estimates) {:.2f} s, differs by {:.1e}\n",
               rj.operator_applications, rj.cg_steps, rj.expansion_steps, rj.proportioning_steps,
               rj.estimate_applications, rj.face_eigenvalue ? " of a face" : "", rj.reestimates,
               row.mprgp_jv.seconds, row.mprgp_jv.difference);
  } else {
    row.mprgp_jv.skipped = true;
  }
  if (preconditioner) {
    tc::qp::QpOptions pc = opt;
    pc.preconditioner = preconditioner;
    Vector x = d.duplicate();
    t0 = Clock::now();
    const auto rp = tc::qp::Mpgp(f, set, pc).solve(d, x);
    row.mprgp_pc = mpgp_cell(rp, since(t0));
    row.mprgp_pc.difference = relative_difference(x, x_m);
    fmt::print(
        stderr,
        "  MPRGP+pc {} ({} cg, {} expansion, {} proportioning) {:.2f} s, differs by {:.1e}\n",
        row.mprgp_pc.applications, rp.cg_steps, rp.expansion_steps, rp.proportioning_steps,
        row.mprgp_pc.seconds, row.mprgp_pc.difference);
  }

  // TAO's bound-constrained solvers cannot take discs; CG is left out there as well (and
  // everywhere with --mprgp-only).
  if (set.has_discs() || s.mprgp_only)
    for (Cell* c : {&row.bqpip, &row.gpcg, &row.blmvm, &row.cg}) c->skipped = true;
  if (s.mprgp_only || set.has_discs()) return;
  Vector lower = d.duplicate(), upper = d.duplicate();
  tc::test::interval_bounds(set, lower, upper);
  tc::test::CountingShell shell(f);
  const tc::test::Budget budget{s.max_applications, s.max_seconds};
  auto run = [&](const char* type, Cell& cell) {
    Vector x = d.duplicate();  // 0 is feasible
    Vector lo = lower.clone(), up = upper.clone();
    const bool bqpip = std::string(type) == TAOBQPIP;
    // BQPIP caps infinite bounds at 1e20 and then does not converge (tao_qp.hpp); it gets a
    // finite upper bound ten times above the largest component of the solution instead.
    if (bqpip) tc::test::cap_infinite_bounds(lo, up, 10 * std::max(x_m.max_abs(), 1.0));
    const auto r = tc::test::run_tao(type, shell.get(), &shell, d, lo, up, x,
                                     bqpip ? tc::test::bqpip_gatol(eps, d.norm()) : eps,
                                     PETSC_MAX_INT, budget);
    cell.converged = r.converged;
    cell.capped = r.budget_hit;
    cell.applications = r.applications;
    cell.seconds = r.seconds;
    cell.difference = relative_difference(x, x_m);
    fmt::print(stderr, "  {} {} reason {} iterations {} {:.2f} s, differs from MPRGP by {:.1e}\n",
               type, r.applications, r.reason, r.iterations, r.seconds, cell.difference);
  };
  run(TAOBQPIP, row.bqpip);
  run(TAOGPCG, row.gpcg);
  run(TAOBLMVM, row.blmvm);

  Vector x = d.duplicate();
  // The budget in applications is CG's iteration limit; its time is not capped (CG is the
  // cheapest of all here).
  const auto rc =
      tc::test::run_cg(shell, d, x, s.rtol,
                       static_cast<PetscInt>(std::min<long>(s.max_applications, PETSC_MAX_INT)));
  row.cg.converged = rc.converged;
  row.cg.capped = !rc.converged;
  row.cg.applications = rc.applications;
  row.cg.seconds = rc.seconds;
  fmt::print(stderr, "  CG {} {:.2f} s\n", rc.applications, rc.seconds);
}

/// The dual of an elastic block on an obstacle: K_u of a box [0,1]²×[0,h] (E = 1, ν = 0.3),
/// top face z = h clamped, own weight pulling down; the bottom face z = 0 may not go below an
/// obstacle z = −g(x, y). Constraint per bottom node i: −a_i u_z,i ≤ a_i g_i with the nodal
/// area a_i (B = rows of −a_i on u_z). Dual: λ ≥ 0, F = B K⁻¹ Bᵀ, d = B K⁻¹ f − c.
/// The obstacle is the free sag scaled by 0.4 at the centre rising to 1.6 at the corners, so
/// the central nodes touch and the outer ones do not.
struct ContactDual {
  tc::core::SparseMatrix k, b;
  tc::linalg::CholeskySolver chol;
  Vector d;
  double scale = 1;  // F and d divided by ≈ λ_max(F), so that TAO's constants see O(1) data
  int n_dofs = 0, n_contact = 0;
  Vector inverse_area2;  // 1/a_i²
  mutable Vector w, v, z;

  void apply(const Vector& x, Vector& y) const {
    b.mult_transpose(x, w);
    chol.solve(w, v);
    b.mult(v, y);
    y.scale(1 / scale);
  }
  /// The lumped preconditioner of FETI, y = A⁻¹ S K Sᵀ A⁻¹ x with B = −A S (A the nodal
  /// areas, S the selection of u_z): F⁻¹ = (A S K⁻¹ Sᵀ A)⁻¹ with K⁻¹ replaced by K on the face.
  /// One sparse product with K, no solve; constant factors do not matter to MPRGP.
  void lumped(const Vector& x, Vector& y) const {
    TC_PETSC(VecPointwiseMult(y.get(), inverse_area2.get(), x.get()));
    b.mult_transpose(y, w);
    k.mult(w, v);
    b.mult(v, y);
    TC_PETSC(VecPointwiseMult(y.get(), inverse_area2.get(), y.get()));
  }
};

ContactDual make_contact(const std::vector<double>& cells) {
  const int nx = static_cast<int>(cells[0]), ny = static_cast<int>(cells[1]),
            nz = static_cast<int>(cells[2]);
  const double h = static_cast<double>(nz) / nx;  // cubic cells
  const auto mesh = tc::mesh::make_box(3, {0, 0, 0}, {1, 1, h}, {nx, ny, nz});
  tc::fem::Material mat;
  mat.young_modulus = 1, mat.poisson_ratio = 0.3;
  ContactDual c;
  c.n_dofs = 3 * mesh.n_nodes();
  const auto graph = tc::fem::node_graph(mesh);
  c.k = tc::fem::assemble(mesh, graph, 3, 3, [&](int, auto type, const auto& x) {
    return tc::fem::stiffness_u(type, x, mat.lame_lambda(), mat.lame_mu());
  });
  std::vector<PetscInt> clamped;
  for (const int node : mesh.boundary_nodes("zmax"))
    for (int k = 0; k < 3; ++k) clamped.push_back(3 * node + k);
  c.k.zero_rows_columns(clamped, 1.0);
  c.chol = tc::linalg::CholeskySolver(c.k);

  // Own weight: f_z = −ρg ∫N_a with ρg = 1 (zero on the clamped dofs).
  Vector f(c.n_dofs);
  {
    const auto vol = tc::fem::volume_integrals(mesh);
    auto fv = f.view();
    for (int a = 0; a < mesh.n_nodes(); ++a) fv[3 * a + 2] = -vol[a];
    for (const PetscInt dof : clamped) fv[dof] = 0;
  }
  Vector u_free(c.n_dofs);
  c.chol.solve(f, u_free);

  const auto bottom = mesh.boundary_nodes("zmin");
  const auto area = tc::fem::boundary_integrals(mesh, "zmin");
  c.n_contact = static_cast<int>(bottom.size());
  const std::vector<PetscInt> one(c.n_contact, 1);
  c.b = tc::core::SparseMatrix(c.n_contact, c.n_dofs, one);
  std::vector<double> gap(c.n_contact);
  {
    const auto uf = u_free.to_std();
    for (int i = 0; i < c.n_contact; ++i) {
      const int node = bottom[i];
      const PetscInt row = i, col = 3 * node + 2;
      const double value = -area[node];
      c.b.add_values({&row, 1}, {&col, 1}, &value);
      const auto& p = mesh.point(node);
      const double r2 = ((p[0] - 0.5) * (p[0] - 0.5) + (p[1] - 0.5) * (p[1] - 0.5)) / 0.5;
      gap[i] = -uf[col] * (0.4 + 1.2 * r2);  // the free sag −u_z > 0, scaled
    }
  }
  c.b.assemble();
  c.inverse_area2 = Vector(c.n_contact);
  {
    auto a = c.inverse_area2.view();
    for (int i = 0; i < c.n_contact; ++i) a[i] = 1 / (area[bottom[i]] * area[bottom[i]]);
  }
  c.w = Vector(c.n_dofs);
  c.v = Vector(c.n_dofs);
  // d = B u_free − c, c_i = a_i g_i.
  c.d = Vector(c.n_contact);
  c.b.mult(u_free, c.d);
  {
    auto dv = c.d.view();
    for (int i = 0; i < c.n_contact; ++i) dv[i] -= area[bottom[i]] * gap[i];
  }
  // Scale by λ_max so that F has norm ≈ 1 (solution unchanged: F/s and d/s).
  const tc::qp::FunctionOperator unscaled([&c](const Vector& x, Vector& y) { c.apply(x, y); }, c.d);
  c.scale = tc::qp::estimate_max_eigenvalue(unscaled, 30).bound;
  c.d.scale(1 / c.scale);
  return c;
}

/// random_qp with κ(F₀) ≤ 10, then F = D F₀ D with D = diag(10^(e_i)), e_i uniform in
/// [0, ½ log₁₀(κ/10)]: κ(F) ≤ κ(F₀)·(max D/min D)² = κ, and the spectrum is spread over the
/// whole range (random_qp alone has one small eigenvalue, the shift, which CG removes in a
/// step or two). With y = D⁻¹x the bounds at 0 stay at 0 and the solution is D⁻¹x*.
tc::test::QpProblem scaled_qp(long n, double kappa, double active, std::uint64_t seed) {
  auto p =
      tc::test::random_qp(PETSC_COMM_SELF, n, tc::test::QpKind::lower, 10.0, active, 0.0, seed);
  Vector scale = p.d.duplicate();
  {
    std::mt19937_64 rng(seed ^ 0x9e3779b97f4a7c15ULL);
    std::uniform_real_distribution<double> u(0.0, 0.5 * std::log10(kappa / 10.0));
    auto v = scale.view();
    for (PetscInt i = 0; i < scale.local_size(); ++i) v[i] = std::pow(10.0, u(rng));
  }
  TC_PETSC(MatDiagonalScale(p.f.get(), scale.get(), scale.get()));
  TC_PETSC(VecPointwiseDivide(p.x_star.get(), p.x_star.get(), scale.get()));
  TC_PETSC(VecPointwiseMult(p.g_star.get(), p.g_star.get(), scale.get()));
  TC_PETSC(MatMult(p.f.get(), p.x_star.get(), p.d.get()));
  p.d.axpy(-1.0, p.g_star);
  p.kappa_bound *= std::pow(10.0, std::log10(kappa / 10.0));
  return p;
}

std::string kappa_text(double k) {
  return fmt::format("1e{}", std::lround(std::log10(k)));
}

}  // namespace

int main(int argc, char** argv) {
  Settings s;
  std::vector<char*> petsc_args{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&] { return std::string(i + 1 < argc ? argv[++i] : ""); };
    if (a == "--sizes")
      s.sizes = parse_list(value());
    else if (a == "--plain-sizes") {
      const auto v = value();
      s.plain_sizes = v == "none" ? std::vector<double>{} : parse_list(v);
    } else if (a == "--disc-sizes") {
      const auto v = value();
      s.disc_sizes = v == "none" ? std::vector<double>{} : parse_list(v);
    } else if (a == "--kappas")
      s.kappas = parse_list(value());
    else if (a == "--active")
      s.active = parse_list(value());
    else if (a == "--rtol")
      s.rtol = std::stod(value());
    else if (a == "--contact") {
      const auto v = value();
      s.contact = v == "none" ? std::vector<double>{} : parse_list(v);
    } else if (a == "--max-applications")
      s.max_applications = std::stol(value());
    else if (a == "--lanczos")
      s.mprgp.lanczos_steps = std::stoi(value());
    else if (a == "--lanczos-tolerance")
      s.mprgp.lanczos_tolerance = std::stod(value());
    else if (a == "--alpha")
      s.mprgp.alpha_factor = std::stod(value());
    else if (a == "--gamma")
      s.mprgp.gamma = std::stod(value());
    else if (a == "--full-gradient-expansion")
      s.mprgp.expansion = tc::qp::Expansion::full_gradient;
    else if (a == "--projected-cg-expansion")
      s.mprgp.expansion = tc::qp::Expansion::projected_cg;
    else if (a == "--expansion-step") {
      const auto v = value();
      s.mprgp.expansion_step = v == "fixed"    ? tc::qp::ExpansionStep::fixed
                               : v == "cauchy" ? tc::qp::ExpansionStep::cauchy
                                               : tc::qp::ExpansionStep::barzilai_borwein;
    } else if (a == "--arc-step") {
      const auto v = value();
      s.mprgp.arc_step = v == "fixed"    ? tc::qp::ExpansionStep::fixed
                         : v == "cauchy" ? tc::qp::ExpansionStep::cauchy
                                         : tc::qp::ExpansionStep::barzilai_borwein;
    } else if (a == "--proportioning")
      s.mprgp.proportioning_test =
          value() == "free" ? tc::qp::ProportioningTest::free : tc::qp::ProportioningTest::reduced;
    else if (a == "--lambda-upfront")
      s.mprgp.eigenvalue_estimate = tc::qp::EigenvalueEstimate::upfront;
    else if (a == "--variants")
      s.variants = strategy_variants();
    else if (a == "--mprgp-only")
      s.mprgp_only = true;
    else if (a == "--max-seconds")
      s.max_seconds = std::stod(value());
    else
      petsc_args.push_back(argv[i]);
  }
  int pargc = static_cast<int>(petsc_args.size());
  petsc_args.push_back(nullptr);  // argv[argc] = NULL, as MPI_Init expects
  char** pargv = petsc_args.data();
  tc::core::PetscSession session(&pargc, &pargv);

  std::vector<Row> rows;
  // The grid of scaled instances, then random_qp as built (κ from the shift alone, "plain")
  // at 50 % active. The seed depends on (n, κ, active) only.
  struct Instance {
    double n, kappa, active;
    bool scaled;
    bool discs = false;
  };
  std::vector<Instance> instances;
  for (const double n : s.sizes)
    for (const double kappa : s.kappas)
      for (const double active : s.active) instances.push_back({n, kappa, active, true});
  for (const double n : s.plain_sizes)
    for (const double kappa : s.kappas) instances.push_back({n, kappa, 0.5, false});
  for (const double n : s.disc_sizes)
    for (const double kappa : s.kappas) instances.push_back({n, kappa, 0.5, true, true});
  for (const auto& in : instances) {
    Row row;
    row.n = static_cast<long>(in.n);
    row.name = in.discs    ? "random, 3D contact nodes (discs)"
               : in.scaled ? "random, scaled"
                           : "random, plain";
    row.kappa = kappa_text(in.kappa);
    row.active = fmt::format("{:.0f} %", 100 * in.active);
    fmt::print(stderr, "{}: n = {}, κ ≤ {}, active {}\n", row.name, row.n, row.kappa, row.active);
    const auto seed = static_cast<std::uint64_t>(in.n + 7 * std::log10(in.kappa) + 100 * in.active);
    auto p = in.discs    ? tc::test::scaled_disc_qp(row.n, in.kappa, in.active, seed)
             : in.scaled ? scaled_qp(row.n, in.kappa, in.active, seed)
                         : tc::test::random_qp(PETSC_COMM_SELF, row.n, tc::test::QpKind::lower,
                                               in.kappa, in.active, 0.0, seed);
    if (in.discs) row.n *= 4;  // variables
    const tc::qp::MatrixOperator f(p.f.get());
    // Jacobi: y = diag(F)⁻¹x (F's diagonal is at hand for these explicit instances).
    Vector inverse_diagonal = p.d.duplicate();
    TC_PETSC(MatGetDiagonal(p.f.get(), inverse_diagonal.get()));
    TC_PETSC(VecReciprocal(inverse_diagonal.get()));
    const tc::qp::FunctionOperator jacobi(
        [&](const Vector& x, Vector& y) {
          TC_PETSC(VecPointwiseMult(y.get(), inverse_diagonal.get(), x.get()));
        },
        p.d);
    Vector diagonal = p.d.duplicate();
    TC_PETSC(MatGetDiagonal(p.f.get(), diagonal.get()));
    run_instance(row, f, p.d, p.set, s, &jacobi, &diagonal);
    rows.push_back(row);
  }

  if (s.contact.size() == 3) {
    const auto t0 = Clock::now();
    auto c = make_contact(s.contact);
    Row row;
    row.name =
        fmt::format("contact {:.0f}×{:.0f}×{:.0f}", s.contact[0], s.contact[1], s.contact[2]);
    row.n = c.n_contact;
    row.kappa = "—";
    row.active = "—";
    fmt::print(stderr, "{}: {} dofs, {} multipliers, set-up {:.1f} s\n", row.name, c.n_dofs,
               c.n_contact, since(t0));
    const tc::qp::FunctionOperator f([&c](const Vector& x, Vector& y) { c.apply(x, y); }, c.d);
    tc::qp::FeasibleSet set(c.d);
    for (PetscInt i = 0; i < c.n_contact; ++i) set.set_interval(i, {0.0, tc::qp::infinity});
    const tc::qp::FunctionOperator lumped([&c](const Vector& x, Vector& y) { c.lumped(x, y); },
                                          c.d);
    // diag(F) for the Jacobi variables: one application per unit vector, outside the
    // counts (physics::DualContactSolver forms F explicitly below 1500 rows, so it has it).
    std::optional<Vector> diagonal;
    {
      diagonal = c.d.duplicate();
      Vector unit = c.d.duplicate(), column = c.d.duplicate();
      for (PetscInt i = 0; i < c.n_contact; ++i) {
        unit.zero();
        unit.view()[i] = 1;
        c.apply(unit, column);
        diagonal->view()[i] = column.read()[i];
      }
    }
    run_instance(row, f, c.d, set, s, &lumped, diagonal ? &*diagonal : nullptr);
    row.active = fmt::format("{:.0f} %", 100.0 * row.n_active / row.n);
    rows.push_back(row);
  }

  fmt::print(
      "rtol = {:g} (‖g^P‖ ≤ rtol‖d‖; CG: ‖Fx − d‖ ≤ rtol‖d‖); budget per solve {} "
      "applications or {:g} s\n",
      s.rtol, s.max_applications, s.max_seconds);
  fmt::print(
      "Cells: applications of F (wall time); MPRGP: total [without the λ_max estimate]; "
      "cap > N: stopped by the budget unconverged; fail at N: stopped unconverged.\n\n");
  fmt::print(
      "| instance | n | κ ≤ | active | MPRGP | BQPIP | GPCG | BLMVM | CG (no bounds) | "
      "MPRGP/CG | MPRGP < every TAO | MPRGP + precond. in face | that < every TAO | "
      "MPRGP, Jacobi variables | that < every TAO | max rel. diff. to MPRGP |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const auto& r : rows) {
    double diff = r.mprgp_pc.converged ? r.mprgp_pc.difference : 0;
    if (r.mprgp_jv.converged) diff = std::max(diff, r.mprgp_jv.difference);
    auto fewer_than_tao = [&](const Cell& m) {
      if (r.bqpip.skipped) return std::string("—");
      bool fewer = m.converged;
      for (const Cell* t : {&r.bqpip, &r.gpcg, &r.blmvm})
        // A capped solver needed more than its count; one that stopped unconverged (line
        // search failure) did not reach the solution at any count.
        if (t->converged || t->capped) fewer = fewer && m.applications < t->applications;
      return fewer ? std::string("yes") : std::string("**no**");
    };
    for (const Cell* t : {&r.bqpip, &r.gpcg, &r.blmvm})
      if (t->converged) diff = std::max(diff, t->difference);
    fmt::print(
        "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.1e} |\n",
        r.name, r.n, r.kappa, r.active, r.mprgp.text(), r.bqpip.text(), r.gpcg.text(),
        r.blmvm.text(), r.cg.text(),
        r.cg.converged
            ? fmt::format("{:.2f}", static_cast<double>(r.mprgp.applications) / r.cg.applications)
            : "—",
        fewer_than_tao(r.mprgp), r.mprgp_pc.text(), fewer_than_tao(r.mprgp_pc), r.mprgp_jv.text(),
        fewer_than_tao(r.mprgp_jv), diff);
  }
  if (!s.variants.empty()) {
    fmt::print(
        "\nMPRGP/MPGP strategies (QpOptions), applications of F including the λ_max estimate; "
        "bold: fewer than the default.\n\n| instance | n | κ ≤ | active |");
    for (const auto& v : s.variants) fmt::print(" {} |", v.name);
    fmt::print(" best TAO |\n|---|---|---|---|");
    for (size_t k = 0; k <= s.variants.size(); ++k) fmt::print("---|");
    fmt::print("\n");
    for (const auto& r : rows) {
      fmt::print("| {} | {} | {} | {} |", r.name, r.n, r.kappa, r.active);
      for (const auto& c : r.variants) {
        const bool better = c.converged && c.applications < r.variants.front().applications;
        const auto text = c.converged ? std::to_string(c.applications) : c.text();
        fmt::print(" {} |", better ? "**" + text + "**" : text);
      }
      long best = 0;
      for (const Cell* t : {&r.bqpip, &r.gpcg, &r.blmvm})
        if (t->converged && (best == 0 || t->applications < best)) best = t->applications;
      fmt::print(" {} |\n", best > 0 ? std::to_string(best) : "—");
    }
  }
  return 0;
}
