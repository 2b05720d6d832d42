// Temperature-dependent materials (κ(θ), c_p(θ), α(θ) as tables in the body's temperature;
// fem::NonlinearHeat, physics::solve_nonlinear_heat), each against a closed form or a
// conservation law:
//  1. steady conduction through a slab with κ(θ) = κ₀(1 + bθ): the Kirchhoff transform
//     Φ(θ) = ∫κ dθ is linear in x, and linear elements of θ reproduce it at the nodes (below);
//  2. the energy ledger with c_p(θ) and κ(θ): thermal_energy = ∫ρ∫c_p dθ dx changes by the heat
//     that came in, to Newton's tolerance;
//  3. a free bar heated uniformly with α(θ): the strain is ∫_{θ₀}^{θ} α dθ;
//  4. a constant written as a number, a one-point table or a flat table: the same history,
//     bit for bit, through the case reader.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "support/problems.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

struct Quiet : physics::Observer {};

/// `mat` with its laws and their numbers at θ, as the case reader sets them.
fem::Material with_laws(fem::Material mat, fem::MaterialLaws laws, double theta) {
  mat.laws = std::move(laws);
  mat.evaluate_laws_at(theta);
  return mat;
}

// ---- 1. Steady slab, κ(θ) = κ₀(1 + bθ) -----------------------------------------------------
// θ(0) = θ₁, θ(L) = θ₂, insulated sides. −(κ(θ)θ')' = 0 gives Φ(θ(x)) = Φ(θ₁) + x/L (Φ(θ₂) −
// Φ(θ₁)) with Φ(θ) = κ₀(θ + bθ²/2), so θ(x) = (√(1 + 2bΦ(θ(x))/κ₀) − 1)/b.
// The discrete solution is exact at the nodes: θ_h is linear on each cell and varies only
// along x, so κ(θ_h) is linear along the cell and the 2-point Gauss rule integrates the cell's
// flux exactly, q_e = (θ_{i+1} − θ_i)/h · κ(θ̄_e) = (Φ(θ_{i+1}) − Φ(θ_i))/h (the secant of the
// quadratic Φ is its slope at the midpoint). Equal fluxes in every cell then make Φ(θ_i) linear
// in x_i: the closed form's nodal values, whatever the number of cells.
TEST(MaterialLaws, SteadySlabWithLinearConductivityIsTheKirchhoffClosedForm) {
  constexpr double kappa0 = 20.0, b = 2e-3, theta1 = 300.0, theta2 = 500.0, length = 0.1;
  // κ₀(1 + bθ) is linear: a two-point table over [250, 550] K is that law exactly.
  const core::TemperatureTable kappa({250.0, 550.0},
                                     {kappa0 * (1 + b * 250.0), kappa0 * (1 + b * 550.0)});
  auto mat = steel();
  mat.thermal_expansion = 0;
  mat = with_laws(mat, {kappa, {}, {}, {}, {}}, theta1);
  // τ = 1e6 s against the slab's diffusion time ρc_pL²/κ ≈ 1e3 s: each backward-Euler step
  // damps the transient by 1 + τκπ²/(ρc_pL²) ≈ 1e4, so four steps leave ~1e-14 of it.
  auto p = box_problem(2, {length, 0.01, 0}, {10, 1, 1}, mat, physics::Scheme::quasistatic, 1e6, 4);
  p.bodies[0].initial_temperature = theta1;
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  p.boundaries.push_back(hold("xmin", {0, 1}));
  p.boundaries.push_back(temperature_bc(0, "xmin", theta1));
  p.boundaries.push_back(temperature_bc(0, "xmax", theta2));
  // Newton to 1e-12 of the equation's scale (‖Aθ‖ ~ θκ/h²; round-off stalls it near 1e-13):
  // the nodal error it leaves is ~1e-12 θ₂ times the conditioning, far below the 1e-8 asserted.
  p.solver.newton_tolerance = 1e-12;
  physics::Simulation sim(p);
  Quiet quiet;
  const auto status = sim.run(quiet);
  ASSERT_TRUE(status.completed) << status.message;
  const auto phi = [&](double t) { return kappa0 * (t + 0.5 * b * t * t); };
  const auto exact = [&](double x) {
    const double f = phi(theta1) + x / length * (phi(theta2) - phi(theta1));
    return (std::sqrt(1 + 2 * b * f / kappa0) - 1) / b;
  };
  const auto theta = sim.state(0).theta.to_std();
  const auto& mesh = p.bodies[0].mesh;
  double worst = 0;
  for (int a = 0; a < mesh.n_nodes(); ++a)
    worst = std::max(worst, std::abs(theta[static_cast<size_t>(a)] - exact(mesh.point(a)[0])));
  const double steps = 4;
  std::printf(
      "slab: max nodal error %.3e K (relative to θ₂ − θ₁: %.3e); Newton %.1f corrections "
      "and %.1f GMRES iterations per step\n",
      worst, worst / (theta2 - theta1), sim.total_newton_iterations() / steps,
      static_cast<double>(sim.total_newton_inner_iterations()) / steps);
  // The linear profile's midpoint is 400 K; the closed form's is 407.2 K: the law matters.
  EXPECT_GT(exact(0.5 * length) - 400.0, 5.0);
  EXPECT_LT(worst / (theta2 - theta1), 1e-8);
}

