// E(θ) and ν(θ) as tables in the body's temperature (physics::BodySystem::update_moduli,
// Simulation::refresh_moduli), against closed forms and the refactorisation policy:
//  1. a free bar heated uniformly with E(θ), ν(θ), α(θ): no stress, the strain ∫_{θ₀}^{θ} α dθ,
//     whatever E and ν are, but only if K_u and K_uθ carry the same C(θ);
//  2. a bar clamped at both ends heated uniformly (uniaxial stress): σ_xx = −E(θ)ε_th(θ), the
//     lateral strain (1 + ν(θ))ε_th(θ);
//  3. the refactorisations follow [solver] modulus_tolerance: 0 → at every step whose starting
//     temperature moved, a huge tolerance → never, and then the history of the numbers
//     E(θ_initial), ν(θ_initial) bit for bit;
//  4. a flat or one-point table of E, ν is the number: the same history bit for bit, through
//     the case reader.
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

constexpr double theta0 = 293.15;
// Steel-like laws (EN 1993-1-2's reduction of E at 200 °C, ν rising a little): strictly
// monotone, so every change of a cell's temperature changes its moduli.
const core::TemperatureTable kYoung({293.15, 473.15, 673.15}, {2.0e11, 1.8e11, 1.4e11});
const core::TemperatureTable kPoisson({293.15, 673.15}, {0.28, 0.32});
const core::TemperatureTable kAlpha({293.15, 500.0, 800.0}, {1.2e-5, 1.4e-5, 1.5e-5});

/// `mat` with E(θ), ν(θ), α(θ) and the numbers at θ_numbers, as the case reader sets them at
/// the body's initial temperature.
fem::Material with_moduli(double theta_numbers) {
  auto mat = steel();
  mat.laws.young_modulus = kYoung;
  mat.laws.poisson_ratio = kPoisson;
  mat.laws.thermal_expansion = kAlpha;
  mat.evaluate_laws_at(theta_numbers);
  return mat;
}

/// ∫_{θ₀}^{θ₁} α dθ by hand (trapezoids on the table's segments, constant below it), for
/// θ₁ in [θ₀, 800 K].
double expansion_by_hand(double theta1) {
  if (theta1 <= 500.0) {
    const double a1 = 1.2e-5 + (theta1 - 293.15) / (500.0 - 293.15) * 0.2e-5;
    return 0.5 * (1.2e-5 + a1) * (theta1 - theta0);
  }
  const double a1 = 1.4e-5 + (theta1 - 500.0) / 300.0 * 0.1e-5;
  return 0.5 * (1.2e-5 + 1.4e-5) * (500.0 - theta0) + 0.5 * (1.4e-5 + a1) * (theta1 - 500.0);
}

/// E, ν of a piecewise-linear table by hand.
double linear(double x0, double v0, double x1, double v1, double x) {
  return v0 + (x - x0) / (x1 - x0) * (v1 - v0);
}

/// A 3D bar [0, L] × [0, 0.02] × [0, 0.03] at the uniform temperature θ₁, quasistatic, its
/// matrices first assembled with the moduli at θ₀ (the numbers of with_moduli(θ₀)): the first
/// step's start must find θ₁ and re-assemble. Rollers on ymin and zmin; xmin always held.
physics::Problem heated_bar(double theta1, bool clamped) {
  constexpr double length = 0.2;
  auto p = box_problem(3, {length, 0.02, 0.03}, {5, 2, 2}, with_moduli(theta0),
                       physics::Scheme::quasistatic, 1.0, 1);
  p.physics.reference_temperature = theta0;
  p.physics.thermoelastic_heating = false;
  p.solver.modulus_tolerance = 0;
  p.bodies[0].initial_temperature = theta1;
  p.boundaries.push_back(hold("xmin", {0}));
  p.boundaries.push_back(hold("ymin", {1}));
  p.boundaries.push_back(hold("zmin", {2}));
  if (clamped) p.boundaries.push_back(hold("xmax", {0}));
  return p;
}

