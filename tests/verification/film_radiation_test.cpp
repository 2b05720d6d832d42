// Film (convection, Robin) and radiation boundaries against closed forms (issue 21):
//  1. lumped cooling: a small body (Biot hV/(Aκ) < 0.01) in a film follows
//     θ(t) = θ∞ + (θ₀ − θ∞) exp(−hA t/(ρc_pV)) to 1e-3 of the temperature drop;
//  2. a slab [0, L] with θ(0) = θ_D and a film (h, θ∞) at x = L reaches the steady profile of
//     the series resistance L/κ + 1/h: q = (θ_D − θ∞)/(L/κ + 1/h), θ(x) = θ_D − q x/κ, to 1e-8
//     of θ_D − θ∞, on Quad4, Tri3, Hex8 and Tet4 meshes (distorted inside), with h constant
//     (in the heat operator), with h(t) (Newton's path) and cut into FETI subdomains;
//  3. a thin plate [0, d] heated by q at x = 0 and radiating at x = d reaches
//     θ(d) = (q/(εσ) + θ∞⁴)^(1/4) (all of q leaves by radiation) and θ(0) = θ(d) + q d/κ,
//     to 1e-6 relative;
//  4. the energy ledger: with no other heat in or out, thermal_energy(t) − thermal_energy(0)
//     = −(heat_film + heat_radiation) to the solver's tolerance;
//  5. two blocks in contact, the upper one exchanging heat through a film or by radiation:
//     the steady series profile (conduction, contact conductance, film or radiation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "support/problems.hpp"
#include "support/test_meshes.hpp"
#include "tc/physics/body/body_field.hpp"
#include "tc/physics/body/boundary_heat_newton.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

struct Quiet : physics::Observer {};

constexpr double kAnyTheta = 293.15;  // the contact conductances here are constants

/// Records thermal_energy after every step.
struct EnergyTrace : physics::Observer {
  std::vector<double> time, energy, film, radiation;
  void step(const physics::Simulation& s) override {
    time.push_back(s.time());
    energy.push_back(s.history("thermal_energy"));
    film.push_back(s.history("heat_film"));
    radiation.push_back(s.history("heat_radiation"));
  }
};

/// A body whose mechanics plays no part: no expansion, no thermoelastic heating.
physics::Problem heat_only(int dim, const mesh::Point& size, const std::array<int, 3>& cells,
                           double step, int n_steps) {
  auto p = box_problem(dim, size, cells, steel(), physics::Scheme::quasistatic, step, n_steps);
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  // Quasistatic bodies must be held: fix xmin (it carries no heat condition by itself).
  p.boundaries.push_back(hold(
      "xmin", dim == 2 ? std::initializer_list<int>{0, 1} : std::initializer_list<int>{0, 1, 2}));
  return p;
}

physics::BoundaryCondition film(const std::string& where, core::TimeTable h, double ambient) {
  physics::BoundaryCondition bc;
  bc.where = where;
  bc.film = physics::Film{std::move(h), core::TimeTable(ambient)};
  return bc;
}