// ---- 2. The energy ledger with c_p(θ) -------------------------------------------------------
// A block heated by a source r and a flux q on xmax, no Dirichlet temperature: Σ_a of the
// step's residual is (ΣH(θ^{k+1}) − ΣH(θ^k))/τ − Σ_a∫rN_a − Σ_a∫qN_a, the conduction summing
// to zero (Σ_a∇N_a = 0), so thermal_energy = Σ_a H_a = ∫ρ∫_{θ₀}^{θ}c_p dθ dx grows by
// (rV + qA)t to Newton's tolerance. c_p doubles and κ halves over the run's range (the flux
// makes a gradient, so κ(θ) matters), so the step is far from linear.
TEST(MaterialLaws, EnergyLedgerClosesWithTheEnthalpy) {
  constexpr double r = 4e8;  // W/m³: ~10 K per 0.1 s step at ρc_p ≈ 3–6e6 J/(m³K)
  const core::TemperatureTable cp({300.0, 400.0, 600.0}, {400.0, 600.0, 800.0});
  const core::TemperatureTable kappa({300.0, 700.0}, {60.0, 30.0});
  for (const bool lumped : {false, true}) {
    auto mat = steel();
    mat.thermal_expansion = 0;
    mat = with_laws(mat, {kappa, cp, {}, {}, {}}, 293.15);
    auto p =
        box_problem(3, {0.02, 0.01, 0.01}, {4, 2, 2}, mat, physics::Scheme::quasistatic, 0.1, 40);
    p.physics.thermal_expansion = false;
    p.physics.thermoelastic_heating = false;
    p.physics.lumped_heat_capacity = lumped;
    p.boundaries.push_back(hold("xmin", {0, 1, 2}));
    p.bodies[0].heat_source = core::TimeTable(r);
    physics::BoundaryCondition flux;
    flux.where = "xmax";
    flux.heat_flux = core::TimeTable(5e5);  // W/m²
    p.boundaries.push_back(flux);
    physics::Simulation sim(p);
    struct Trace : physics::Observer {
      std::vector<double> time, energy, max_theta;
      void step(const physics::Simulation& s) override {
        time.push_back(s.time());
        energy.push_back(s.history("thermal_energy"));
        max_theta.push_back(s.history("max_temperature"));
      }
    } trace;
    const auto status = sim.run(trace);
    ASSERT_TRUE(status.completed) << status.message;
    const double volume = 0.02 * 0.01 * 0.01, area = 0.01 * 0.01;
    const double power = r * volume + 5e5 * area;  // thermal_energy(0) = 0: the block at θ₀
    double worst = 0;
    for (size_t k = 0; k < trace.time.size(); ++k)
      worst = std::max(worst, std::abs(trace.energy[k] - power * trace.time[k]));
    const double heat = power * trace.time.back();
    std::printf(
        "ledger (%s): heat in %.6e J, max θ %.1f K, worst |ΔE − Q| %.3e J (relative "
        "%.3e); Newton %ld corrections, %ld GMRES iterations in %zu steps\n",
        lumped ? "lumped" : "consistent", heat, trace.max_theta.back(), worst, worst / heat,
        sim.total_newton_iterations(), sim.total_newton_inner_iterations(), trace.time.size());
    EXPECT_GT(trace.max_theta.back(), 600.0);  // c_p's whole table is crossed
    // Newton stops at 1e-10 of ‖Aθ‖ (θ ~ 500 K absolute), but converges quadratically: the
    // last correction leaves a residual far below that, and its sum is what the ledger sees.
    EXPECT_LT(worst, 1e-8 * heat);
  }
}

