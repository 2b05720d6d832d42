#pragma once
// The thermoelastic instability (TEI) of a deep layer under a rigid non-conducting flat sliding
// at V (issue 38; docs/theory.md, "Thermoelastic instability of a layer under a rigid flat"):
// the closed form of the linear stability theory and the transient FE run that measures the
// growth rate b of a seeded cos(mx) mode.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <vector>

#include "jaeger_band.hpp"  // jaeger::mapped, jaeger::depth_levels: the graded box
#include "support/problems.hpp"
#include "tc/model/rigid_tool.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test::tei {

// ---------------------------------------------------------------------------------------------
// The closed form (Burton, Nerlikar & Kilaparti 1973 for a half-plane on a rigid non-conductor;
// derived in docs/theory.md). The half-plane y < 0, the perturbation θ' = Θ e^{bt} e^{λy} cos mx,
// λ = √(m² + b/κ): the thermoelastic potential and the Airy correction that frees the surface
// give u_y(x, 0) = 2α(1 + ν)Θ/(λ + m) cos mx; the rigid flat keeps u_y uniform, so the pressure
// P cos mx with the compliance 2(1 − ν²)/(E m) cancels it, P = E m α Θ/((1 − ν)(λ + m)); all
// the frictional heat 𝔉 V P into the layer, k λ Θ = 𝔉 V P. Hence λ(λ + m) = 𝔉 V E α m/(k(1 − ν)),
// with ℓ = λ/m and r = V/V_cr, V_cr = 2k(1 − ν)m/(𝔉 E α): ℓ(ℓ + 1) = 2r, b = κm²(ℓ² − 1).
struct Constants {
  double young = 2e11, poisson = 0.3, expansion = 1.2e-5;  // E [Pa], ν, α [1/K]
  double conductivity = 50, density = 7850, specific_heat = 460;
  double friction = 0.1;
  double wavelength = 0.02;  // λ_w = 2π/m [m]; the box is half of it wide
  [[nodiscard]] double m() const { return 2 * std::numbers::pi / wavelength; }
  [[nodiscard]] double kappa() const { return conductivity / (density * specific_heat); }
  [[nodiscard]] double rate_unit() const { return kappa() * m() * m(); }  // κm² [1/s]
  [[nodiscard]] double critical_speed() const {
    return 2 * conductivity * (1 - poisson) * m() / (friction * young * expansion);
  }
};

/// ℓ = λ/m of the unstable (or least stable) mode at r = V/V_cr: the root of ℓ(ℓ + 1) = 2r.
inline double decay_ratio(double r) {
  return 0.5 * (std::sqrt(1 + 8 * r) - 1);
}
/// b/(κm²) = ℓ² − 1.
inline double rate(double r) {
  const double l = decay_ratio(r);
  return l * l - 1;
}
/// Backward Euler with the staggered loop converged: the mode's amplitude is multiplied by
/// 1/(1 − bτ) per step, i.e. the rate b_τ = −ln(1 − bτ)/τ measured over whole steps.
inline double discrete_rate(double b, double tau) {
  return -std::log(1 - b * tau) / tau;
}
/// The pressure of the mode per kelvin of its surface amplitude: P/Θ = E α/((1 − ν)(ℓ + 1)).
inline double pressure_per_kelvin(const Constants& c, double r) {
  return c.young * c.expansion / ((1 - c.poisson) * (decay_ratio(r) + 1));
}

