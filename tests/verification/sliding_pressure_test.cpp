// A compliant slider dragged over a stiff block with a slide per step V τ of one or two of the
// block's cells h: the contact pressure must stay uniform (docs/theory.md, "Sliding: the gap's
// linearisation"). With the gap (2.6) linearised about the configuration of the step's start,
// each step read the slide along the slave's nodal normals: the end-of-step gap was V τ n_k·t
// (measured: correlation 0.9995 with it, ratio 1.0004), which turned the slave's surface and
// so the next step's normals, an explicit advection of the surface's shape with the Courant
// number V τ/h_s of the slave's cells h_s: the pressure grew by ~1.25 per step once V τ > h_s
// (unstable at 0.9h, stable at 0.75h with h_s = h/1.3; matching meshes stable at V τ = h and
// unstable at 2h), 2D and 3D, with and without friction, quasistatic and dynamic.
// The slider [−l, l] × [0, H] (ν = 0, E_s = 10³, 1.3 times as many cells as the block under it)
// pressed by its top (u_y = −δ = −pH/E_s) and dragged at V by it, on a block 10⁴ times stiffer:
// uniform uniaxial stress σ_yy = −p is the exact state, with friction too when the ends carry
// the moment of the bottom's shear (tractions (0, ±𝔉p), as in jaeger_band.hpp), so the spread
// left is the block's compliance (the strip's dent, ~p l/E_b against the slider's δ = p H/E_s:
// 2–10·10⁻⁴ measured, whatever the step).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "support/problems.hpp"
#include "tc/contact/mortar_pair.hpp"
#include "tc/mesh/box.hpp"
#include "tc/run/simulation.hpp"

