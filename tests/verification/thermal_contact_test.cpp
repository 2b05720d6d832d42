// Thermal contact (2.13, §4.4) end to end through Simulation with the mortar pair on
// non-matching meshes (verification.md, "Thermal contact"), each figure against a closed form:
//  - Steady conduction through two blocks pressed by a known force (4C's
//    tsi_contact3D_conduction): h = β_C p_n, q = Δθ/(L₁/κ₁ + 1/h + L₂/κ₂), [θ] = −q/h.
//    Also: the lagged conductance of (6.2) diverges there and converges for a weak one.
//  - Frictional heating: two insulated blocks sliding at v under N: heat_generated = 𝔉 N v t,
//    heat_to_slave = δ_C heat_generated, Δthermal_energy = heat_generated, and the slave's
//    energy = heat_to_slave − heat_conducted (conduction on and off).
//  - Switches: heat_conduction = false → nothing crosses; frictional_heating = false → nothing
//    generated.
//  - Coupling: a slave heated between the master and a fixed wall: the pressure of the
//    laterally constrained blocks p = (δ + h_s β ΔT/M_s)/(h_s/M_s + h_m/M_m).
//  - Two half-spaces under constant frictional power: the surface temperatures' closed forms.
//  - InterfaceHeatSolver against the dense coupled solve (Dirichlet node on the interface), by
//    its LU and by refinement with an earlier LU.
//  - Aitken relaxation of the Coulomb fixed point: same answer, no more iterations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>

#include "support/body_energy.hpp"
#include "support/grid_laplacian.hpp"
#include "support/problems.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/physics/interface_heat/interface_heat_solver.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kTheta0 = 293.15;
constexpr double kAnyTheta = kTheta0;  // the conductances and 𝔉 here are constants

/// Σ ∫ ρc_p(θ − θ₀) of one body (history's thermal_energy per body).
/// A dense n×m matrix as a PETSc matrix (all entries stored).
core::SparseMatrix sparse(const Eigen::MatrixXd& d) {
  const std::vector<PetscInt> nnz(static_cast<size_t>(d.rows()), static_cast<PetscInt>(d.cols()));
  core::SparseMatrix m(d.rows(), d.cols(), nnz);
  std::vector<PetscInt> rows(d.rows()), cols(d.cols());
  for (PetscInt i = 0; i < d.rows(); ++i) rows[i] = i;
  for (PetscInt j = 0; j < d.cols(); ++j) cols[j] = j;
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> r = d;
  m.add_values(rows, cols, r.data());
  m.assemble();
  return m;
}

/// Two 1D bodies (6 and 5 nodes, A = M/τ + K of linear elements), interface nodes {3, 4, 5}
/// and {0, 1, 2}, Dirichlet data at slave node 0 and at master node 1, which is on the
/// interface; L_Γ symmetric positive semidefinite over the interface, set per case.
struct TwoChains {
  static constexpr int ns = 6, nm = 5;
  static Eigen::MatrixXd chain(int n, double c, double k) {
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int e = 0; e + 1 < n; ++e) {
      a(e, e) += c / 3 + k;
      a(e + 1, e + 1) += c / 3 + k;
      a(e, e + 1) += c / 6 - k;
      a(e + 1, e) += c / 6 - k;
    }
    return a;
  }
  const Eigen::MatrixXd as = chain(ns, 2.0, 5.0), am = chain(nm, 1.0, 3.0);
  const std::vector<int> gs = {3, 4, 5}, gm = {0, 1, 2};
  const physics::ConstrainedSolver solver_s{sparse(as), {0}, ""}, solver_m{sparse(am), {1}, ""};
  const Eigen::VectorXd b = Eigen::VectorXd::Random(ns + nm);
  static constexpr double theta_s0 = 300.0, theta_m1 = 310.0;

  /// L over both bodies' nodes from lg over [gs, gm] (6 × 6).
  [[nodiscard]] Eigen::MatrixXd full_l(const Eigen::MatrixXd& lg) const {
    Eigen::MatrixXd l = Eigen::MatrixXd::Zero(ns + nm, ns + nm);
    const int where[6] = {3, 4, 5, ns + 0, ns + 1, ns + 2};
    for (int a = 0; a < 6; ++a)
      for (int c = 0; c < 6; ++c) l(where[a], where[c]) = lg(a, c);
    return l;
  }
  [[nodiscard]] static contact::ThermalContact blocks(const Eigen::MatrixXd& l) {
    return {sparse(l.topLeftCorner(ns, ns)), sparse(l.topRightCorner(ns, nm)),
            sparse(l.bottomLeftCorner(nm, ns)), sparse(l.bottomRightCorner(nm, nm))};
  }
  /// θ of both bodies by the solver (its conductance set by the caller).
  [[nodiscard]] Eigen::VectorXd solve(const physics::InterfaceHeatSolver& solver) const {
    core::Vector bs = core::Vector::from(std::vector<double>(b.data(), b.data() + ns));
    core::Vector bm = core::Vector::from(std::vector<double>(b.data() + ns, b.data() + ns + nm));
    core::Vector xs(ns), xm(nm);
    xs.view()[0] = theta_s0;
    xm.view()[1] = theta_m1;
    solver.solve(bs, bm, xs, xm);
    Eigen::VectorXd x(ns + nm);
    const auto s = xs.to_std(), m = xm.to_std();
    for (int i = 0; i < ns; ++i) x(i) = s[i];
    for (int i = 0; i < nm; ++i) x(ns + i) = m[i];
    return x;
  }
  /// The dense (A + L) with the constrained rows replaced by θ = θ_D.
  [[nodiscard]] Eigen::VectorXd reference(const Eigen::MatrixXd& l) const {
    Eigen::MatrixXd full = l;
    full.topLeftCorner(ns, ns) += as;
    full.bottomRightCorner(nm, nm) += am;
    Eigen::VectorXd rhs = b;
    for (const auto& [row, value] : {std::pair{0, theta_s0}, {ns + 1, theta_m1}}) {
      full.row(row).setZero();
      full(row, row) = 1.0;
      rhs(row) = value;
    }
    return full.lu().solve(rhs);
  }
};