// ---------------------------------------------------------------------------------------------
// The run. The layer [0, W] × [−H, 0], W = λ_w/2, H = 1.5λ_w, plane strain, quasistatic
// mechanics (V ≤ 0.4 m/s against wave speeds of km/s: no inertia term of the theory; the
// dynamic TEI of Afferrante & Ciavarella 2007 matters only near those speeds) and backward
// Euler heat; the sides x = 0, W on rollers (u_x = 0) and adiabatic, the symmetry planes of a
// cos(mx) mode; the bottom held (u = 0) at θ₀ (the mode is ~e^{−ℓmH} ≤ 3·10⁻³ there). Its top
// is the slave of a pair with the rigid plane y = 0 (normal (0, −1), out of the tool), 𝔉 = 0.1,
// adiabatic (all the frictional heat into the layer). The tool presses by d₀ in the first step
// (p₀ ≈ 1 MPa through the laterally held layer's modulus E(1 − ν)/((1 + ν)(1 − 2ν))) and slides
// along x at V from then on. No thermoelastic heating (the classical theory leaves the
// Gough–Joule term out).
struct Settings {
  double r = 2;                 // V/V_cr
  int nx = 20;                  // cells along the half wavelength
  double first = 5e-5;          // the top cell's depth [m]; the cells grow by ≤ 1.15 downwards
  double cells_per_step = 1;    // V τ / h_x
  double pressure = 1e7;        // p₀ [Pa]
  double seed_fraction = 0.05;  // the seed's pressure P/p₀ at the start
  physics::Scheme scheme = physics::Scheme::quasistatic;
  bool tight_qps = true;  // qp_tolerance 1e-13 without forcing; false: the solver's defaults
};

struct Layout {
  Constants c;
  double width = 0, depth = 0, speed = 0, tau = 0, press = 0, pressure = 0, seed = 0;
  int steps = 0;  // slide steps after the press
};

inline Layout layout(const Settings& s) {
  Layout g;
  g.width = 0.5 * g.c.wavelength;
  g.depth = 1.5 * g.c.wavelength;
  g.speed = s.r * g.c.critical_speed();
  g.tau = s.cells_per_step * g.width / s.nx / g.speed;
  // The slide: 1.5/|b| (the mode grows or decays by e^{1.5}), at most 2/(κm²) near V_cr where
  // b → 0; the fit takes its later half, when the faster modes (b ≤ −κm²) of the seed's misfit
  // and of the base state's start have decayed by e^{−1} or more against the mode.
  const double u = g.c.rate_unit(), b = std::abs(rate(s.r)) * u;
  g.steps = static_cast<int>(std::ceil(std::min(1.5 / b, 2 / u) / g.tau));
  g.pressure = s.pressure;
  const double e = g.c.young, nu = g.c.poisson;
  g.press = g.pressure * g.depth * (1 + nu) * (1 - 2 * nu) / (e * (1 - nu));
  // The seed's surface amplitude from its pressure: at 5 % of p₀ the mode, grown by e^{1.5}
  // at most, keeps the contact closed (checked: min λ_n > 0 at every step).
  g.seed = s.seed_fraction * g.pressure / pressure_per_kelvin(g.c, s.r);
  return g;
}