// ---- 3. A free bar heated uniformly with α(θ) -----------------------------------------------
// A 3D bar on rollers (xmin, ymin, zmin each hold their normal component) at a uniform θ₁: it
// expands freely, stress-free, u_x(L) = L ε_th with ε_th = ∫_{θ₀}^{θ₁} α dθ. The integral by
// hand below (trapezoids of the table's segments), not by core::TemperatureTable::integral.
// u = ε_th x is linear, so the elements hold it exactly: round-off only (~1e-16 relative
// per operation, a few hundred operations in the solve).
TEST(MaterialLaws, FreeBarHeatedUniformlyStrainsByTheIntegralOfAlpha) {
  constexpr double theta0 = 293.15, length = 0.2;
  // α(θ): 1.2e-5 at 293.15 K, 1.4e-5 at 500 K, 1.5e-5 at 800 K (tangent coefficient).
  const core::TemperatureTable alpha({293.15, 500.0, 800.0}, {1.2e-5, 1.4e-5, 1.5e-5});
  for (const double theta1 : {450.0, 650.0, 250.0}) {
    double strain = 0;  // ∫_{θ₀}^{θ₁} α dθ by hand
    if (theta1 <= 500.0) {
      const double a1 = 1.2e-5 + (theta1 - 293.15) / (500.0 - 293.15) * 0.2e-5;
      strain = theta1 >= theta0 ? 0.5 * (1.2e-5 + a1) * (theta1 - theta0)
                                : 1.2e-5 * (theta1 - theta0);  // constant below the table
    } else {
      const double a1 = 1.4e-5 + (theta1 - 500.0) / 300.0 * 0.1e-5;
      strain = 0.5 * (1.2e-5 + 1.4e-5) * (500.0 - theta0) + 0.5 * (1.4e-5 + a1) * (theta1 - 500.0);
    }
    auto mat = with_laws(steel(), {{}, {}, alpha, {}, {}}, theta1);
    auto p =
        box_problem(3, {length, 0.02, 0.03}, {5, 2, 2}, mat, physics::Scheme::quasistatic, 1.0, 1);
    p.physics.reference_temperature = theta0;
    p.physics.thermoelastic_heating = false;
    p.bodies[0].initial_temperature = theta1;
    p.boundaries.push_back(hold("xmin", {0}));
    p.boundaries.push_back(hold("ymin", {1}));
    p.boundaries.push_back(hold("zmin", {2}));
    physics::Simulation sim(p);
    Quiet quiet;
    const auto status = sim.run(quiet);
    ASSERT_TRUE(status.completed) << status.message;
    const auto u = sim.state(0).u.to_std();
    const auto& mesh = p.bodies[0].mesh;
    double worst = 0;
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.point(a)[static_cast<size_t>(k)];
        worst = std::max(worst, std::abs(u[static_cast<size_t>(3 * a + k)] - strain * x));
      }
    std::printf("free bar at %.0f K: ε_th = %.12e, worst |u − ε_th x| / (ε_th L) = %.3e\n", theta1,
                strain, worst / std::abs(strain * length));
    EXPECT_LT(worst, 1e-10 * std::abs(strain * length));
  }
}