// Round-off only: 1e-12 of the largest temperature.
void expect_solves(const TwoChains& c, const physics::InterfaceHeatSolver& solver,
                   const Eigen::MatrixXd& l) {
  const Eigen::VectorXd x = c.solve(solver), ref = c.reference(l);
  for (int i = 0; i < x.size(); ++i)
    EXPECT_NEAR(x(i), ref(i), 1e-12 * ref.cwiseAbs().maxCoeff()) << i;
}

TEST(InterfaceHeatSolver, SolvesTheCoupledSystemExactlyWithDirichletNodesOnTheInterface) {
  const TwoChains c;
  const Eigen::MatrixXd g = Eigen::MatrixXd::Random(6, 6);
  const Eigen::MatrixXd l = c.full_l(40.0 * g * g.transpose());
  physics::InterfaceHeatSolver solver(c.solver_s, c.ns, c.gs, c.solver_m, c.nm, c.gm);
  const auto tc = TwoChains::blocks(l);
  solver.set_conductance(tc);
  EXPECT_EQ(solver.active_nodes(), 6);
  expect_solves(c, solver, l);
  EXPECT_EQ(solver.setup_solves(), 6);  // one column of S per interface node, once
  solver.set_conductance(tc);
  EXPECT_EQ(solver.setup_solves(), 6);
}

TEST(InterfaceHeatSolver, RefinesWithTheLastLuWhileLStaysOnItsNodes) {
  // L on the first two nodes of each side (J = 4 nodes), then 0.1 % larger there (as γ moves in
  // the fixed point): refinement with the first LU; then 30× larger: refinement does not
  // contract, a new LU; then on all six nodes: J grows, a new LU. Every solve to round-off
  // against the dense solve (the refinement's stop, 1e-12 of the interface values, is below
  // the 1e-12 of the largest temperature asked here only by their ratio, ~1).
  // Five random draws of the data; without `refine` a new LU every time.
  for (unsigned seed = 1; seed <= 5; ++seed) {
    std::srand(seed);
    const TwoChains c;
    const Eigen::MatrixXd g = Eigen::MatrixXd::Random(6, 6);
    Eigen::MatrixXd part = 40.0 * g * g.transpose();
    for (const int a : {2, 5}) part.row(a).setZero(), part.col(a).setZero();
    physics::InterfaceHeatSolver solver(c.solver_s, c.ns, c.gs, c.solver_m, c.nm, c.gm);
    const auto check = [&](const Eigen::MatrixXd& lg, bool refine, int active, long lus) {
      const Eigen::MatrixXd l = c.full_l(lg);
      solver.set_conductance(TwoChains::blocks(l), refine);
      expect_solves(c, solver, l);
      EXPECT_EQ(solver.active_nodes(), active) << seed;
      EXPECT_EQ(solver.factorizations(), lus) << seed;
    };
    check(part, true, 4, 1);
    const long before = solver.refinement_steps();
    check(1.001 * part, true, 4, 1);
    EXPECT_GT(solver.refinement_steps(), before) << seed;
    check(30.0 * part, true, 4, 2);
    check(40.0 * g * g.transpose(), true, 6, 3);
    check(part, true, 6, 4);  // L on fewer nodes than J: J kept (L moved far: a new LU)
    check(part, false, 4, 5);
  }
}