inline physics::Problem problem(const Settings& s, const Layout& g) {
  const double theta0 = 293.15;
  physics::Problem p;
  p.dimension = 2;
  p.time.scheme = s.scheme;
  p.time.step = g.tau;
  p.time.end = g.tau * (1 + g.steps);
  p.physics.reference_temperature = theta0;
  p.physics.thermoelastic_heating = false;

  fem::Material mat;
  mat.density = g.c.density;
  mat.young_modulus = g.c.young;
  mat.poisson_ratio = g.c.poisson;
  mat.thermal_expansion = g.c.expansion;
  mat.specific_heat = g.c.specific_heat;
  mat.thermal_conductivity = g.c.conductivity;

  physics::Body layer;
  layer.name = "layer";
  layer.material = mat;
  const auto levels = jaeger::depth_levels(s.first, g.depth);
  const int ny = static_cast<int>(levels.size()) - 1;
  const auto box = mesh::make_box(2, {0, -1, 0}, {g.width, 0, 0}, {s.nx, ny, 1});
  layer.mesh = jaeger::mapped(box, [&](mesh::Point q) {
    q[1] = levels[static_cast<size_t>(std::lround(-q[1] * ny))];
    return q;
  });
  layer.initial_temperature = theta0;
  p.bodies.push_back(std::move(layer));

  p.boundaries.push_back(displacement_bc(0, "xmin", {{0, 0.0}}));
  p.boundaries.push_back(displacement_bc(0, "xmax", {{0, 0.0}}));
  p.boundaries.push_back(displacement_bc(0, "ymin", {{0, 0.0}, {1, 0.0}}));
  p.boundaries.push_back(temperature_bc(0, "ymin", theta0));

  physics::RigidTool tool;
  tool.point = {0.5 * g.width, 0, 0};
  tool.normal = {0, -1, 0};
  tool.motion[0] = core::TimeTable({0, g.tau, p.time.end}, {0, 0, g.speed * (p.time.end - g.tau)});
  tool.motion[1] = core::TimeTable({0, g.tau}, {0, -g.press});
  physics::ContactSettings c;
  c.slave_body = 0;
  c.slave_where = "ymax";
  c.master_body = -1;
  c.rigid_master = tool;
  c.friction = g.c.friction;
  p.contacts = {c};
  // The normal rows stop on their own ‖d_n‖ (qp::QpOptions::row_groups), not only on the
  // slip's V τ D that dominates ‖d‖; ε = 1e-13 with no looser forcing in the friction loop still
  // keeps λ_n to ~1e-8 of p₀ for a clean rate (the defaults: −0.15 % at 2 V_cr, the test
  // TheSolversDefaultQpsSolveTheNormalRowsOfASlide). The coupling to 1e-10 of ‖λ‖ leaves
  // ≤ 1e-7 of the mode, whose pressure is 5 % of p₀.
  if (s.tight_qps) {
    p.solver.qp_tolerance = 1e-13;
    p.solver.friction.qp_forcing_cap = 1e-13;
  }
  p.solver.coupling_tolerance = 1e-10;
  p.solver.max_coupling_iterations = 100;
  physics::place_rigid_tools(p);
  return p;
}

/// The per-step record of one run.
struct Trace {
  std::vector<double> t, theta_mode, pressure_mode;  // cos(mx) coefficients of θ − θ₀ and λ_n
  double min_pressure = 1e300;  // min λ_n over the contact nodes and the slide's steps [Pa]
  double min_slip = 1e300;      // min of the slip per unit length over them, / (V τ)
  double max_slip = -1e300;
  long coupling = 0;
  int cut_backs = 0;  // steps taken as two halves
};

/// The cos(mx) coefficient (2/W)∫₀^W f cos(mx) dx by the trapezoidal rule on the uniform nodes:
/// exactly orthogonal to the other cos(jmx) of the nodes (the discrete cosine transform), so
/// the box's other modes (the base state's corners, below) do not leak into it.
inline double cos_coefficient(const std::vector<std::pair<double, double>>& xf, double m,
                              double w) {
  double s = 0;
  for (size_t j = 0; j + 1 < xf.size(); ++j) {
    const auto [x0, f0] = xf[j];
    const auto [x1, f1] = xf[j + 1];
    s += 0.5 * (f0 * std::cos(m * x0) + f1 * std::cos(m * x1)) * (x1 - x0);
  }
  return 2 * s / w;
}