// ---- 4. A constant as a number or a table: the same history ---------------------------------
// Through the case reader (the tables' checks and flattening included): a heated, thermoelastic
// block whose κ, c_p and α are numbers, one-point tables or flat tables runs the same steps bit
// for bit (wall_seconds aside): a constant law takes the constant-property path.
std::string material_case(const std::string& kappa, const std::string& cp,
                          const std::string& alpha) {
  return "dimension = 2\n"
         "[time]\nscheme = \"dynamic\"\nstep = 1e-3\nend = 4e-3\n"
         "[materials.steel]\ndensity = 7850.0\nyoung_modulus = 2.0e11\npoisson_ratio = 0.3\n"
         "thermal_expansion = " +
         alpha + "\nspecific_heat = " + cp + "\nthermal_conductivity = " + kappa +
         "\n"
         "[[bodies]]\nname = \"b\"\nmaterial = \"steel\"\ninitial_temperature = 320.0\n"
         "mesh = { box = { min = [0.0, 0.0], max = [0.02, 0.01], cells = [4, 2] } }\n"
         "[[boundary]]\nbody = \"b\"\nwhere = \"xmin\"\ndisplacement = [0.0, 0.0]\n"
         "temperature = 293.15\n"
         "[[boundary]]\nbody = \"b\"\nwhere = \"xmax\"\nheat_flux = 1e6\n";
}

TEST(MaterialLaws, AConstantAsANumberOrAOnePointOrAFlatTableGivesTheSameHistory) {
  const std::vector<std::array<std::string, 3>> forms = {
      {"50.0", "450.0", "1.2e-5"},
      {"{ temperature = [400.0], value = [50.0] }", "{ temperature = [300.0], value = [450.0] }",
       "{ temperature = [350.0], value = [1.2e-5] }"},
      {"{ temperature = [300.0, 400.0, 900.0], value = [50.0, 50.0, 50.0] }",
       "{ temperature = [250.0, 700.0], value = [450.0, 450.0] }",
       "{ temperature = [300.0, 310.0], value = [1.2e-5, 1.2e-5] }"}};
  const auto dir =
      std::filesystem::temp_directory_path() / ("tc_material_laws_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<std::vector<std::vector<double>>> histories;
  std::vector<std::string> columns;
  for (size_t f = 0; f < forms.size(); ++f) {
    const auto file = dir / ("case" + std::to_string(f) + ".toml");
    std::ofstream(file) << material_case(forms[f][0], forms[f][1], forms[f][2]);
    const auto p = io::read_case(file);
    ASSERT_FALSE(p.bodies[0].material.nonlinear_heat());
    ASSERT_FALSE(p.bodies[0].material.nonlinear_expansion());
    physics::Simulation sim(p);
    std::vector<std::vector<double>> rows;
    for (int s = 0; s < 4; ++s) {
      sim.advance();
      rows.push_back(sim.history_row());
    }
    columns = sim.history_columns();
    histories.push_back(std::move(rows));
  }
  std::filesystem::remove_all(dir);
  const auto wall = std::find(columns.begin(), columns.end(), "wall_seconds") - columns.begin();
  for (size_t f = 1; f < histories.size(); ++f)
    for (size_t s = 0; s < histories[0].size(); ++s)
      for (size_t c = 0; c < columns.size(); ++c) {
        if (static_cast<std::ptrdiff_t>(c) == wall) continue;
        EXPECT_EQ(histories[f][s][c], histories[0][s][c])
            << "form " << f << ", step " << s + 1 << ", column " << columns[c];
      }
  // The run was not trivial: heat came in and the block moved.
  const auto col = [&](const std::string& name) {
    return std::find(columns.begin(), columns.end(), name) - columns.begin();
  };
  EXPECT_GT(histories[0].back()[static_cast<size_t>(col("max_temperature"))], 320.0);
  EXPECT_GT(histories[0].back()[static_cast<size_t>(col("strain_energy"))], 0.0);
}

}  // namespace
}  // namespace tc::test