TEST(InterfaceHeatSolver, ByForwardColumnsGivesTheSameTemperaturesInOneSolvePerBody) {
  // Two 3D grids (shifted Laplacians, 14³ and 13³: CHOLMOD's supernodal factors) joined on a
  // 6 × 6 patch of their facing sides, a Dirichlet node on each patch, L random SPD over the
  // patches. With -tc_forward_compliance S comes from Y = L⁻¹P E_T and each solve shares its
  // halves (P G(b) = Yᵀz, θ = PᵀL⁻ᵀ(z − Y Pᵀ L_Γ y)): the same θ as the two full solves per
  // body to round-off, 1e-12 of the largest temperature (κ of the grids and of I + S L is
  // O(10²)). Exactly equal would mean the halves were not taken.
  const auto& packages = linalg::available_cholesky_packages();
  if (std::find(packages.begin(), packages.end(), std::string(MATSOLVERCHOLMOD)) == packages.end())
    GTEST_SKIP() << "no CHOLMOD";
  const PetscInt gs = 14, gm = 13, side = 6;
  const auto as = shifted_laplacian(gs), am = shifted_laplacian(gm);
  std::vector<int> ps, pm;  // the slave's top patch, the master's bottom one, in the same order
  for (PetscInt y = 0; y < side; ++y)
    for (PetscInt x = 0; x < side; ++x) {
      ps.push_back(static_cast<int>(x + gs * (y + gs * (gs - 1))));
      pm.push_back(static_cast<int>(x + gm * y));
    }
  const physics::ConstrainedSolver solver_s{as, {ps[7]}, MATSOLVERCHOLMOD},
      solver_m{am, {pm[20]}, MATSOLVERCHOLMOD};
  const PetscInt ns = gs * gs * gs, nm = gm * gm * gm;
  const auto np = static_cast<Eigen::Index>(ps.size());
  const Eigen::MatrixXd g = Eigen::MatrixXd::Random(2 * np, 2 * np);
  const Eigen::MatrixXd lg = 0.5 * g * g.transpose();
  const auto block = [&](PetscInt rows, PetscInt cols, const std::vector<int>& r,
                         const std::vector<int>& c, Eigen::Index r0, Eigen::Index c0) {
    core::SparseMatrix m(rows, cols,
                         std::vector<PetscInt>(static_cast<size_t>(rows), 2 * side * side));
    for (Eigen::Index a = 0; a < np; ++a)
      for (Eigen::Index b = 0; b < np; ++b) {
        const PetscInt i = r[static_cast<size_t>(a)], j = c[static_cast<size_t>(b)];
        const double v = lg(r0 + a, c0 + b);
        m.add_values(std::span(&i, 1), std::span(&j, 1), &v);
      }
    m.assemble();
    return m;
  };
  const contact::ThermalContact l{block(ns, ns, ps, ps, 0, 0), block(ns, nm, ps, pm, 0, np),
                                  block(nm, ns, pm, ps, np, 0), block(nm, nm, pm, pm, np, np)};
  const auto solve = [&](bool forward) {
    if (forward) TC_PETSC(PetscOptionsSetValue(nullptr, "-tc_forward_compliance", nullptr));
    physics::InterfaceHeatSolver solver(solver_s, ns, ps, solver_m, nm, pm);
    solver.set_conductance(l);  // S's first cover: the path is chosen here
    if (forward) TC_PETSC(PetscOptionsClearValue(nullptr, "-tc_forward_compliance"));
    core::Vector bs(ns), bm(nm), xs(ns), xm(nm);
    {
      auto bv = bs.view();
      for (PetscInt i = 0; i < ns; ++i) bv[i] = std::sin(0.1 * static_cast<double>(i));
      auto cv = bm.view();
      for (PetscInt i = 0; i < nm; ++i) cv[i] = std::cos(0.2 * static_cast<double>(i));
    }
    xs.view()[ps[7]] = 300.0;
    xm.view()[pm[20]] = 310.0;
    solver.solve(bs, bm, xs, xm);
    auto x = xs.to_std();
    const auto m = xm.to_std();
    x.insert(x.end(), m.begin(), m.end());
    return x;
  };
  const auto full = solve(false), halves = solve(true);
  double scale = 0, diff = 0;
  for (size_t i = 0; i < full.size(); ++i) {
    scale = std::max(scale, std::abs(full[i]));
    diff = std::max(diff, std::abs(full[i] - halves[i]));
  }
  for (const auto* x : {&full, &halves}) {  // θ_D back from diag·θ_D / diag, to round-off
    EXPECT_NEAR((*x)[static_cast<size_t>(ps[7])], 300.0, 1e-12 * scale);
    EXPECT_NEAR((*x)[static_cast<size_t>(ns + pm[20])], 310.0, 1e-12 * scale);
  }
  EXPECT_LE(diff, 1e-12 * scale);
  EXPECT_GT(diff, 0.0) << "the forward-solve path was not taken";
}

// ---------------------------------------------------------------------------------------------
// Steady conduction (verification.md's 4C case): lower block [0.5,1.5]²×[−0.5,0.5] (3×3×3,
// slave, its top) and upper block [0.5,1.5]²×[0.5,1.5] (2×2×2, master), E = 4000, ν = 0,
// α = 0, κ = 52, γ_C^s = γ_C^m = γ; bottom at θ_low, top at θ_high and pushed down 0.015:
// p = Eδ/(L₁ + L₂) = 30. ρc_p = 1 and τ = 1e4 s: each backward-Euler step damps the transient
// by 1/(1 + τκπ²/(4ρc_p L²)) < 1e-5, so three steps reach the steady state to round-off.
constexpr double kLow = kTheta0 + 20, kHigh = kTheta0 + 40, kKappa = 52, kPush = 0.015;