/// One run: seeded with θ₀ + ε e^{ℓmy} cos(mx) (the eigenmode's temperature) right after the
/// press when `seeded`, the unseeded base state otherwise.
inline Trace run_one(const Settings& s, const Layout& g, bool seeded) {
  const auto p = problem(s, g);
  const double theta0 = p.physics.reference_temperature, m = g.c.m();
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  sim.advance();  // the press, in stick: no heat
  if (seeded) {
    auto cp = sim.checkpoint();
    const auto& mesh = p.bodies[0].mesh;
    const double lm = decay_ratio(s.r) * m;
    for (int a = 0; a < mesh.n_nodes(); ++a) {
      const auto q = mesh.point(a);
      cp.bodies[0].theta[static_cast<size_t>(a)] +=
          g.seed * std::exp(lm * q[1]) * std::cos(m * q[0]);
    }
    sim.restore(cp);
  }
  Trace tr;
  const auto& mesh = p.bodies[0].mesh;
  const auto top = mesh.boundary_nodes("ymax");
  for (int k = 0; k < g.steps; ++k) {
    const int cut = sim.cut_back_steps();
    sim.advance();
    // A step cut back ([solver] max_cutbacks) is two of τ/2: the mode's factor is
    // 1/(1 − bτ/2)², within (bτ)²/4 ≤ 2·10⁻⁵ of one step's; its slip is the last half's.
    const bool whole = sim.cut_back_steps() == cut;
    tr.cut_backs += whole ? 0 : 1;
    tr.coupling = sim.total_coupling_iterations();
    const auto theta = sim.state(0).theta.to_std();
    std::vector<std::pair<double, double>> xt;
    for (const int a : top)
      xt.emplace_back(mesh.point(a)[0], theta[static_cast<size_t>(a)] - theta0);
    std::sort(xt.begin(), xt.end());
    const auto& nodes = sim.mortar()->contact_nodes();
    const auto lambda = sim.contact_multipliers();
    const auto& slip = sim.contact_slip();
    std::vector<std::pair<double, double>> xp;
    for (size_t j = 0; j < nodes.size(); ++j) {
      xp.emplace_back(mesh.point(nodes[j])[0], lambda[2 * j]);
      tr.min_pressure = std::min(tr.min_pressure, lambda[2 * j]);
      // The slip B_τΔu is weighted by D_kk = ∫ψ_k (h_x, h_x/2 at the ends): per unit length
      // against the tool's V τ, signed by the first node's (the tangent's orientation is the
      // mortar's): ≈ 1 everywhere is a full slip the same way at every node.
      const double x = mesh.point(nodes[j])[0], hx = g.width / s.nx;
      const double w = x < 0.5 * hx || x > g.width - 0.5 * hx ? 0.5 * hx : hx;
      const double sl = slip[2 * j + 1] / (w * g.speed * g.tau) * (slip[1] < 0 ? -1 : 1);
      if (!whole) continue;
      tr.min_slip = std::min(tr.min_slip, sl);
      tr.max_slip = std::max(tr.max_slip, sl);
    }
    std::sort(xp.begin(), xp.end());
    tr.t.push_back(sim.time());
    tr.theta_mode.push_back(cos_coefficient(xt, m, g.width));
    tr.pressure_mode.push_back(cos_coefficient(xp, m, g.width));
  }
  return tr;
}

/// The least-squares slope of ln|a| against t over the samples [from, end).
inline double log_slope(const std::vector<double>& t, const std::vector<double>& a, size_t from) {
  double st = 0, sy = 0, stt = 0, sty = 0;
  const double n = static_cast<double>(t.size() - from);
  for (size_t j = from; j < t.size(); ++j) {
    const double y = std::log(std::abs(a[j]));
    st += t[j], sy += y, stt += t[j] * t[j], sty += t[j] * y;
  }
  return (n * sty - st * sy) / (n * stt - st * st);
}

struct Result {
  Settings s;
  Layout g;
  double theory = 0;       // b of the closed form [1/s]
  double theory_tau = 0;   // b_τ = −ln(1 − bτ)/τ
  double fe = 0;           // the fitted rate of the seeded − unseeded θ mode over the later half
  double fe_pressure = 0;  // the same of the pressure's cos(mx) coefficient
  double fe_seeded = 0;    // the seeded run's θ mode alone (the base state not subtracted)
  double spread = 0;       // max |per-step rate/b_τ − 1| over the later half (clean mode)
  double pressure_ratio = 0;  // the mode's P/Θ at the end against the closed form, − 1
  double min_pressure = 0;    // min λ_n / p₀ over both runs' slide steps
  double min_slip = 0, max_slip = 0;
  double coupling_per_step = 0;
  int cut_backs = 0;
  double seconds = 0;
  [[nodiscard]] double error() const { return fe / theory_tau - 1; }
  /// b from the measured per-step factor g = e^{b_fe τ}: b = (1 − 1/g)/τ, against the theory.
  [[nodiscard]] double inverted() const { return (1 - std::exp(-fe * g.tau)) / g.tau; }
};