namespace tc::test {
namespace {

constexpr double kL = 1, kHeight = 0.5, kSoft = 1e3, kStiff = 1e7, kPressure = 1, kSpeed = 1;

struct Settings {
  int dim = 2;
  double h = 0.1;             // the block's cells along the slide
  double steps_per_cell = 1;  // V τ = h / steps_per_cell
  double friction = 0;        // 𝔉
  bool dynamic = false;       // Newmark (the default contact scheme) with a light slider
  int steps = 100;            // slide steps after the pressing one
};

struct Result {
  std::vector<double> spread;  // (max − min)/mean of λ_n over the contact nodes, per step
  double worst_gap = 0;        // max |g_k/w_k| over the contact nodes at the end of each step
};

physics::Problem sliding_problem(const Settings& s) {
  const int vd = s.dim - 1;  // the vertical axis
  const std::string top = s.dim == 2 ? "ymax" : "zmax", bottom = s.dim == 2 ? "ymin" : "zmin";
  const double step = s.h / s.steps_per_cell, tau = step / kSpeed;
  physics::Problem p;
  p.dimension = s.dim;
  p.time.scheme = s.dynamic ? physics::Scheme::dynamic : physics::Scheme::quasistatic;
  p.time.step = tau;
  p.time.end = tau * (1 + s.steps);
  p.physics.reference_temperature = 293.15;
  p.physics.thermoelastic_heating = false;
  p.physics.thermal_expansion = false;
  fem::Material soft;
  // Dynamic: the slider's first vertical mode, √(E/ρ)/(4H) ≈ 1.6·10⁴/s, far above the 10/s of
  // the steps, so the run is the quasistatic one with Newmark's scheme and contact treatment.
  soft.density = 1e-6;
  soft.specific_heat = 1;
  soft.thermal_conductivity = 1;
  soft.thermal_expansion = 0;
  soft.young_modulus = kSoft;
  soft.poisson_ratio = 0;
  fem::Material stiff = soft;
  stiff.young_modulus = kStiff;
  stiff.poisson_ratio = 0.3;
  // Non-matching: 1.3 times as many cells along the slide as the block has under the slider.
  const int ns = static_cast<int>(std::lround(1.3 * 2 * kL / s.h));
  const double x0 = -2 * kL, x1 = kL + s.steps * step + 1.5 * kL;
  const int nx = static_cast<int>(std::lround((x1 - x0) / s.h));
  physics::Body slider, block;
  slider.name = "slider";
  slider.material = soft;
  block.name = "block";
  block.material = stiff;
  if (s.dim == 2) {
    slider.mesh = mesh::make_box(2, {-kL, 0, 0}, {kL, kHeight, 0}, {ns, 2, 1});
    block.mesh = mesh::make_box(2, {x0, -2 * kL, 0}, {x1, 0, 0}, {nx, 6, 1});
  } else {
    slider.mesh = mesh::make_box(3, {-kL, 0, 0}, {kL, 0.4, kHeight}, {ns, 2, 2});
    block.mesh = mesh::make_box(3, {x0, -0.2, -2 * kL}, {x1, 0.6, 0}, {nx, 3, 6});
  }
  slider.initial_temperature = block.initial_temperature = p.physics.reference_temperature;
  p.bodies.push_back(std::move(slider));
  p.bodies.push_back(std::move(block));

  const double delta = kPressure * kHeight / kSoft;
  const core::TimeTable press({0, tau}, {0, -delta});
  const core::TimeTable drag({0, tau, p.time.end}, {0, 0, kSpeed * (p.time.end - tau)});
  if (s.dim == 2)
    p.boundaries.push_back(displacement_bc(0, top, {{0, drag}, {1, press}}));
  else
    p.boundaries.push_back(displacement_bc(0, top, {{0, drag}, {1, 0.0}, {2, press}}));
  // The ends' shear ±𝔉p once the slide has begun (the first step presses in stick).
  if (s.friction > 0)
    for (const auto& [where, sign] : {std::pair{"xmax", 1.0}, std::pair{"xmin", -1.0}}) {
      physics::BoundaryCondition bc;
      bc.body = 0;
      bc.where = where;
      bc.traction[vd] = core::TimeTable({0, tau, 2 * tau}, {0, 0, sign * s.friction * kPressure});
      p.boundaries.push_back(bc);
    }
  if (s.dim == 2)
    p.boundaries.push_back(displacement_bc(1, bottom, {{0, 0.0}, {1, 0.0}}));
  else
    p.boundaries.push_back(displacement_bc(1, bottom, {{0, 0.0}, {1, 0.0}, {2, 0.0}}));
  auto c = contact_pair(0, bottom, 1, top, s.friction);
  c.heat_conduction = false;
  c.frictional_heating = false;
  p.contacts = {c};
  p.solver.qp_tolerance = 1e-10;
  p.solver.coupling_tolerance = 1e-8;
  p.solver.max_coupling_iterations = 50;
  return p;
}

Result run(const Settings& s) {
  const auto p = sliding_problem(s);
  physics::Simulation sim(p);
  sim.enable_mortar_contact();
  // The gap at the end of each step measured by a mortar pair of its own in the configuration
  // u^{k+1}: what the linearised constraint of the step left (0 at every node in contact).
  const std::string top = s.dim == 2 ? "ymax" : "zmax", bottom = s.dim == 2 ? "ymin" : "zmin";
  contact::MortarPair after(p.bodies[0].mesh, bottom, p.bodies[1].mesh, top);
  Result r;
  for (int k = 0; k <= s.steps; ++k) {
    sim.advance();
    const auto lambda = sim.contact_multipliers();
    const size_t n = sim.mortar()->contact_nodes().size();
    double lo = lambda[0], hi = lambda[0], sum = 0;
    for (size_t j = 0; j < n; ++j) {
      const double ln = lambda[static_cast<size_t>(s.dim) * j];
      lo = std::min(lo, ln);
      hi = std::max(hi, ln);
      sum += ln;
    }
    r.spread.push_back((hi - lo) / (sum / static_cast<double>(n)));
    after.update(sim.state(0).u.to_std(), sim.state(1).u.to_std());
    for (size_t j = 0; j < after.gap().size(); ++j)
      r.worst_gap = std::max(r.worst_gap, std::abs(after.gap()[j] / after.weights()[j]));
  }
  return r;
}

double worst(const std::vector<double>& v, size_t from, size_t to) {
  return *std::max_element(v.begin() + static_cast<std::ptrdiff_t>(from),
                           v.begin() + static_cast<std::ptrdiff_t>(to));
}

/// V τ = h/2 (the reference: a slide per step below a slave cell h/1.3), h and 2h over 100 slide
/// steps: the worst spread within 3 times the reference's, its growth from the first half of the
/// slide to the second within 1.5 times the reference's, and the end-of-step gap below the
/// block's dent.
void check_steps(Settings s, const char* what) {
  const double levels[] = {2, 1, 0.5};
  double reference = 0, reference_growth = 1;
  for (const double spc : levels) {
    s.steps_per_cell = spc;
    const auto r = run(s);
    const size_t n = r.spread.size(), half = n / 2;
    const double all = worst(r.spread, 1, n), first = worst(r.spread, 1, half),
                 second = worst(r.spread, half, n);
    std::printf(
        "[ measure  ] %s V τ = %.1f h: pressure spread worst %.2e (first half %.2e, second "
        "%.2e), end-of-step gap %.2e m (δ = %.1e m)\n",
        what, 1 / spc, all, first, second, r.worst_gap, kPressure * kHeight / kSoft);
    // What the step's linearisation leaves is second order in the slide's change between steps,
    // a fraction of the dent p l/E_b that moves with the slider (before the fix: 0.3 δ at V τ = h,
    // 3 δ at 2h).
    EXPECT_LT(r.worst_gap, kPressure * kL / kStiff) << what << " V τ = " << 1 / spc << " h";
    if (spc == 2) {
      reference = all;
      reference_growth = std::max(1.0, second / first);
      continue;
    }
    // The block's compliance sets the spread at every step size (2–10·10⁻⁴); 3 times the
    // reference's leaves room for where the dent falls against the cells. Before the fix the
    // spread at V τ = h and 2h grew by ~1.25 per step to 2.5 and 9 (separation) by step 60.
    // The quasistatic reference holds its spread (1.0 from the first half to the second); the
    // dynamic one's rises linearly at the slider's ends, at any V τ and before the fix too.
    EXPECT_LT(all, 3 * reference) << what << " V τ = " << 1 / spc << " h";
    EXPECT_LT(second / first, 1.5 * reference_growth) << what << " V τ = " << 1 / spc << " h";
  }
}

TEST(SlidingPressure, StaysUniformWhenAStepSlidesOneOrTwoCells2D) {
  check_steps({.dim = 2}, "2D frictionless");
  check_steps({.dim = 2, .friction = 0.5}, "2D 𝔉 = ½");
}

TEST(SlidingPressure, StaysUniformWhenAStepSlidesOneOrTwoCellsDynamic) {
  check_steps({.dim = 2, .dynamic = true}, "2D dynamic");
}

TEST(SlidingPressure, StaysUniformWhenAStepSlidesOneOrTwoCells3D) {
  // h = l/5 (13 × 2 × 2 slider cells): ~1 s per run.
  check_steps({.dim = 3, .h = 0.2}, "3D frictionless");
  check_steps({.dim = 3, .h = 0.2, .friction = 0.5}, "3D 𝔉 = ½");
}

}  // namespace
}  // namespace tc::test