physics::Problem conduction_blocks(double gamma, int steps = 3) {
  auto p = pressed_conduction_blocks(kTheta0, kKappa, kPush, steps);
  p.boundaries.push_back(temperature_bc(0, "zmin", kLow));
  p.boundaries.push_back(temperature_bc(1, "zmax", kHigh));
  auto c = contact_pair(0, "zmax", 1, "zmin");
  c.conductance_slave = c.conductance_master = gamma;
  p.contacts = {c};
  return p;
}

struct NullObserver : physics::Observer {};

TEST(ThermalContact, SteadyConductionThroughPressedBlocksIsTheSeriesResistance) {
  const auto p = conduction_blocks(10.0);  // β_C = 5
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  NullObserver none;
  double conducted_before = 0;
  for (int s = 0; s < 3; ++s) {
    conducted_before = sim.history("heat_conducted");
    sim.advance();
  }
  const double pressure = 4000 * kPush / 2.0;                          // 30
  const double h = sim.interface_laws().beta_c(kAnyTheta) * pressure;  // 150
  ASSERT_NEAR(h, 150.0, 1e-12);
  const double q = (kHigh - kLow) / (1.0 / kKappa + 1.0 / h + 1.0 / kKappa);  // 443.1818…
  ASSERT_NEAR(q, 443.1818, 1e-4);
  // Linear elements reproduce the piecewise linear profile exactly and the pressure is uniform
  // (mortar patch test), so what is left is the QP/coupling tolerances (1e-12) and the
  // factorisations' round-off: 1e-8 relative is far above both and far below the 1 % asked.
  const double tol = 1e-8;
  const auto lambda = sim.contact_multipliers();
  const auto& rows = sim.dual_solver()->rows();
  ASSERT_EQ(rows.n_nodes(), 16);  // the 4×4 nodes of the slave's top
  for (PetscInt k = 0; k < rows.n_nodes(); ++k) EXPECT_NEAR(lambda[3 * k], pressure, tol * 30);
  // The interface temperatures: 4C's 28.5227273 (lower, slave) and 31.4772727 (upper, master).
  const double th_slave = kLow + q / kKappa, th_master = kHigh - q / kKappa;
  EXPECT_NEAR(th_slave - kTheta0, 28.5227273, 1e-7);
  EXPECT_NEAR(th_master - kTheta0, 31.4772727, 1e-7);
  for (int b = 0; b < 2; ++b) {
    const auto theta = sim.state(b).theta.to_std();
    const auto& m = p.bodies[b].mesh;
    for (int a = 0; a < m.n_nodes(); ++a) {
      const double z = m.point(a)[2];
      const double expected =
          b == 0 ? kLow + q * (z + 0.5) / kKappa : th_master + q * (z - 0.5) / kKappa;
      EXPECT_NEAR(theta[a], expected, tol * (kHigh - kLow)) << "body " << b << " node " << a;
    }
  }
  // The jump [θ] = θ_s − θ_m = −q/h and the flux out of the slave β_C λ_n [θ] = −q per node.
  EXPECT_NEAR(th_slave - th_master, -q / h, 1e-12);
  const auto& flux = sim.contact_heat_flux();
  ASSERT_EQ(flux.size(), 16u);
  for (const double f : flux) EXPECT_NEAR(f, -q, tol * q);
  // heat_conducted (slave → master) over the last step: −q · area · τ (area 1).
  EXPECT_NEAR((sim.history("heat_conducted") - conducted_before) / p.time.step, -q, tol * q);
  // No other heat: the frictionless pair generates none.
  EXPECT_EQ(sim.history("heat_generated"), 0.0);
  EXPECT_GT(sim.interface_heat_solver()->active_nodes(), 0);
  std::cout << "[ measure  ] implicit conductance, strong (h L/κ = 5.8): "
            << sim.total_coupling_iterations() << " coupling iterations in 3 steps\n";
}

TEST(ThermalContact, LaggedConductanceDivergesWhenStrongAndConvergesWhenWeak) {
  // (6.2) puts L θ^p on the right: the heat step iterates θ ← A⁻¹(b − Lθ), which converges
  // iff ρ(A⁻¹L) < 1; here ρ ≈ h(L₁/κ₁ + L₂/κ₂) = 150·2/52 = 5.8 (strong) and 0.058 (weak).
  NullObserver none;
  {
    auto p = conduction_blocks(10.0);
    p.solver.conductance_treatment = physics::ConductanceTreatment::lagged;
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    const auto status = sim.run(none);
    EXPECT_FALSE(status.completed) << "the lagged conductance was expected to diverge";
    std::cout << "[ measure  ] lagged conductance, strong: " << status.message << "\n";
  }
  long iterations[2] = {0, 0};
  for (const auto treatment :
       {physics::ConductanceTreatment::implicit, physics::ConductanceTreatment::lagged}) {
    auto p = conduction_blocks(0.1);  // β_C = 0.05, h = 1.5
    p.solver.conductance_treatment = treatment;
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    const auto status = sim.run(none);
    ASSERT_TRUE(status.completed) << status.message;
    const double h = sim.interface_laws().beta_c(kAnyTheta) * 30;
    const double q = (kHigh - kLow) / (2.0 / kKappa + 1.0 / h);
    for (const double f : sim.contact_heat_flux()) EXPECT_NEAR(f, -q, 1e-8 * q);
    iterations[treatment == physics::ConductanceTreatment::lagged] =
        sim.total_coupling_iterations();
  }
  std::cout << "[ measure  ] weak conductance (h L/κ = 0.058), coupling iterations in 3 steps: "
            << "implicit " << iterations[0] << ", lagged " << iterations[1] << "\n";
  EXPECT_LT(iterations[0], iterations[1]);
}

