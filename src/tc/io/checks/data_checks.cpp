#include "tc/io/checks/data_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "tc/fem/assembler.hpp"

namespace tc::io {

RingingData trapezoidal_ringing(const core::TimeTable& d, double v0, double tau, int steps) {
  RingingData r;
  // Beyond the table's last point d is constant or linear: the speed no longer changes and the
  // alternation stays as it is, so two steps past it are enough (a run may have 10⁸ steps).
  const double last = d.times().empty() ? 0.0 : d.times().back();
  double v = v0, s_before = v0, s_last = v0;  // u̇^k, s_{k−2}, s_{k−1}
  for (int k = 0; k < steps && k * tau <= last + 2 * tau; ++k) {
    const double s = (d((k + 1) * tau) - d(k * tau)) / tau;
    r.max_speed = std::max(r.max_speed, std::abs(s));
    v = 2 * s - v;  // u̇^{k+1}
    s_before = s_last;
    s_last = s;
    // A smooth d keeps |u̇^{k+1} − s_k| ≤ |s_k − s_{k−1}| (half the step's change of speed, for a
    // parabola); what is above it alternates and stays.
    const double excess = std::abs(v - s_last) - std::abs(s_last - s_before);
    // The alternation stays once made, so a jump shows as the first value that more than
    // doubles the largest so far (round-off before it does not name the place).
    if (excess > 2 * r.alternation) r.at_time = (k + 1) * tau;
    r.alternation = std::max(r.alternation, excess);
  }
  return r;
}

std::vector<std::string> check_time_data(const physics::Problem& p) {
  std::vector<std::string> warnings;
  if (p.time.scheme != physics::Scheme::dynamic || p.time.step <= 0) return warnings;
  const int steps = p.time.n_steps();
  const char* axis = "xyz";
  for (const auto& b : p.boundaries)
    for (int c = 0; c < p.dimension; ++c) {
      const auto& table = b.displacement[static_cast<size_t>(c)];
      if (!table || table->is_constant()) continue;
      const auto& body = p.bodies[static_cast<size_t>(b.body)];
      const auto r = trapezoidal_ringing(*table, body.initial_velocity[static_cast<size_t>(c)],
                                         p.time.step, steps);
      if (r.max_speed > 0 && r.alternation > 0.05 * r.max_speed)
        warnings.push_back(fmt::format(
            "[[boundary]] of body '{}' where '{}': the prescribed displacement along {} jumps "
            "in velocity at t = {:g} s, by {:.3g} m/s (its largest speed {:.3g} m/s): Newmark's "
            "average acceleration (no numerical damping) then alternates the body's velocity "
            "by ±{:.3g} m/s from step to step, and its kinetic energy and reactions with it; "
            "positions, contact forces and heat are not affected. Ramp the velocity over a few "
            "steps to avoid it (docs/choices.md, \"A jump in a prescribed velocity rings\")",
            body.name, b.where, axis[c], r.at_time - 2 * p.time.step, r.alternation, r.max_speed,
            r.alternation));
    }
  return warnings;
}

namespace {

/// Σ(∫N_a)²/m_a over Σ∫N_a, from the mesh's row sums ∫N_a and lumped shares m_a: the factor by
/// which a uniform source's nodal temperatures f_a/m_a = s∫N_a/m_a overstate ∫θ_h.
double uniform_source_overstatement(const mesh::Mesh& m) {
  const auto w = fem::volume_integrals(m), v = fem::lumped_volumes(m);
  double driven = 0, heat = 0;
  for (size_t a = 0; a < w.size(); ++a) {
    driven += w[a] * w[a] / v[a];
    heat += w[a];
  }
  return driven / heat;
}

/// The largest extent along an axis of the cell's nodes: its size h for the conduction time.
double cell_extent(const mesh::Mesh& m, int c) {
  double extent = 0;
  for (int d = 0; d < m.dim(); ++d) {
    double lo = INFINITY, hi = -INFINITY;
    for (const int a : m.cell(c)) {
      lo = std::min(lo, m.point(a)[static_cast<size_t>(d)]);
      hi = std::max(hi, m.point(a)[static_cast<size_t>(d)]);
    }
    extent = std::max(extent, hi - lo);
  }
  return extent;
}

}  // namespace

std::vector<std::string> check_lumped_capacity(const physics::Problem& p) {
  std::vector<std::string> warnings;
  if (!p.physics.lumped_heat_capacity || p.time.step <= 0) return warnings;
  for (const auto& body : p.bodies) {
    if (body.rigid_tool || fem::lumps_by_row_sums(body.mesh)) continue;
    double h = 0;
    const char* type = "";
    for (int c = 0; c < body.mesh.n_cells(); ++c) {
      const auto t = body.mesh.cell_type(c);
      if (fem::lumps_by_row_sums(t)) continue;
      h = std::max(h, cell_extent(body.mesh, c));
      type = mesh::name(t);
    }
    const auto& mat = body.material;
    const double diffusivity = mat.thermal_conductivity / mat.heat_capacity();
    const double fourier = diffusivity * p.time.step / (h * h);
    if (!(fourier < 1.0)) continue;
    warnings.push_back(fmt::format(
        "body '{}': its {} cells lump the heat capacity by HRZ (heat_capacity = \"lumped\"), "
        "and the step is short for them: κτ/(ρc h²) = {:.3g} for its largest cell (h = {:.3g} "
        "m), below 1. Until conduction evens its nodes out (a few ρc h²/κ = {:.3g} s), the heat "
        "a source puts in (the thermoelastic term, a flux, friction) leaves the corners colder "
        "than the mid-edge nodes, and the thermal expansion it drives is up to {:.2g} times what "
        "the heat would give. Hex27 or Quad9 (or first-order) "
        "cells, heat_capacity = \"consistent\", or a step of at least {:.3g} s avoid it "
        "(docs/choices.md, \"Mass of second-order cells\")",
        body.name, type, fourier, h, h * h / diffusivity, uniform_source_overstatement(body.mesh),
        h * h / diffusivity));
  }
  return warnings;
}

}  // namespace tc::io
