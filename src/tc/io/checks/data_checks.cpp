#include "tc/io/checks/data_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

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

}  // namespace tc::io