// ---------------------------------------------------------------------------------------------
// Frictional heating: the slave [0,1]²×[1,1.5] (4×4×2) is pressed (step 1) onto the master
// [−0.25,1.25]²×[0,1] (5×5×3, bottom held) and then dragged along x at v by its top; both
// insulated, α = 0, no thermoelastic heating. The master is wider, so the slave stays covered.
constexpr double kV = 0.01, kTau = 0.1, kFriction = 0.3;
constexpr int kSlideSteps = 10;

physics::Problem sliding_blocks(bool conduction, bool frictional_heating, double friction) {
  auto mat = steel();
  mat.thermal_expansion = 0;
  auto p = slider_on_base(mat, kTau, kV, kSlideSteps, kTheta0, kTheta0 + 5, friction);
  p.contacts.at(0).heat_conduction = conduction;
  p.contacts.at(0).frictional_heating = frictional_heating;
  return p;
}

struct SlideResult {
  double expected = 0;  // Σ_sliding steps τ 𝔉 N v
  double slave_energy = 0, master_energy = 0;
};

SlideResult slide(physics::Simulation& sim) {
  SlideResult r;
  const double e_s0 = body_energy(sim, 0, kTheta0), e_m0 = body_energy(sim, 1, kTheta0);
  sim.advance();  // the press
  for (int s = 0; s < kSlideSteps; ++s) {
    sim.advance();
    r.expected += kTau * sim.problem().contacts.at(0).friction(kAnyTheta) *
                  sim.history("contact_normal_force") * kV;
  }
  r.slave_energy = body_energy(sim, 0, kTheta0) - e_s0;
  r.master_energy = body_energy(sim, 1, kTheta0) - e_m0;
  return r;
}

class FrictionalHeating : public ::testing::TestWithParam<bool> {};

TEST_P(FrictionalHeating, IsFrictionTimesLoadTimesSlidingDistanceSplitByDeltaC) {
  const bool conduction = GetParam();
  const auto p = sliding_blocks(conduction, true, kFriction);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  const double e0 = sim.history("thermal_energy");
  const auto r = slide(sim);
  const double generated = sim.history("heat_generated");
  ASSERT_GT(generated, 0);
  // 𝔉 N v t: the slave slides at v once the first sliding step has built the elastic shear
  // (𝔉 p h/G ≈ 1e-6 m against v t = 1e-2 m), so 1 % is generous; the measured error is printed.
  EXPECT_NEAR(generated, r.expected, 0.01 * r.expected);
  // The mechanical dissipation Σ λ_τᵀB_τΔu of the converged steps: the heat is the same sum
  // at the iterate of the last heat step, so they agree to the coupling tolerance (1e-8).
  EXPECT_NEAR(generated, sim.history("frictional_dissipation"), 1e-7 * generated);
  // δ_C = γ_s/(γ_s + γ_m) = 0.2 of it to the slave: by construction, to round-off.
  EXPECT_NEAR(sim.history("heat_to_slave") / generated, sim.interface_laws().delta_c(kAnyTheta),
              1e-12);
  EXPECT_NEAR(sim.interface_laws().delta_c(kAnyTheta), 0.2, 1e-15);
  EXPECT_NEAR(sim.history("heat_to_slave") + sim.history("heat_to_master"), generated,
              1e-12 * generated);
  // Insulated pair: backward Euler conserves 1ᵀM_θθ exactly up to the inputs, and 1ᵀK_θ = 0,
  // 1ᵀL_θγ = 0 over both bodies, so the energy rise is the heat generated to the solves'
  // round-off (θ ~ 300 K carries ~1e-13 relative, i.e. ~1e-7 J on ρc_p V θ ~ 1e9 J).
  EXPECT_NEAR(sim.history("thermal_energy") - e0, generated, 1e-6 * generated);
  // Each body: what friction gave it minus (plus) what it conducted away.
  const double conducted = sim.history("heat_conducted");
  EXPECT_NEAR(r.slave_energy, sim.history("heat_to_slave") - conducted, 1e-6 * generated);
  EXPECT_NEAR(r.master_energy, sim.history("heat_to_master") + conducted, 1e-6 * generated);
  if (conduction)  // the slave starts 5 K hotter: heat goes to the master
    EXPECT_GT(conducted, 0.01 * generated);
  else
    EXPECT_EQ(conducted, 0.0);
  std::cout << "[ measure  ] frictional heating (conduction " << (conduction ? "on" : "off")
            << "): heat_generated " << generated << " J, 𝔉Nvt " << r.expected
            << " J, relative error " << (generated - r.expected) / r.expected << ", dissipation "
            << sim.history("frictional_dissipation") << " J, conducted " << conducted
            << " J, coupling iterations " << sim.total_coupling_iterations() << " in " << sim.step()
            << " steps\n";
}

