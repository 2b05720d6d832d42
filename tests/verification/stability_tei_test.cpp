// The linear stability analysis (src/tc/stability) on configuration T of docs/theory.md,
// "Linear stability": a steel layer [0, W] × [−H, 0], W = π/m (half a wavelength), its sides
// symmetry planes (u_x = 0, adiabatic), its base held at u = 0, θ = θ₀, under a rigid adiabatic
// flat pressed into it and sliding at V with 𝔉 = 0.1. The half-period box holds the modes
// cos(n m x), n = 0, 1, 2, …; the half-plane's closed form (Burton, Nerlikar & Kilaparti 1973
// for a rigid non-conducting flat; derived again in docs/theory.md) gives for mode n
//   ℓ(ℓ + 1) = 2 V/(n V_cr),   b = κ (n m)² (ℓ² − 1),   V_cr = 2 k (1 − ν) m/(𝔉 E α),
// with the shear of friction left out (its correction to Re b is O((c𝔉)²) ≈ 8e-4). Each
// eigenvalue's mode is told by the cosine its surface temperature projects on.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <numbers>

#include "tc/io/case/case_reader.hpp"
#include "tc/stability/analysis.hpp"

namespace tc::test {
namespace {

namespace fs = std::filesystem;

constexpr double kE = 2e11, kNu = 0.3, kAlpha = 1.2e-5, kK = 50, kRho = 7850, kCp = 460;
constexpr double kFriction = 0.1, kWidth = 0.01, kDepth = 0.03;
constexpr double kM = std::numbers::pi / kWidth;
constexpr double kKappa = kK / (kRho * kCp);
const double kVcr = 2 * kK * (1 - kNu) * kM / (kFriction * kE * kAlpha);

/// The closed-form growth rate of mode n at speed v.
double closed_form(int n, double v) {
  const double r = v / (n * kVcr);
  const double l = (std::sqrt(1 + 8 * r) - 1) / 2;
  return kKappa * (n * kM) * (n * kM) * (l * l - 1);
}

std::string case_text(int nx, int ny, const std::string& normal_control) {
  return fmt::format(R"(dimension = 2
[time]
scheme = "quasistatic"
step = 0.01
end = 1.0
[physics]
thermoelastic_heating = false
[materials.steel]
density = {}
young_modulus = {}
poisson_ratio = {}
thermal_expansion = {}
specific_heat = {}
thermal_conductivity = {}
[[bodies]]
name = "layer"
material = "steel"
mesh = {{ box = {{ min = [0.0, {}], max = [{}, 0.0], cells = [{}, {}] }} }}
[[boundary]]
body = "layer"
where = "xmin"
displacement = [0.0, "free"]
[[boundary]]
body = "layer"
where = "xmax"
displacement = [0.0, "free"]
[[boundary]]
body = "layer"
where = "ymin"
displacement = [0.0, 0.0]
temperature = 293.15
[contact]
slave = {{ body = "layer", where = "ymax" }}
master = {{ rigid = "plane", point = [0.0, 0.0], normal = [0.0, -1.0], displacement = [{{ t = [0.0, 0.01, 1.0], value = [0.0, 0.0, 0.0907] }}, -1.0e-6] }}
friction = {}
[stability]
normal_control = "{}"
)",
                     kRho, kE, kNu, kAlpha, kCp, kK, -kDepth, kWidth, nx, ny, kFriction,
                     normal_control);
}

physics::Problem configuration_t(int nx, int ny, const std::vector<double>& speeds, int count,
                                 const std::string& normal_control = "force") {
  const auto dir = fs::temp_directory_path() / fmt::format("tc_stability_{}", getpid());
  fs::create_directories(dir);
  const auto file = dir / "case.toml";
  std::ofstream(file) << case_text(nx, ny, normal_control);
  auto p = io::read_case(file);
  fs::remove_all(dir);
  p.stability->speeds = speeds;
  p.stability->eigenvalues = count;
  return p;
}

/// The cosine cos(n m x) (n ≤ 4) that the mode's surface temperature projects on most.
int wavenumber(const physics::Problem& p, const stability::Linearisation& lin,
               const stability::Eigenpair& e) {
  const auto& mesh = p.bodies.at(0).mesh;
  const auto f = stability::mode_fields(lin, e, 2, mesh.n_nodes());
  std::array<double, 5> c{};
  for (int a = 0; a < mesh.n_nodes(); ++a) {
    if (std::abs(mesh.point(a)[1]) > 1e-12) continue;
    for (int n = 0; n < 5; ++n)
      c[n] += f.theta_re[a] * std::cos(n * kM * mesh.point(a)[0]) * (n ? 2.0 : 1.0);
  }
  int best = 0;
  for (int n = 1; n < 5; ++n)
    if (std::abs(c[n]) > std::abs(c[best])) best = n;
  return best;
}

/// The largest growth rate among the eigenvalues whose mode is cos(n m x); NaN when none.
double leading_of_mode(const physics::Problem& p, const stability::Linearisation& lin,
                       const stability::EigenResult& r, int n) {
  for (const auto& e : r.pairs)  // by decreasing real part
    if (wavenumber(p, lin, e) == n) return e.re;
  return std::nan("");
}

// Relative error of the n = 1 growth rate at V/V_cr = 0.5, 2, 4 and of the n = 2 rate at
// 4 V_cr (r = 2 for it), 5 % as the issue asks; the Q1 mesh (h_y = H/ny) resolves the thermal
// decay length 1/(ℓ n m) (5 mm at r = 0.5, 1.3 mm at 4 V_cr, 1.0 mm for n = 2) with
// 3 to 15 cells.
TEST(StabilityTei, GrowthRatesAgreeWithTheClosedForm) {
  const std::vector<double> r{0.5, 2.0, 4.0};
  std::vector<double> speeds;
  for (const double x : r) speeds.push_back(x * kVcr);
  auto p = configuration_t(20, 90, speeds, 12);
  stability::Linearisation lin;
  const auto out = stability::analyse(p, {}, &lin);
  ASSERT_EQ(out.speeds.size(), 3u);
  EXPECT_EQ(out.open_nodes, 0);
  for (size_t i = 0; i < r.size(); ++i) {
    const double b = leading_of_mode(p, lin, out.speeds[i].rates, 1);
    const double exact = closed_form(1, speeds[i]);
    std::cout << fmt::format("V/V_cr = {}: n = 1: b = {:.6g} 1/s, closed form {:.6g} ({:+.2f} %)\n",
                             r[i], b, exact, 100 * (b / exact - 1));
    EXPECT_NEAR(b, exact, 0.05 * std::abs(exact)) << "V/V_cr = " << r[i];
  }
  const double b2 = leading_of_mode(p, lin, out.speeds[2].rates, 2);
  const double exact2 = closed_form(2, speeds[2]);
  std::cout << fmt::format("V/V_cr = 4: n = 2: b = {:.6g} 1/s, closed form {:.6g} ({:+.2f} %)\n",
                           b2, exact2, 100 * (b2 / exact2 - 1));
  EXPECT_NEAR(b2, exact2, 0.05 * exact2);
  // At 4 V_cr the n = 2 mode grows fastest (5.75 κm² against 4.63 κm² for n = 1).
  EXPECT_EQ(wavenumber(p, lin, out.speeds[2].rates.pairs.front()), 2);
}

// The critical speed by the b = 0 pencil (A₀ x = −V A₁ x) against V_cr, 5 % as the issue
// asks, and against an independent route: the sign change of the n = 1 growth rate between
// 0.95 V_cr and 1.05 V_cr, interpolated linearly (b is smooth in V there: the error of the
// interpolation is O(0.05²) of V_cr).
TEST(StabilityTei, CriticalSpeedAgreesWithTheClosedForm) {
  auto p = configuration_t(20, 90, {0.95 * kVcr, 1.05 * kVcr}, 12);
  stability::Linearisation lin;
  const auto out = stability::analyse(p, {}, &lin);
  ASSERT_TRUE(out.critical.has_value());
  std::cout << fmt::format("V_c = {:.6g} m/s, closed form {:.6g} ({:+.2f} %)\n", out.critical->re,
                           kVcr, 100 * (out.critical->re / kVcr - 1));
  EXPECT_NEAR(out.critical->re, kVcr, 0.05 * kVcr);
  ASSERT_TRUE(out.growth_at_critical.has_value());
  // Leading rate at V_c: 0 up to SLEPc's tolerance against the scale κm² of the rates.
  EXPECT_LT(std::abs(*out.growth_at_critical), 1e-6 * kKappa * kM * kM);
  const double b0 = leading_of_mode(p, lin, out.speeds[0].rates, 1);
  const double b1 = leading_of_mode(p, lin, out.speeds[1].rates, 1);
  ASSERT_LT(b0, 0);
  ASSERT_GT(b1, 0);
  const double crossing = 0.95 * kVcr + (1.05 - 0.95) * kVcr * (-b0) / (b1 - b0);
  EXPECT_NEAR(out.critical->re, crossing, 1e-2 * kVcr);
}

// Mesh refinement at 4 V_cr (the thinnest mode, decay length 1.3 mm): the n = 1 rate on meshes
// of h = H/45, H/90, H/180 (W/10, W/20, W/40 across) with the shear of friction left out of the
// mechanics, as the closed form leaves it out: the error falls at Q1's order h² (a ratio of
// ~4 per halving) towards 0, so what remains in the test above (~0.5 % at 4 V_cr with the shear)
// is the shear's effect in the symmetric box, not the discretisation.
TEST(StabilityTei, GrowthRateConvergesUnderMeshRefinement) {
  const double v = 4 * kVcr, exact = closed_form(1, v);
  std::vector<double> errors;
  for (const int k : {1, 2, 4}) {
    auto p = configuration_t(10 * k, 45 * k, {v}, 6);
    p.stability->critical_speed = false;
    p.stability->friction_shear = false;
    stability::Linearisation lin;
    const auto out = stability::analyse(p, {}, &lin);
    const double b = leading_of_mode(p, lin, out.speeds[0].rates, 1);
    errors.push_back(std::abs(b / exact - 1));
    std::cout << fmt::format("{} × {} cells: b = {:.6g} 1/s, error {:.3f} %\n", 10 * k, 45 * k, b,
                             100 * errors.back());
  }
  // Observed order log2(e₁/e₂) within [1.6, 2.4] of Q1's 2 (each halving), the finest 0.2 %.
  for (size_t i = 0; i + 1 < errors.size(); ++i) {
    const double order = std::log2(errors[i] / errors[i + 1]);
    std::cout << fmt::format("observed order {:.2f}\n", order);
    EXPECT_GT(order, 1.6);
    EXPECT_LT(order, 2.4);
  }
  EXPECT_LT(errors[2], 0.002);
}

// The n = 0 mode of the tool held in position (normal_control = "displacement", as the case
// moves it): the layer is constrained between the tool and its base, so a uniform heating
// raises the mean pressure, p' = E α ∫θ dy / ((1 − 2ν) H) (uniaxial strain), and heats more.
// With θ' = Θ sinh(q(y + H)) (θ = θ₀ at the base) and k θ'(0) = 𝔉 V p' at the top:
//   z² cosh z / (cosh z − 1) = 𝔉 V E α H / (k (1 − 2ν)),   z = qH,   b = κ z²/H²,
// unstable from V₀ = 2 k (1 − 2ν)/(𝔉 E α H) (z → 0), here 0.06 V_cr: the half-plane has no
// such mode, the finite layer under a held tool has. The shear of friction on the top is
// resisted by the side planes and moves this rate at O(𝔉²); 3 %.
double uniform_mode(double v) {
  const double rhs = kFriction * v * kE * kAlpha * kDepth / (kK * (1 - 2 * kNu));
  double lo = 1e-6, hi = 50;  // z² cosh z/(cosh z − 1) increases from 2
  for (int i = 0; i < 200; ++i) {
    const double z = 0.5 * (lo + hi);
    (z * z * std::cosh(z) / (std::cosh(z) - 1) < rhs ? lo : hi) = z;
  }
  const double z = 0.5 * (lo + hi);
  return kKappa * z * z / (kDepth * kDepth);
}

TEST(StabilityTei, HeldToolHasTheUniformModeOfTheConstrainedLayer) {
  auto p = configuration_t(20, 90, {kVcr}, 12, "displacement");
  stability::Linearisation lin;
  const auto out = stability::analyse(p, {}, &lin);
  const auto& lead = out.speeds[0].rates.pairs.front();
  const double exact = uniform_mode(kVcr);
  std::cout << fmt::format(
      "held tool at V_cr: leading b = {:.6g} 1/s (mode n = {}), closed form "
      "{:.6g} ({:+.2f} %)\n",
      lead.re, wavenumber(p, lin, lead), exact, 100 * (lead.re / exact - 1));
  EXPECT_EQ(wavenumber(p, lin, lead), 0);
  EXPECT_NEAR(lead.re, exact, 0.03 * exact);
  const double v0 = 2 * kK * (1 - 2 * kNu) / (kFriction * kE * kAlpha * kDepth);
  ASSERT_TRUE(out.critical.has_value());
  std::cout << fmt::format("held tool: V_c = {:.6g} m/s, closed form V_0 = {:.6g} ({:+.2f} %)\n",
                           out.critical->re, v0, 100 * (out.critical->re / v0 - 1));
  EXPECT_NEAR(out.critical->re, v0, 0.03 * v0);
}

// The Gough–Joule term (thermoelastic_heating): in the perturbation it adds θ₀K_uθᵀCK_uθ ≥ 0 to
// the heat capacity (C the constrained compliance). In the slowest diffusion mode of the box
// under force control (n = 0: θ(y) only, the tool free along y, so uniaxial strain with
// div u = βθ/(λ + 2μ)) the capacity is exactly ρc_p(1 + δ), δ = β²θ₀/(ρc_p(λ + 2μ)): its rate
// falls by 1/(1 + δ) (1e-3: the FE mode is the same with and without the term up to the
// discrete coupling's consistency); the TEI mode's rate falls by about δ (0.5–2 %), and V_c
// (b = 0: no rate, M does not enter) stays.
TEST(StabilityTei, ThermoelasticHeatingRaisesTheCapacityByTheCouplingNumber) {
  const double theta0 = 293.15;
  const double lame = kE * kNu / ((1 + kNu) * (1 - 2 * kNu)), mu = kE / (2 * (1 + kNu));
  const double beta = (3 * lame + 2 * mu) * kAlpha;
  const double delta = beta * beta * theta0 / (kRho * kCp * (lame + 2 * mu));
  std::array<stability::StabilityResult, 2> out;
  std::array<double, 2> tei{};
  for (const int heating : {0, 1}) {
    auto p = configuration_t(20, 90, {1e-9, 2 * kVcr}, 12);
    p.physics.thermoelastic_heating = heating == 1;
    stability::Linearisation lin;
    out[heating] = stability::analyse(p, {}, &lin);
    tei[heating] = leading_of_mode(p, lin, out[heating].speeds[1].rates, 1);
  }
  const double slow0 = out[0].speeds[0].rates.pairs.front().re;
  const double slow1 = out[1].speeds[0].rates.pairs.front().re;
  std::cout << fmt::format(
      "δ = {:.6f}: slowest mode {:.6g} → {:.6g} (ratio {:.5f}, 1/(1 + δ) = "
      "{:.5f}); n = 1 at 2 V_cr {:.6g} → {:.6g} ({:+.2f} %)\n",
      delta, slow0, slow1, slow1 / slow0, 1 / (1 + delta), tei[0], tei[1],
      100 * (tei[1] / tei[0] - 1));
  ASSERT_LT(slow0, 0);
  EXPECT_NEAR(slow1 / slow0, 1 / (1 + delta), 1e-3);
  EXPECT_LT(tei[1], tei[0] * (1 - 0.5 * delta));
  EXPECT_GT(tei[1], tei[0] * (1 - 2 * delta));
  EXPECT_NEAR(out[1].critical->re, out[0].critical->re, 1e-6 * out[0].critical->re);
}

}  // namespace
}  // namespace tc::test