inline Result run(const Settings& s) {
  Result r;
  r.s = s;
  r.g = layout(s);
  const auto start = std::chrono::steady_clock::now();
  const auto seeded = run_one(s, r.g, true);
  const auto base = run_one(s, r.g, false);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.theory = rate(s.r) * r.g.c.rate_unit();
  r.theory_tau = discrete_rate(r.theory, r.g.tau);
  std::vector<double> dt, dp;
  for (size_t k = 0; k < seeded.t.size(); ++k) {
    dt.push_back(seeded.theta_mode[k] - base.theta_mode[k]);
    dp.push_back(seeded.pressure_mode[k] - base.pressure_mode[k]);
  }
  const size_t half = seeded.t.size() / 2;
  r.fe = log_slope(seeded.t, dt, half);
  r.fe_pressure = log_slope(seeded.t, dp, half);
  r.fe_seeded = log_slope(seeded.t, seeded.theta_mode, half);
  for (size_t k = half; k + 1 < dt.size(); ++k)
    r.spread =
        std::max(r.spread, std::abs(std::log(dt[k + 1] / dt[k]) / r.g.tau / r.theory_tau - 1));
  r.pressure_ratio = dp.back() / dt.back() / pressure_per_kelvin(r.g.c, s.r) - 1;
  r.min_pressure = std::min(seeded.min_pressure, base.min_pressure) / r.g.pressure;
  r.min_slip = std::min(seeded.min_slip, base.min_slip);
  r.max_slip = std::max(seeded.max_slip, base.max_slip);
  r.cut_backs = seeded.cut_backs + base.cut_backs;
  r.coupling_per_step = static_cast<double>(seeded.coupling + base.coupling) /
                        (2.0 * static_cast<double>(r.g.steps + 1));
  return r;
}

/// One line of the table: V/V_cr, h_x, the top cell, τ, b FE, b_τ, the error, b inverted
/// against b, the pressure mode's rate, the seeded run alone, the closure and slip checks.
inline void print(const Result& r) {
  const double u = r.g.c.rate_unit();
  std::printf(
      "[ measure  ] V/V_cr %.2f  h_x %.3g mm  h_y %.3g mm  τ %.4g s (bτ %+.3f) | b_FE/κm² "
      "%+.5f  b_τ/κm² %+.5f (%+.2f %%) | (1−e^{−b_FE τ})/τ vs b %+.5f / %+.5f (%+.2f %%) | λ_n "
      "mode %+.2f %% | unsubtracted %+.5f | P/Θ %+.2f %% | min λ_n/p₀ %.3f slip %.4f–%.4f | "
      "spread %.1e | %.1f it/step, %d cut back | %.1f s\n",
      r.s.r, 1e3 * r.g.width / r.s.nx, 1e3 * r.s.first, r.g.tau, r.theory * r.g.tau, r.fe / u,
      r.theory_tau / u, 100 * r.error(), r.inverted() / u, r.theory / u,
      100 * (r.inverted() / r.theory - 1), 100 * (r.fe_pressure / r.theory_tau - 1),
      r.fe_seeded / u, 100 * r.pressure_ratio, r.min_pressure, r.min_slip, r.max_slip, r.spread,
      r.coupling_per_step, r.cut_backs, r.seconds);
}

}  // namespace tc::test::tei