TEST(ThermalContact, DynamicSlidingHeatEqualsTheDissipationEveryStep) {
  // The sliding pair with Newmark (contact-stabilised): the slave is dragged at v from rest, so
  // u̇ at the interface oscillates from step to step (2v, 0, 2v, … with the trapezoidal rule).
  // The heat of a step and the mechanical dissipation are one sum, the friction work
  // λ_τ,k·(B_τΔu)_k, at the last heat iterate and at the converged step: equal to the
  // coupling tolerance (1e-8), and each step's is 𝔉Nvτ up to the oscillation of λ_n.
  auto p = sliding_blocks(false, true, kFriction);
  p.time.scheme = physics::Scheme::dynamic;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  sim.advance();  // the press
  double expected = 0, worst = 0, spread = 0, supports = 0;
  for (int s = 0; s < kSlideSteps; ++s) {
    const double g0 = sim.history("heat_generated"), d0 = sim.history("frictional_dissipation");
    sim.advance();
    const double g = sim.history("heat_generated") - g0;
    const double d = sim.history("frictional_dissipation") - d0;
    const double fnvt = kTau * kFriction * sim.history("contact_normal_force") * kV;
    expected += fnvt;
    supports += kTau * kFriction * std::abs(sim.history("reaction_slider_zmax_z")) * kV;
    worst = std::max(worst, std::abs(g - d) / fnvt);
    spread = std::max(spread, std::abs(g / fnvt - 1));
    EXPECT_NEAR(g, d, 1e-7 * fnvt) << "step " << sim.step();
    // Δu/τ of the step is v (the drag is prescribed) but for the elastic shear's oscillation;
    // the power at t^{k+1}, λ_τ·B_τu̇^{k+1}, would be off by ~100 % here (measured: 1.95, 0.09).
    EXPECT_NEAR(g, fnvt, 0.05 * fnvt) << "step " << sim.step();
  }
  const double generated = sim.history("heat_generated");
  EXPECT_NEAR(generated, expected, 0.01 * expected);
  // Independently of λ: the normal force from the support reactions (M ü + K u − f on the
  // slider's top). The stabilised scheme's λ is twice the traction (traction_per_multiplier);
  // counted with λ itself, heat and N would both be 2× this.
  EXPECT_NEAR(generated, supports, 0.02 * supports);
  std::cout << "[ measure  ] dynamic sliding: heat_generated " << generated << " J, 𝔉Nvt "
            << expected << " J, relative error " << (generated - expected) / expected
            << ", 𝔉 × support reaction × vt " << supports << " J, per step within " << spread
            << " of 𝔉Nvτ, worst |heat − dissipation| per step / "
            << "𝔉Nvτ " << worst << "\n";
}

INSTANTIATE_TEST_SUITE_P(ConductionOnOrOff, FrictionalHeating, ::testing::Bool(),
                         [](const auto& info) {
                           return std::string(info.param ? "conduction_on" : "conduction_off");
                         });

TEST(ThermalContact, AitkenRelaxationDoesNotSlowTheCoulombFixedPoint) {
  // The Tresca → Coulomb fixed point of the sliding pair, plain (6.3) and Aitken-relaxed: the
  // same answer (to the coupling tolerance) in no more iterations; the counts are printed.
  long iterations[2] = {0, 0};
  double heat[2] = {0, 0};
  for (const bool aitken : {false, true}) {
    auto p = sliding_blocks(true, true, kFriction);
    p.solver.friction.acceleration = aitken;
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    slide(sim);
    iterations[aitken] = sim.total_coupling_iterations();
    heat[aitken] = sim.history("heat_generated");
  }
  EXPECT_NEAR(heat[1], heat[0], 1e-6 * heat[0]);
  EXPECT_LE(iterations[1], iterations[0]);
  std::cout << "[ measure  ] sliding pair, coupling iterations in 11 steps: plain " << iterations[0]
            << ", Aitken " << iterations[1] << "\n";
}

// ---------------------------------------------------------------------------------------------
TEST(ThermalContact, SwitchedOffConductionLetsNoHeatCross) {
  // The sliding pair with a 5 K difference and no friction: with conduction each body's energy
  // changes (the control that lets the test fail), without it neither does, to round-off.
  for (const bool conduction : {true, false}) {
    const auto p = sliding_blocks(conduction, true, 0.0);
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    const auto r = slide(sim);
    const double scale = 5 * p.bodies[0].material.heat_capacity() * 0.5;  // ρc_p ΔT V ≈ 8.8e6 J
    EXPECT_EQ(sim.history("heat_generated"), 0.0);
    if (conduction) {
      EXPECT_GT(sim.history("heat_conducted"), 1e-5 * scale);  // measured ≈ 1e-4 scale
      EXPECT_NEAR(r.slave_energy, -sim.history("heat_conducted"), 1e-12 * scale);
    } else {
      EXPECT_EQ(sim.history("heat_conducted"), 0.0);
      EXPECT_NEAR(r.slave_energy, 0.0, 1e-12 * scale);
      EXPECT_NEAR(r.master_energy, 0.0, 1e-12 * scale);
      for (const double f : sim.contact_heat_flux()) EXPECT_EQ(f, 0.0);
    }
  }
}