// ---- 1. Free bar --------------------------------------------------------------------------
// Free expansion u = ε_th x is linear, held exactly by the elements, and stress-free for any
// C: K_u u = K_uθ ϑ_α holds only when K_uθ's β = (3λ + 2μ)α has the λ, μ of K_u (had K_uθ kept
// E(θ₀) while K_u took E(θ₁), u would be scaled by E(θ₀)/E(θ₁), 1.2 % off here). Round-off
// only: 1e-10 relative.
TEST(MaterialModuli, FreeBarHeatedUniformlyIsStressFreeWithTheStrainOfAlpha) {
  for (const double theta1 : {450.0, 650.0}) {
    const double strain = expansion_by_hand(theta1);
    const auto p = heated_bar(theta1, false);
    physics::Simulation sim(p);
    Quiet quiet;
    const auto status = sim.run(quiet);
    ASSERT_TRUE(status.completed) << status.message;
    EXPECT_EQ(sim.mechanical_refactorisations(), 1);  // θ₀'s moduli → θ₁'s at step 1
    const auto u = sim.state(0).u.to_std();
    const auto& mesh = p.bodies[0].mesh;
    double worst = 0;
    for (int a = 0; a < mesh.n_nodes(); ++a)
      for (int k = 0; k < 3; ++k) {
        const double x = mesh.point(a)[static_cast<size_t>(k)];
        worst = std::max(worst, std::abs(u[static_cast<size_t>(3 * a + k)] - strain * x));
      }
    std::printf("free bar at %.0f K: worst |u − ε_th x| / (ε_th L) = %.3e\n", theta1,
                worst / (strain * 0.2));
    EXPECT_LT(worst, 1e-10 * strain * 0.2);
  }
}

// ---- 2. Clamped bar -----------------------------------------------------------------------
// u_x = 0 at both ends, lateral faces free (rollers on ymin, zmin only): the uniaxial state
// ε_xx = 0, σ_yy = σ_zz = 0, so σ_xx = −E(θ₁)ε_th and ε_yy = ε_zz = (1 + ν(θ₁))ε_th, uniform
// and linear in the coordinates (held exactly by the elements). The reaction on xmax is
// σ_xx·A (A = 0.02 × 0.03); u_y = (1 + ν)ε_th y. Tolerance 0 refactorises at θ₁, so both hold
// to round-off of the solve: 1e-8 relative (the brief's bound; measured ~1e-13).
TEST(MaterialModuli, ClampedBarHeatedUniformlyHasTheStressOfTheModulusAtItsTemperature) {
  for (const double theta1 : {450.0, 650.0}) {
    const double strain = expansion_by_hand(theta1);
    const double e = theta1 <= 473.15 ? linear(293.15, 2.0e11, 473.15, 1.8e11, theta1)
                                      : linear(473.15, 1.8e11, 673.15, 1.4e11, theta1);
    const double nu = linear(293.15, 0.28, 673.15, 0.32, theta1);
    const double area = 0.02 * 0.03;
    const auto p = heated_bar(theta1, true);
    physics::Simulation sim(p);
    Quiet quiet;
    const auto status = sim.run(quiet);
    ASSERT_TRUE(status.completed) << status.message;
    const double force = -e * strain * area;  // σ_xx A, the force of the support on the bar
    const double reaction = sim.history("reaction_block_xmax_x");
    const auto u = sim.state(0).u.to_std();
    const auto& mesh = p.bodies[0].mesh;
    double worst = 0;
    for (int a = 0; a < mesh.n_nodes(); ++a) {
      const auto& x = mesh.point(a);
      worst = std::max({worst, std::abs(u[static_cast<size_t>(3 * a)]),
                        std::abs(u[static_cast<size_t>(3 * a + 1)] - (1 + nu) * strain * x[1]),
                        std::abs(u[static_cast<size_t>(3 * a + 2)] - (1 + nu) * strain * x[2])});
    }
    std::printf(
        "clamped bar at %.0f K: E = %.6e, reaction %.12e against −Eε_thA = %.12e "
        "(relative %.2e); worst |u − u_exact| / (ε_th·0.03) = %.2e\n",
        theta1, e, reaction, force, std::abs(reaction - force) / std::abs(force),
        worst / (strain * 0.03));
    // The support pushes the bar back: minus σ_xx A on the xmax face's outward normal +x.
    EXPECT_NEAR(reaction, force, 1e-8 * std::abs(force));
    EXPECT_LT(worst, 1e-8 * strain * 0.03);
  }
}

// ---- 3. The refactorisations follow the tolerance ----------------------------------------
// A 2D block heated through xmax (θ = 500 K there, backward Euler), quasistatic mechanics,
// 6 steps: the temperature moves at every step. Tolerance 0: one refactorisation per step
// whose starting temperature differs from the last one factorised (counted here from the
// nodal θ, not by the solver's own test); a huge tolerance: none, and the run is the one with
// E, ν the numbers at the initial temperature, to the bit (the same assembly, never redone).
physics::Problem heated_block(double tolerance, bool tables) {
  auto mat = tables ? with_moduli(theta0) : steel();
  if (!tables) {
    mat.young_modulus = 2.0e11;
    mat.poisson_ratio = 0.28;
  }
  mat.thermal_expansion = 1.2e-5;
  mat.laws.thermal_expansion = {};
  auto p = box_problem(2, {0.02, 0.01}, {8, 4, 1}, mat, physics::Scheme::quasistatic, 0.5, 6);
  p.physics.reference_temperature = theta0;
  p.solver.modulus_tolerance = tolerance;
  p.boundaries.push_back(hold("xmin", {0, 1}));
  auto hot = temperature_bc(0, "xmax", 500.0);
  p.boundaries.push_back(hot);
  return p;
}