std::vector<std::string> faces(int dim) {
  if (dim == 2) return {"xmin", "xmax", "ymin", "ymax"};
  return {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
}

// ---- 1. Lumped cooling ---------------------------------------------------------------------

struct Cooling {
  double worst = 0;     // max over the run of |θ_mean − θ_exact| / (θ₀ − θ_exact)
  double worst_be = 0;  // the same against backward Euler's own discrete exponential
};

Cooling lumped_cooling(int dim, int steps_per_tau) {
  // A 1 cm steel cube (2D: square, per metre) with h = 5 W/(m²K): Biot = h(V/A)/κ = 1.7e-4
  // (2D 2.5e-4), time constant T = ρc_pV/(hA) ≈ 1180 s (2D 1770 s). Mean temperature from
  // thermal_energy = ρc_p∫(θ − θ₀), compared over one time constant.
  const double side = 0.01, h = 5.0, theta_inf = 300.0, theta_start = 400.0;
  const auto mat = steel();
  const double volume = dim == 2 ? side * side : side * side * side;
  const double area = dim == 2 ? 4 * side : 6 * side * side;
  const double big_t = mat.density * mat.specific_heat * volume / (h * area);
  const double tau = big_t / steps_per_tau;
  auto p = heat_only(dim, {side, side, side}, {2, 2, 2}, tau, steps_per_tau);
  p.bodies[0].initial_temperature = theta_start;
  for (const auto& f : faces(dim)) p.boundaries.push_back(film(f, h, theta_inf));
  physics::Simulation sim(p);
  EnergyTrace trace;
  const auto status = sim.run(trace);
  EXPECT_TRUE(status.completed) << status.message;
  const double theta0 = p.physics.reference_temperature;
  Cooling c;
  for (size_t k = 1; k < trace.time.size(); ++k) {
    const double mean = theta0 + trace.energy[k] / (mat.heat_capacity() * volume);
    const double exact = theta_inf + (theta_start - theta_inf) * std::exp(-trace.time[k] / big_t);
    const double be = theta_inf + (theta_start - theta_inf) *
                                      std::pow(1.0 + tau / big_t, -static_cast<double>(k));
    c.worst = std::max(c.worst, std::abs(mean - exact) / (theta_start - exact));
    c.worst_be = std::max(c.worst_be, std::abs(mean - be) / (theta_start - be));
  }
  return c;
}

TEST(FilmBoundary, LumpedCoolingFollowsTheExponential) {
  // Backward Euler's error in the exponential: (1 + τ/T)^(−n) = exp(−t/T)(1 + tτ/(2T²) + …),
  // so against the drop θ₀ − θ(t) the relative error is e^(−t/T)/(1 − e^(−t/T))·tτ/(2T²):
  // 0.29 τ/T at t = T, largest there over (0, T] (≈ τ/(2T) as t → 0). With τ = T/1000: 2.9e-4.
  // The space error (the body is not quite isothermal: its decay rate is hA/(ρc_pV) times
  // 1 − O(Biot), Biot per axis h(side/2)/κ = 5e-4, the rate ~1.7e-4 slower) is ~1e-4 of the
  // drop at t = T: measured 1.2e-4 against backward Euler's own (1 + τ/T)^(−n). Together
  // 6.2e-4 (τ = T/1000) and 3.7e-4 (T/2000) < 1e-3; their ratio is (1.2 + 5)/(1.2 + 2.5) ≈ 1.7,
  // not 2, because only the time part is halved.
  for (const int dim : {2, 3}) {
    const auto coarse = lumped_cooling(dim, 1000);
    const auto fine = lumped_cooling(dim, 2000);
    std::printf(
        "dim %d: lumped cooling, worst error / drop: τ = T/1000 %.3e, τ = T/2000 %.3e; "
        "against backward Euler's discrete exponential %.3e\n",
        dim, coarse.worst, fine.worst, coarse.worst_be);
    EXPECT_LT(coarse.worst, 1e-3);
    EXPECT_LT(fine.worst, 1e-3);
    // First order in τ: the part above the space error halves with τ.
    const double time_coarse = coarse.worst - coarse.worst_be,
                 time_fine = fine.worst - fine.worst_be;
    EXPECT_NEAR(time_coarse / time_fine, 2.0, 0.2);
    EXPECT_LT(coarse.worst_be, 2e-4);  // what is left is the Biot (space) part
  }
}

// ---- 2. Slab with a prescribed temperature and a film -------------------------------------

enum class FilmKind { constant, table };

double slab_error(mesh::CellType type, FilmKind kind, int subdomains = 1) {
  // L = 0.1 m, κ = 50, h = 500: Biot hL/κ = 1, q = 100/(0.002 + 0.002) = 25000 W/m².
  const double length = 0.1, h = 500.0, theta_d = 400.0, theta_inf = 300.0;
  const int dim = mesh::dimension(type);
  const bool simplex = type == mesh::CellType::Tri3 || type == mesh::CellType::Tet4;
  // Steady state by backward Euler with τ = 1e8 s ≫ ρc_pL²/κ ≈ 700 s: each step shrinks the
  // transient by ~1e-5, three steps leave ~1e-15 of it.
  auto p = heat_only(dim, {length, 0.02, 0.02}, {8, 2, 2}, 1e8, 3);
  auto& m = p.bodies[0].mesh;
  if (simplex) m = dim == 2 ? split_quads(m) : split_hexes(m);
  m = perturb(m, 0.15 * 0.0125);  // interior nodes only: faces stay planar
  p.bodies[0].subdomains = subdomains;
  auto hot = physics::BoundaryCondition{};
  hot.where = "xmin";
  hot.temperature = core::TimeTable(theta_d);
  p.boundaries.push_back(hot);
  p.boundaries.push_back(film("xmax",
                              kind == FilmKind::constant
                                  ? core::TimeTable(h)
                                  : core::TimeTable({0.0, 1.0}, {0.5 * h, h}),  // h(t) → Newton
                              theta_inf));
  physics::Simulation sim(p);
  Quiet quiet;
  const auto status = sim.run(quiet);
  EXPECT_TRUE(status.completed) << status.message;
  const double kappa = p.bodies[0].material.thermal_conductivity;
  const double q = (theta_d - theta_inf) / (length / kappa + 1.0 / h);
  const auto theta = sim.state(0).theta.to_std();
  double worst = 0;
  for (int a = 0; a < m.n_nodes(); ++a)
    worst = std::max(worst, std::abs(theta[a] - (theta_d - q * m.point(a)[0] / kappa)));
  // The film's loss equals q·area in steady state (the last step's increment of heat_film).
  return worst / (theta_d - theta_inf);
}

TEST(FilmBoundary, SlabReachesTheSeriesResistanceProfile) {
  // Linear elements reproduce a linear field exactly on any mesh (patch test) and θ is uniform
  // on the film face, so the only errors are the transient left (~1e-15) and round-off of the
  // solves (~1e-13): 1e-8 of θ_D − θ∞ is far above both.
  for (const auto type :
       {mesh::CellType::Quad4, mesh::CellType::Tri3, mesh::CellType::Hex8, mesh::CellType::Tet4})
    for (const auto kind : {FilmKind::constant, FilmKind::table}) {
      const double e = slab_error(type, kind);
      std::printf("slab, %s, film h %s: max |θ − θ_exact| / (θ_D − θ∞) = %.3e\n", mesh::name(type),
                  kind == FilmKind::constant ? "constant" : "h(t)", e);
      EXPECT_LT(e, 1e-8) << mesh::name(type);
    }
}

TEST(FilmBoundary, SlabCutIntoSubdomainsReachesTheSameProfile) {
  // FETI (tolerance 1e-10 of the dual residual) in place of the factorisation: the film's
  // matrix is assembled per subdomain (constant h), and Newton's correction is preconditioned
  // by the FETI solve (h(t)).
  for (const auto type : {mesh::CellType::Quad4, mesh::CellType::Hex8})
    for (const auto kind : {FilmKind::constant, FilmKind::table}) {
      const double e = slab_error(type, kind, 2);
      std::printf("slab in 2 subdomains, %s, film h %s: %.3e\n", mesh::name(type),
                  kind == FilmKind::constant ? "constant" : "h(t)", e);
      EXPECT_LT(e, 1e-8) << mesh::name(type);
    }
}

// ---- 3. Thin plate: heat flux in, radiation out --------------------------------------------

double plate_error(mesh::CellType type) {
  const double d = 0.002, q = 1.0e4, eps = 0.8, theta_inf = 300.0;
  const int dim = mesh::dimension(type);
  auto p = heat_only(dim, {d, 0.01, 0.01}, {4, 2, 2}, 1e8, 4);
  auto& m = p.bodies[0].mesh;
  if (type == mesh::CellType::Tri3 || type == mesh::CellType::Tet4)
    m = dim == 2 ? split_quads(m) : split_hexes(m);
  p.bodies[0].initial_temperature = theta_inf;
  physics::BoundaryCondition in;
  in.where = "xmin";
  in.heat_flux = core::TimeTable(q);
  physics::BoundaryCondition out;
  out.where = "xmax";
  out.radiation = physics::Radiation{core::TimeTable(eps), core::TimeTable(theta_inf)};
  p.boundaries.push_back(in);
  p.boundaries.push_back(out);
  physics::Simulation sim(p);
  Quiet quiet;
  const auto status = sim.run(quiet);
  EXPECT_TRUE(status.completed) << status.message;
  const double kappa = p.bodies[0].material.thermal_conductivity;
  const double surface =
      std::pow(q / (eps * physics::stefan_boltzmann) + std::pow(theta_inf, 4), 0.25);
  std::printf("  %s: %ld Newton corrections, %ld CG iterations in %d steps\n", mesh::name(type),
              sim.total_newton_iterations(), sim.total_newton_inner_iterations(), sim.step());
  const auto theta = sim.state(0).theta.to_std();
  double worst = 0;
  for (int a = 0; a < m.n_nodes(); ++a) {
    const double exact = surface + q * (d - m.point(a)[0]) / kappa;
    worst = std::max(worst, std::abs(theta[a] - exact) / exact);
  }
  return worst;
}

TEST(RadiationBoundary, ThinPlateReachesTheRadiativeEquilibrium) {
  // Steady 1D conduction is linear in x (exact for linear elements) and θ is uniform on the
  // radiating face, where the nodal rule integrates θ⁴ exactly; Newton stops at 1e-10 of the
  // residual's scale. Four steps of τ = 1e8 s leave no transient: 1e-6 bounds what remains.
  for (const auto type :
       {mesh::CellType::Quad4, mesh::CellType::Tri3, mesh::CellType::Hex8, mesh::CellType::Tet4}) {
    const double e = plate_error(type);
    std::printf("radiating plate, %s: max relative error %.3e\n", mesh::name(type), e);
    EXPECT_LT(e, 1e-6) << mesh::name(type);
  }
}

/// The 2D plate of plate_error (Quad4): 1e4 W/m² into xmin, radiation (ε = 0.8, 300 K) out of
/// xmax, `steps` steps of τ = 1e8 s.
physics::Problem radiating_plate_2d(int steps) {
  auto p = heat_only(2, {0.002, 0.01, 0}, {4, 2, 1}, 1e8, steps);
  physics::BoundaryCondition in;
  in.where = "xmin";
  in.heat_flux = core::TimeTable(1.0e4);
  physics::BoundaryCondition out;
  out.where = "xmax";
  out.radiation = physics::Radiation{core::TimeTable(0.8), core::TimeTable(300.0)};
  p.boundaries.push_back(in);
  p.boundaries.push_back(out);
  return p;
}

TEST(RadiationBoundary, EachCgIterationOfANewtonCorrectionSolvesWithAOnce) {
  // The radiating plate's first heat step, from 300 K, with the solves with A counted: CG on
  // (A + N')δ = −r preconditioned by A⁻¹ needs one solve for its first direction and one for
  // each later direction, so a correction of k iterations costs k solves — not k + 1: the
  // last iteration's residual meets the tolerance before a preconditioner would make a
  // direction no one uses (on the pin-on-plate, one interface solve of three per heat step).
  auto p = radiating_plate_2d(1);
  p.bodies[0].initial_temperature = 300.0;
  const physics::BodySystem sys(p, 0);
  const physics::BodyField field(p, sys);
  int solves = 0;
  physics::HeatOperator op;
  op.systems = {&sys};
  op.apply = [&](const auto& x, const auto& y) { field.a_theta.mult(*x[0], *y[0]); };
  op.solve = [&](const auto& r, const auto& z) {
    ++solves;
    field.heat->solve(*r[0], *z[0]);
  };
  // b: the flux into xmin (the steady state is the radiative equilibrium, ~1 040 K: from 300 K
  // Newton takes several corrections)
  core::Vector b(sys.n_theta()), theta(sys.n_theta());
  const double t = p.time.step;
  sys.thermal_load(t, b);
  theta.fill(300.0);
  const auto o = physics::solve_boundary_heat(op, t, {&b}, {&theta}, 1e-10, 20);
  ASSERT_TRUE(o.converged);
  ASSERT_GT(o.iterations, 1);  // several corrections, each with its own CG
  EXPECT_EQ(solves, o.inner_iterations);
}

TEST(RadiationBoundary, NewtonFailureIsReportedWithStepIterationAndResidual) {
  auto p = radiating_plate_2d(2);
  p.solver.max_newton_iterations = 1;
  physics::Simulation sim(p);
  Quiet quiet;
  const auto status = sim.run(quiet);
  EXPECT_FALSE(status.completed);
  EXPECT_EQ(status.exit_code, 1);
  EXPECT_NE(status.message.find("Newton"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("step 1"), std::string::npos) << status.message;
  EXPECT_NE(status.message.find("residual"), std::string::npos) << status.message;
}

// ---- 4. The energy ledger ------------------------------------------------------------------

TEST(FilmBoundary, EnergyLedgerCloses) {
  // No Dirichlet temperature, no source, no flux: 1ᵀ of the backward Euler step is
  // 1ᵀM_θ(θ^{k+1} − θ^k) = −τ(Σ h∫(θ − θ∞) + Σ∫εσ(θ⁴ − θ∞⁴)), 1ᵀK_θ = 0, so the change of
  // thermal_energy (= 1ᵀM_θ(θ − θ₀)) equals −(heat_film + heat_radiation) up to the solves:
  // round-off for the constant film (factorised), Newton's 1e-10 with radiation and h(t).
  for (const int dim : {2, 3}) {
    for (const bool radiation : {false, true}) {
      auto p = heat_only(dim, {0.05, 0.03, 0.02}, {5, 3, 2}, 2.0, 40);
      p.bodies[0].initial_temperature = 500.0;
      p.boundaries.push_back(film("xmax", 40.0, 300.0));
      p.boundaries.push_back(film("ymax", core::TimeTable({0.0, 80.0}, {10.0, 100.0}), 280.0));
      if (radiation) {
        physics::BoundaryCondition r;
        r.where = "ymin";
        r.radiation = physics::Radiation{core::TimeTable(0.9), core::TimeTable(250.0)};
        p.boundaries.push_back(r);
      }
      physics::Simulation sim(p);
      EnergyTrace trace;
      const auto status = sim.run(trace);
      ASSERT_TRUE(status.completed) << status.message;
      double worst = 0;
      const double lost = trace.film.back() + trace.radiation.back();
      for (size_t k = 0; k < trace.time.size(); ++k)
        worst = std::max(worst, std::abs(trace.energy[k] - trace.energy[0] + trace.film[k] +
                                         trace.radiation[k]));
      std::printf(
          "dim %d%s: heat lost %.6e J (film %.6e, radiation %.6e), ledger error %.3e "
          "(relative %.3e)\n",
          dim, radiation ? " with radiation" : "", lost, trace.film.back(), trace.radiation.back(),
          worst, worst / lost);
      EXPECT_GT(trace.film.back(), 0.0);
      EXPECT_EQ(trace.radiation.back() > 0.0, radiation);
      EXPECT_LT(worst, 1e-9 * std::abs(lost));
    }
  }
}

// ---- 5. A contact pair cooled or heated through a film or radiation ------------------------

/// thermal_contact_test's series conduction (4C's tsi_contact3D_conduction): two unit blocks
/// pressed to λ_n = 30, β_C = 5, so the interface conductance is h_c = 150 W/(m²K); the lower
/// block's bottom held at θ_low, the upper block's top exchanging with the surroundings by a
/// film (constant h or h(t)) or by radiation instead of a prescribed temperature.
enum class Exchange { film, film_table, radiation };

double contact_pair_error(Exchange kind) {
  const double theta0 = 293.15, theta_low = theta0 + 20, kappa = 52, push = 0.015;
  const double h_film = 100, ambient = kind == Exchange::radiation ? 600.0 : theta0 + 40;
  const double eps = 0.9;
  // ρc_pL²/κ = 0.02 s against τ = 1e4 s: three steps reach the steady state to round-off.
  auto p = pressed_conduction_blocks(theta0, kappa, push, 4);
  p.boundaries.push_back(temperature_bc(0, "zmin", theta_low));
  physics::BoundaryCondition top;
  top.body = 1;
  top.where = "zmax";
  if (kind == Exchange::radiation)
    top.radiation = physics::Radiation{core::TimeTable(eps), core::TimeTable(ambient)};
  else
    top.film =
        physics::Film{kind == Exchange::film ? core::TimeTable(h_film)
                                             : core::TimeTable({0.0, 1.0}, {0.5 * h_film, h_film}),
                      core::TimeTable(ambient)};
  p.boundaries.push_back(top);
  auto c = contact_pair(0, "zmax", 1, "zmin");
  c.conductance_slave = c.conductance_master = 10.0;
  p.contacts = {c};
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  Quiet quiet;
  const auto status = sim.run(quiet);
  EXPECT_TRUE(status.completed) << status.message;
  const double h_c =
      sim.interface_laws().beta_c(kAnyTheta) * 4000 * push / 2.0;  // β_C λ_n, λ_n = E δ/(2L) = 30
  EXPECT_NEAR(h_c, 150.0, 1e-12);
  const double r_bodies = 2 / kappa + 1 / h_c;  // lower, interface, upper
  // q: the heat flux from the surroundings down to the lower block's bottom [W/m²].
  double q = 0;
  if (kind == Exchange::radiation) {
    // q = εσ(θ∞⁴ − θ_top⁴) with θ_top = θ_low + q r_bodies: a monotone scalar equation,
    // solved by bisection to round-off.
    double lo = 0, hi = eps * physics::stefan_boltzmann * std::pow(ambient, 4);
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      const double top_t = theta_low + mid * r_bodies;
      (eps * physics::stefan_boltzmann * (std::pow(ambient, 4) - std::pow(top_t, 4)) > mid ? lo
                                                                                           : hi) =
          mid;
    }
    q = 0.5 * (lo + hi);
  } else {
    q = (ambient - theta_low) / (r_bodies + 1 / h_film);
  }
  const double th_slave = theta_low + q / kappa, th_master = th_slave + q / h_c;
  double worst = 0;
  for (int b = 0; b < 2; ++b) {
    const auto theta = sim.state(b).theta.to_std();
    const auto& m = p.bodies[b].mesh;
    for (int a = 0; a < m.n_nodes(); ++a) {
      const double z = m.point(a)[2];
      const double exact =
          b == 0 ? theta_low + q * (z + 0.5) / kappa : th_master + q * (z - 0.5) / kappa;
      worst = std::max(worst, std::abs(theta[a] - exact));
    }
  }
  std::printf("contact pair, %s: q = %.6f W/m², %ld Newton corrections\n",
              kind == Exchange::film         ? "film"
              : kind == Exchange::film_table ? "film h(t)"
                                             : "radiation",
              q, sim.total_newton_iterations());
  return worst / std::abs(th_master + q * 0.5 / kappa - theta_low);
}

TEST(FilmBoundary, ContactPairWithAFilmOrRadiationReachesTheSeriesProfile) {
  // As thermal_contact_test's series conduction: linear elements and a uniform pressure
  // reproduce the piecewise linear profile; the QP and coupling tolerances (1e-12) and the
  // solves' round-off remain, and Newton's 1e-10 on the radiation and h(t) paths: 1e-8 of
  // the temperature difference across the stack bounds them.
  for (const auto kind : {Exchange::film, Exchange::film_table, Exchange::radiation}) {
    const double e = contact_pair_error(kind);
    std::printf("  max |θ − θ_exact| / (θ_top − θ_low) = %.3e\n", e);
    EXPECT_LT(e, 1e-8);
  }
}

}  // namespace
}  // namespace tc::test