TEST(ThermalContact, SwitchedOffFrictionalHeatingGeneratesNone) {
  for (const bool heating : {true, false}) {
    const auto p = sliding_blocks(false, heating, kFriction);
    physics::Simulation sim(p);
    sim.enable_mortar_contact();
    const auto r = slide(sim);
    EXPECT_GT(sim.history("frictional_dissipation"), 0);  // it slides either way
    if (heating) {
      EXPECT_GT(sim.history("heat_generated"), 0.5 * r.expected);  // the control
    } else {
      EXPECT_EQ(sim.history("heat_generated"), 0.0);
      EXPECT_EQ(sim.history("heat_to_slave"), 0.0);
      EXPECT_EQ(sim.history("heat_to_master"), 0.0);
      const double scale = r.expected;  // what friction would have made
      EXPECT_NEAR(r.slave_energy, 0.0, 1e-9 * scale);
      EXPECT_NEAR(r.master_energy, 0.0, 1e-9 * scale);
    }
  }
}

// ---------------------------------------------------------------------------------------------
TEST(ThermalContact, TwoHalfSpacesUnderConstantFrictionalPower) {
  // verification.md: two half-spaces, frictional power D per area from t = 0, conductance
  // h = β_C p, effusivities e_i = √(κρc_p)_i, H = h(1/e_s + 1/e_m):
  //   e_s Δθ_s + e_m Δθ_m = 2D√(t/π),
  //   Δθ_s − Δθ_m = D(δ_C/e_s − (1 − δ_C)/e_m)(1 − e^{H²t} erfc(H√t))/H.
  // Columns of 1×1×120 Hex8 (6 m tall, diffusion length √(κt/ρc_p) = 1 m at t = 1 s, so the far
  // ends are 6 lengths away: e^{−9} of the flux reaches them), ρc_p = κ = 1 (e = 1),
  // ν = 0, α = 0; p = Eδ/(L_s + L_m) = 1, γ_s = 5, γ_m = 1.25 (β_C = 1, δ_C = 0.8), 𝔉 = 0.5,
  // the slave's top dragged at v = 1e-3 from t = 0 (the elastic shear takes 1e-7 m of it).
  constexpr double kL = 6, kE = 1.2e8, kPress = 1e-7, kSpeed = 1e-3, kT = 1.0, kStep = 0.005;
  fem::Material mat;
  mat.density = 1;
  mat.young_modulus = kE;
  mat.poisson_ratio = 0;
  mat.thermal_expansion = 0;
  mat.specific_heat = 1;
  mat.thermal_conductivity = 1;
  physics::Problem p;
  p.dimension = 3;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = kStep;
  p.time.end = kT;
  p.physics.reference_temperature = kTheta0;
  p.physics.thermoelastic_heating = false;
  p.bodies.push_back(box_body("upper", mat, {0, 0, 0}, {1, 1, kL}, {1, 1, 120}, kTheta0));
  p.bodies.push_back(box_body("lower", mat, {0, 0, -kL}, {1, 1, 0}, {1, 1, 120}, kTheta0));
  const core::TimeTable drag({0, kT}, {0, kSpeed * kT});
  p.boundaries.push_back(displacement_bc(0, "zmax", {{0, drag}, {1, 0.0}, {2, -kPress}}));
  p.boundaries.push_back(displacement_bc(1, "zmin", {{0, 0.0}, {1, 0.0}, {2, 0.0}}));
  auto c = contact_pair(0, "zmin", 1, "zmax", 0.5);
  c.conductance_slave = 5;
  c.conductance_master = 1.25;
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-12;
  p.solver.coupling_tolerance = 1e-10;
  p.solver.max_coupling_iterations = 50;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  ASSERT_NEAR(sim.interface_laws().beta_c(kAnyTheta), 1.0, 1e-14);
  ASSERT_NEAR(sim.interface_laws().delta_c(kAnyTheta), 0.8, 1e-14);
  double generated_before = 0;
  while (sim.step() < p.time.n_steps()) {
    generated_before = sim.history("heat_generated");
    sim.advance();
  }
  const double pressure = kE * kPress / (2 * kL);
  const double power = (sim.history("heat_generated") - generated_before) / kStep;  // area 1
  // The power the run makes: 𝔉 N v with the normal force N of the step (N is 0.9 % below
  // p·area: the friction force bends the tall columns and the overlap shrinks by v t = 1e-3).
  const double normal = sim.history("contact_normal_force");
  EXPECT_NEAR(normal, pressure, 0.02 * pressure);
  EXPECT_NEAR(power, 0.5 * normal * kSpeed, 1e-4 * power);  // measured 6e-5: the slip rate
  // at the quadrature points vs the nodal multipliers of the step
  auto surface = [&](int b) {  // mean θ − θ₀ of the body's nodes at z = 0
    const auto theta = sim.state(b).theta.to_std();
    const auto& m = p.bodies[b].mesh;
    double sum = 0;
    int n = 0;
    for (int a = 0; a < m.n_nodes(); ++a)
      if (std::abs(m.point(a)[2]) < 1e-12) {
        sum += theta[a] - kTheta0;
        ++n;
      }
    return sum / n;
  };
  const double ds = surface(0), dm = surface(1);
  const double h = sim.interface_laws().beta_c(kAnyTheta) * pressure, H = 2 * h, t = kT;
  const double sum_expected = 2 * power * std::sqrt(t / M_PI);
  const double jump_expected =
      power * (0.8 - 0.2) * (1 - std::exp(H * H * t) * std::erfc(H * std::sqrt(t))) / H;
  std::cout << "[ measure  ] two half-spaces at t = 1: e_sΔθ_s + e_mΔθ_m = " << ds + dm
            << " (closed form " << sum_expected << ", relative error "
            << (ds + dm - sum_expected) / sum_expected << "), jump " << ds - dm << " (closed form "
            << jump_expected << ", relative error " << (ds - dm - jump_expected) / jump_expected
            << ")\n";
  // Backward Euler with τ = 0.005 s on a response ∝ √t and h = 0.05 against a diffusion
  // length of 1: both errors are O(1e-3) at t = 1; 1 % bounds them.
  EXPECT_NEAR(ds + dm, sum_expected, 0.01 * sum_expected);
  EXPECT_NEAR(ds - dm, jump_expected, 0.01 * jump_expected);
}

