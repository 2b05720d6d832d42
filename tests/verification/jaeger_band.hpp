#pragma once
// The run of Jaeger's moving band (issue 38; docs/theory.md, "Jaeger's moving band") against
// the closed forms of jaeger_closed_form.hpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <utility>
#include <vector>

#include "jaeger_closed_form.hpp"
#include "support/body_energy.hpp"
#include "support/problems.hpp"
#include "tc/mesh/box.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test::jaeger {

// ---------------------------------------------------------------------------------------------
// The run. A slider [−l, l] × [0, H] (H = l/2) of a compliant material (E_s, ν = 0), its top
// held at u_y = −δ (pressed in the first step) and moved along x at V from then on, on a block
// [−l − 2l, l + S + a] × [−D, 0] 10⁴ times stiffer, bottom held; quasistatic (no wave or inertia
// enters Jaeger's problem, and a dynamic scheme would only add the slider's vibration to the
// pressure); α = 0 and no thermoelastic heating, so what is checked is the heat path alone:
// friction work → heat → the block's conduction. The contact pair: the slider's bottom (slave)
// on the block's top (master), 𝔉 = ½, γ_C^s = 0, γ_C^m = 1: δ_C = 0, β_C = 0, all the frictional
// heat into the block and none across; the block insulated elsewhere, k = ρc_p = 1 (k_d = 1).
//
// The pressure is uniform: a rigid flat pressing a ν = 0 layer through a clamped top is in
// uniform uniaxial stress; under sliding the bottom's shear 𝔉p and the drive's equal shear on
// the top need the moment of ±𝔉p on the slider's ends, given as tractions (0, ±𝔉p) on xmax
// and xmin, so that the uniform state σ_yy = −p, σ_xy = 𝔉p is the exact solution. The block's
// compliance (a strip load on a half-plane, settlement differences ~p l/E_b against the
// slider's p H/E_s, 2·10⁻⁴ times a log) leaves ~10⁻³ of p: the run measures it.
struct Settings {
  double pe = 2;
  double h = 0.1;             // the block's cells along the surface (the first one h/4 deep)
  double steps_per_cell = 1;  // slide steps per cell: V τ = h / steps_per_cell
};

struct Layout {
  Band band;
  double h = 0, tau = 0, slide = 0, ahead = 0, behind = 0, depth = 0, height = 0;
  int slide_steps = 0;
  double pressure = 0, friction = 0.5, flux = 0;  // p, 𝔉, q = 𝔉 p V
};

inline double round_up(double x, double unit) {
  return unit * std::ceil(x / unit - 1e-9);
}

inline Layout layout(const Settings& s) {
  Layout g;
  g.band.l = 1;
  g.band.v = 2 * s.pe * g.band.kd / g.band.l;
  g.h = s.h;
  const double l = g.band.l;
  // The slide S: the steady state is missing the tail ≈ E₁(V²t/(4k_d)) = E₁(Pe S/(2l)) of the
  // past; S ≥ 8l/Pe + 2l keeps it ≤ E₁(4 + Pe) (the transient closed form at the end is within
  // 0.15 % of the steady one at Pe 0.5, 2 and 10; each run prints it), and S ≥ 4l brings every
  // point under the band at the end in through the leading edge after the start.
  g.slide = round_up(std::max(4 * l, 8 * l / s.pe + 2 * l), l);
  // Ahead of the final leading edge: the steady field falls as e^{−VX/k_d} there; 5k_d/V.
  g.ahead = round_up(std::max(1.5 * l, 2.5 * l / s.pe), 0.5 * l);
  g.behind = 2 * l;
  // Depth: 2.5 diffusion lengths of the run, the bottom's image ≤ E₁(6.25) q l/(πk).
  const double t = g.slide / g.band.v;
  g.depth = std::max(2 * l, round_up(2.5 * std::sqrt(g.band.kd * t), 0.5 * l));
  g.height = 0.5 * l;
  const double step = s.h / s.steps_per_cell;
  g.slide_steps = static_cast<int>(std::lround(g.slide / step));
  g.tau = step / g.band.v;
  g.pressure = 1.0 / (g.friction * g.band.v);  // q = 1 W/m²: θ in units of q l/k
  g.flux = g.friction * g.pressure * g.band.v;
  return g;
}