int refactorisations(double tolerance, int& moved, std::vector<std::vector<double>>* rows) {
  const auto p = heated_block(tolerance, true);
  physics::Simulation sim(p);
  moved = 0;
  std::vector<double> last = std::vector<double>(static_cast<size_t>(sim.state(0).theta.size()),
                                                 theta0);  // the factorised (initial) one
  for (int s = 0; s < 6; ++s) {
    const auto now = sim.state(0).theta.to_std();
    if (now != last) ++moved, last = now;
    sim.advance();
    if (rows) rows->push_back(sim.history_row());
  }
  return sim.mechanical_refactorisations();
}

TEST(MaterialModuli, RefactorisationsFollowTheTolerance) {
  int moved = 0;
  const int every = refactorisations(0.0, moved, nullptr);
  std::printf("tolerance 0: %d refactorisations, %d step starts with a new θ\n", every, moved);
  EXPECT_EQ(every, moved);
  EXPECT_GE(moved, 5);  // the heating went on through the run
  const int some = refactorisations(1e-2, moved, nullptr);
  std::printf("tolerance 1e-2: %d refactorisations\n", some);
  EXPECT_GE(some, 1);
  EXPECT_LT(some, every);
  std::vector<std::vector<double>> lagged, constant;
  EXPECT_EQ(refactorisations(1e300, moved, &lagged), 0);
  {
    physics::Simulation sim(heated_block(0.0, false));
    for (int s = 0; s < 6; ++s) {
      sim.advance();
      constant.push_back(sim.history_row());
    }
    const auto& columns = sim.history_columns();
    const auto wall = std::find(columns.begin(), columns.end(), "wall_seconds") - columns.begin();
    for (size_t s = 0; s < constant.size(); ++s)
      for (size_t c = 0; c < columns.size(); ++c) {
        if (static_cast<std::ptrdiff_t>(c) == wall) continue;
        EXPECT_EQ(lagged[s][c], constant[s][c]) << "step " << s + 1 << ", " << columns[c];
      }
  }
}

// ---- 4. A flat table is the number --------------------------------------------------------
std::string moduli_case(const std::string& e, const std::string& nu) {
  return "dimension = 2\n"
         "[time]\nscheme = \"dynamic\"\nstep = 1e-3\nend = 4e-3\n"
         "[materials.steel]\ndensity = 7850.0\nyoung_modulus = " +
         e + "\npoisson_ratio = " + nu +
         "\nthermal_expansion = 1.2e-5\nspecific_heat = 450.0\nthermal_conductivity = 50.0\n"
         "[[bodies]]\nname = \"b\"\nmaterial = \"steel\"\ninitial_temperature = 320.0\n"
         "mesh = { box = { min = [0.0, 0.0], max = [0.02, 0.01], cells = [4, 2] } }\n"
         "[[boundary]]\nbody = \"b\"\nwhere = \"xmin\"\ndisplacement = [0.0, 0.0]\n"
         "temperature = 293.15\n"
         "[[boundary]]\nbody = \"b\"\nwhere = \"xmax\"\nheat_flux = 1e6\n";
}

TEST(MaterialModuli, AFlatOrOnePointTableOfTheModuliGivesTheHistoryOfTheNumbers) {
  const std::vector<std::array<std::string, 2>> forms = {
      {"2.0e11", "0.3"},
      {"{ temperature = [400.0], value = [2.0e11] }", "{ temperature = [300.0], value = [0.3] }"},
      {"{ temperature = [300.0, 400.0, 900.0], value = [2.0e11, 2.0e11, 2.0e11] }",
       "{ temperature = [250.0, 700.0], value = [0.3, 0.3] }"}};
  const auto dir =
      std::filesystem::temp_directory_path() / ("tc_material_moduli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::vector<std::vector<std::vector<double>>> histories;
  std::vector<std::string> columns;
  for (size_t f = 0; f < forms.size(); ++f) {
    const auto file = dir / ("case" + std::to_string(f) + ".toml");
    std::ofstream(file) << moduli_case(forms[f][0], forms[f][1]);
    const auto p = io::read_case(file);
    ASSERT_FALSE(p.bodies[0].material.nonlinear_moduli());
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
  const auto col = std::find(columns.begin(), columns.end(), "strain_energy") - columns.begin();
  EXPECT_GT(histories[0].back()[static_cast<size_t>(col)], 0.0);  // the block moved
}

}  // namespace
}  // namespace tc::test