// ---------------------------------------------------------------------------------------------
TEST(ThermalContact, HeatedSlaveBetweenMasterAndWallPressesHarder) {
  // Slave [0,1]²×[1,1.5] (3×3×2) on master [0,1]²×[0,1] (2×2×3), rollers on every lateral face,
  // master's bottom held, slave's top a wall pushed down δ (step 1) and then held. A uniform
  // source r heats the insulated slave (conduction off, so the master stays at θ₀):
  // ΔT = r t/(ρc_p) exactly (consistent mass, uniform source). Laterally constrained blocks:
  // ε_zz = (βΔT − p)/M, M = λ + 2μ, and h_s ε_s + h_m ε_m = −δ give
  //   p = (δ + h_s βΔT/M_s)/(h_s/M_s + h_m/M_m).
  const auto mat = steel();
  physics::Problem p;
  p.dimension = 3;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 0.1;
  p.time.end = 1.0;
  p.physics.reference_temperature = kTheta0;
  p.physics.thermoelastic_heating = false;
  const double delta = 1e-5, h_s = 0.5, h_m = 1.0, r = 3.5e8;  // ΔT = 100 K after 1 s
  p.bodies.push_back(box_body("heated", mat, {0, 0, 1}, {1, 1, 1.5}, {3, 3, 2}, kTheta0));
  p.bodies.push_back(box_body("base", mat, {0, 0, 0}, {1, 1, 1}, {2, 2, 3}, kTheta0));
  p.bodies[0].heat_source = core::TimeTable(r);
  p.boundaries.push_back(displacement_bc(0, "zmax", {{2, -delta}}));
  p.boundaries.push_back(displacement_bc(1, "zmin", {{2, 0.0}}));
  for (int b = 0; b < 2; ++b)
    for (const auto* side : {"xmin", "xmax"})
      p.boundaries.push_back(displacement_bc(b, side, {{0, 0.0}}));
  for (int b = 0; b < 2; ++b)
    for (const auto* side : {"ymin", "ymax"})
      p.boundaries.push_back(displacement_bc(b, side, {{1, 0.0}}));
  auto c = contact_pair(0, "zmin", 1, "zmax");
  c.conductance_slave = c.conductance_master = 1e-3;
  c.heat_conduction = false;
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-12;
  p.solver.coupling_tolerance = 1e-12;
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  const double m_mod = mat.lame_lambda() + 2 * mat.lame_mu();
  const double beta = mat.thermal_stress_modulus();
  for (int s = 1; s <= 10; ++s) {
    sim.advance();
    const double dtheta = r * sim.time() / mat.heat_capacity();
    const double expected = (delta + h_s * beta * dtheta / m_mod) / ((h_s + h_m) / m_mod);
    // The fields are uniform in each block, which trilinear elements and the mortar patch test
    // reproduce exactly: 1e-6 relative covers the tolerances and is far inside the 2 % asked.
    EXPECT_NEAR(sim.history("contact_normal_force"), expected, 1e-6 * expected) << "step " << s;
    for (const double t : sim.state(0).theta.to_std())
      EXPECT_NEAR(t - kTheta0, dtheta, 1e-9 * dtheta);
  }
  // The pressure did rise, by two orders of magnitude over the cold press δM/(h_s + h_m)
  // (a check that the test can fail).
  EXPECT_GT(sim.history("contact_normal_force"), 50 * delta * m_mod / (h_s + h_m));
}

}  // namespace
}  // namespace tc::test