/// make_box's mesh with every point mapped by `map` (the cells, their order and the boundaries
/// kept): the block's depth graded.
inline mesh::Mesh mapped(const mesh::Mesh& m, const std::function<mesh::Point(mesh::Point)>& map) {
  mesh::Mesh out(m.dim());
  for (int a = 0; a < m.n_nodes(); ++a) out.add_point(map(m.point(a)));
  for (int c = 0; c < m.n_cells(); ++c) out.add_cell(m.cell_type(c), m.cell(c));
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) out.add_facet(name, f);
  return out;
}

/// The block's depth cells: the first h/4 deep (the boundary layer √(k_d l/V) = l/√(2Pe) is
/// 0.22 l at Pe 10, so ≥ 9 cells in it at h = l/10), growing geometrically by at most 1.15.
inline std::vector<double> depth_levels(double first, double depth) {
  const int n = static_cast<int>(std::ceil(std::log(1 + depth * 0.15 / first) / std::log(1.15)));
  double lo = 1.0, hi = 1.15;  // ratio r with first (rⁿ − 1)/(r − 1) = depth
  for (int it = 0; it < 200; ++it) {
    const double r = 0.5 * (lo + hi);
    const double sum = std::abs(r - 1) < 1e-12 ? first * n : first * (std::pow(r, n) - 1) / (r - 1);
    (sum > depth ? hi : lo) = r;
  }
  const double r = 0.5 * (lo + hi);
  std::vector<double> y{0};
  double d = first;
  for (int j = 0; j < n; ++j, d *= r) y.push_back(y.back() - d);
  y.back() = -depth;
  return y;
}

inline physics::Problem problem(const Layout& g) {
  const double l = g.band.l, theta0 = 293.15;
  physics::Problem p;
  p.dimension = 2;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = g.tau;
  p.time.end = g.tau * (1 + g.slide_steps);
  p.physics.reference_temperature = theta0;
  p.physics.thermoelastic_heating = false;
  p.physics.thermal_expansion = false;

  fem::Material soft;
  soft.density = 1;
  soft.specific_heat = 1;
  soft.thermal_conductivity = 1;
  soft.thermal_expansion = 0;
  soft.young_modulus = 1e3;
  soft.poisson_ratio = 0;
  fem::Material stiff = soft;
  stiff.thermal_conductivity = g.band.k;
  stiff.specific_heat = g.band.k / g.band.kd;
  stiff.young_modulus = 1e7;
  stiff.poisson_ratio = 0.3;

  physics::Body slider;
  slider.name = "slider";
  slider.material = soft;
  // Non-matching: 1.3 times as many cells as the block has under it.
  const int ns = static_cast<int>(std::lround(1.3 * 2 * l / g.h));
  slider.mesh = mesh::make_box(2, {-l, 0, 0}, {l, g.height, 0}, {ns, 2, 1});
  slider.initial_temperature = theta0;
  p.bodies.push_back(std::move(slider));

  physics::Body block;
  block.name = "block";
  block.material = stiff;
  const double x0 = -l - g.behind, x1 = l + g.slide + g.ahead;
  const int nx = static_cast<int>(std::lround((x1 - x0) / g.h));
  const auto levels = depth_levels(0.25 * g.h, g.depth);
  const int ny = static_cast<int>(levels.size()) - 1;
  const auto box = mesh::make_box(2, {x0, -1, 0}, {x1, 0, 0}, {nx, ny, 1});
  block.mesh = mapped(box, [&](mesh::Point q) {
    const auto j = static_cast<size_t>(std::lround(-q[1] * ny));
    q[1] = levels[j];
    return q;
  });
  block.initial_temperature = theta0;
  p.bodies.push_back(std::move(block));

  const double delta = g.pressure * g.height / soft.young_modulus;
  const core::TimeTable press({0, g.tau}, {0, -delta});
  const core::TimeTable drag({0, g.tau, p.time.end}, {0, 0, g.band.v * (p.time.end - g.tau)});
  p.boundaries.push_back(displacement_bc(0, "ymax", {{0, drag}, {1, press}}));
  // The ends' shear ±𝔉p once the slide has begun (the first step presses in stick: no shear).
  const double shear = g.friction * g.pressure;
  for (const auto& [where, sign] : {std::pair{"xmax", 1.0}, std::pair{"xmin", -1.0}}) {
    physics::BoundaryCondition bc;
    bc.body = 0;
    bc.where = where;
    bc.traction[1] = core::TimeTable({0, g.tau, 2 * g.tau}, {0, 0, sign * shear});
    p.boundaries.push_back(bc);
  }
  p.boundaries.push_back(displacement_bc(1, "ymin", {{0, 0.0}, {1, 0.0}}));

  auto c = contact_pair(0, "ymin", 1, "ymax", g.friction);
  c.conductance_slave = 0;
  c.conductance_master = 1;  // δ_C = 0: all the heat into the block
  c.heat_conduction = false;
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  p.solver.max_coupling_iterations = 50;
  return p;
}

struct Result {
  Layout g;
  double fe_max = 0, fe_mean = 0;  // θ − θ₀ of the block's surface under the band at the end
  double cf_max = 0, cf_mean = 0;  // the uniform band's steady closed form
  double tr_max = 0, tr_mean = 0;  // the transient closed form at the end (the slide's length)
  double own_worst = 0;            // max |θ_FE − θ_own|/max θ_own over X ∈ [−l, 2l]: (a)
  double spread = 0;               // max |λ_n,k/p̄ − 1| over the slider's contact nodes: (b)
  double mean_pressure = 0;        // p̄/p − 1, p̄ = N/(2l) (the block's compliance)
  double friction_heat = 0;        // heat_generated / Σ_steps τ T V − 1
  double to_block = 0;             // heat_to_master / heat_generated − 1 (δ_C = 0)
  double block_energy = 0;  // the block's ∫ρc(θ − θ₀) / heat_to_master − 1 (insulated)
  double bottom = 0;  // the insulated bottom's image, ≤ q l/(πk) E₁(D²/(k_d t)) / θ_max
  double seconds = 0;
};

inline Result run(const Settings& s) {
  Result r;
  r.g = layout(s);
  const auto& g = r.g;
  const auto p = problem(g);
  const double theta0 = p.physics.reference_temperature, l = g.band.l;
  const auto start = std::chrono::steady_clock::now();
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  double work = 0;  // Σ τ T V over the slide (the first step presses in stick)
  for (int k = 0; k <= g.slide_steps; ++k) {
    sim.advance();
    if (k > 0) work += g.tau * sim.history("contact_tangential_force") * g.band.v;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  // The band's frame: the slider's bottom nodes where they are now; the run's own flux there,
  // ‖λ_τ,k‖ V (full slip at V: the slip rate is V less the slider's constant shear).
  const auto& slider = p.bodies[0].mesh;
  const auto us = sim.state(0).u.to_std();
  const auto& nodes = sim.mortar()->contact_nodes();
  const auto lambda = sim.contact_multipliers();
  const double unit = sim.traction_per_multiplier();
  std::vector<std::pair<double, double>> own;
  double centre = 0;
  const double mean_p = sim.history("contact_normal_force") / (2 * l);
  for (size_t k = 0; k < nodes.size(); ++k) {
    const auto a = static_cast<size_t>(nodes[k]);
    const double x = slider.point(nodes[k])[0] + us[2 * a];
    centre += x / static_cast<double>(nodes.size());
    own.emplace_back(x, std::abs(lambda[2 * k + 1]) * unit * g.band.v);
    r.spread = std::max(r.spread, std::abs(lambda[2 * k] * unit / mean_p - 1));
  }
  std::sort(own.begin(), own.end());
  std::vector<double> xs, qs;
  for (const auto& [x, q] : own) xs.push_back(x - centre), qs.push_back(q);
  r.mean_pressure = mean_p / g.pressure - 1;

  // The block's surface in that frame: the nodal maximum and the trapezoidal mean over the
  // band (its edges fall on nodes: the slide is a whole number of cells).
  const auto& block = p.bodies[1].mesh;
  const auto theta = sim.state(1).theta.to_std();
  std::vector<std::pair<double, double>> surface;  // (X, θ − θ₀)
  for (const int a : block.boundary_nodes("ymax"))
    surface.emplace_back(block.point(a)[0] - centre, theta[static_cast<size_t>(a)] - theta0);
  std::sort(surface.begin(), surface.end());
  double integral = 0;
  for (size_t j = 0; j < surface.size(); ++j) {
    const auto [x, t] = surface[j];
    if (x > -l - 1e-6 * l && x < l + 1e-6 * l) r.fe_max = std::max(r.fe_max, t);
    if (j + 1 == surface.size()) break;
    const auto [x1, t1] = surface[j + 1];
    const double a = std::max(x, -l), b = std::min(x1, l);
    const auto at = [&](double y) { return t + (t1 - t) * (y - x) / (x1 - x); };
    if (b > a) integral += 0.5 * (at(a) + at(b)) * (b - a);
  }
  r.fe_mean = integral / (2 * l);
  // (a): behind −l the wake is not yet steady after a finite slide; ahead of 2l it is ~0.
  std::vector<double> fe, mine;
  double own_max = 0;
  for (const auto& [x, t] : surface) {
    if (x < -l - 1e-6 * l || x > 2 * l) continue;
    fe.push_back(t);
    mine.push_back(steady_profile(g.band, xs, qs, x));
    own_max = std::max(own_max, mine.back());
  }
  for (size_t j = 0; j < fe.size(); ++j)
    r.own_worst = std::max(r.own_worst, std::abs(fe[j] - mine[j]) / own_max);

  r.cf_max = band_maximum([&](double x) { return steady_uniform(g.band, g.flux, x); }, l);
  r.cf_mean = steady_uniform_mean(g.band, g.flux);
  const double t_end = g.slide / g.band.v;
  const auto tr = [&](double x) { return transient_uniform(g.band, g.flux, x, t_end); };
  r.tr_max = band_maximum(tr, l);
  r.tr_mean = (graded(tr, -l, 0, -l) + graded(tr, 0, l, l)) / (2 * l);
  r.bottom = g.flux * l / (std::numbers::pi * g.band.k) *
             -std::expint(-g.depth * g.depth / (g.band.kd * t_end)) / r.cf_max;
  const double generated = sim.history("heat_generated");
  r.friction_heat = generated / work - 1;
  r.to_block = sim.history("heat_to_master") / generated - 1;
  r.block_energy = body_energy(sim, 1, theta0) / sim.history("heat_to_master") - 1;
  return r;
}

/// One line of the table: Pe, h, τ, θ_max FE / closed form, θ̄ FE / closed form, the FE against
/// the transient closed form at the end, (a)'s worst difference, the pressure's spread, seconds.
inline void print(const Result& r) {
  std::printf(
      "[ measure  ] Pe %5.2f  h %.4f  τ %.2e (Vτ %.5f) | θ_max %.5f / %.5f (%+6.2f %%) | θ̄ %.5f / "
      "%.5f "
      "(%+6.2f %%) | against the transient %+6.2f %% %+6.2f %% | (a) own flux %.2f %% | p "
      "spread %.1e | %5.1f s\n",
      r.g.band.pe(), r.g.h, r.g.tau, r.g.band.v * r.g.tau, r.fe_max, r.cf_max,
      100 * (r.fe_max / r.cf_max - 1), r.fe_mean, r.cf_mean, 100 * (r.fe_mean / r.cf_mean - 1),
      100 * (r.fe_max / r.tr_max - 1), 100 * (r.fe_mean / r.tr_mean - 1), 100 * r.own_worst,
      r.spread, r.seconds);
}

}  // namespace tc::test::jaeger
