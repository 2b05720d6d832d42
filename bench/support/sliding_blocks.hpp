#pragma once
// The benchmarks' two-block sliding problems: two steel bodies, the master (body 0) clamped at
// its lower face, the slave's (body 1) upper face held in x, pressed down by `depth` over
// [0, t_press] and then dragged along y by `slide` until `end`.
#include <utility>

#include "../../tests/support/problems.hpp"  // steel(): the constants the tests use
#include "tc/core/table.hpp"
#include "tc/mesh/mesh.hpp"
#include "tc/model/problem.hpp"

namespace tc::bench {

/// Quasistatic, mechanical only (no thermal expansion or heating), `steps` steps of 0.1 s; each
/// body cut into `subdomains` (FETI when > 1). The supports: clamp_and_drag.
inline physics::Problem two_steel_blocks(mesh::Mesh master, mesh::Mesh slave, int steps,
                                         int subdomains = 1) {
  physics::Problem p;
  p.dimension = 3;
  p.time.scheme = physics::Scheme::quasistatic;
  p.time.step = 0.1;
  p.time.end = 0.1 * steps;
  p.physics.thermal_expansion = false;
  p.physics.thermoelastic_heating = false;
  for (auto [name, m] : {std::pair{"master", &master}, {"slave", &slave}}) {
    physics::Body body;
    body.name = name;
    body.material = test::steel();
    body.mesh = std::move(*m);
    body.initial_temperature = p.physics.reference_temperature;
    body.subdomains = subdomains;
    p.bodies.push_back(std::move(body));
  }
  return p;
}

inline void clamp_and_drag(physics::Problem& p, double t_press, double depth, double end,
                           double slide) {
  physics::BoundaryCondition clamp;
  clamp.body = 0;
  clamp.where = "zmin";
  for (auto& d : clamp.displacement) d = core::TimeTable(0.0);
  p.boundaries.push_back(std::move(clamp));
  physics::BoundaryCondition top;
  top.body = 1;
  top.where = "zmax";
  top.displacement[0] = core::TimeTable(0.0);
  top.displacement[1] = core::TimeTable({0.0, t_press, end}, {0.0, 0.0, slide});
  top.displacement[2] = core::TimeTable({0.0, t_press}, {0.0, -depth});
  p.boundaries.push_back(std::move(top));
}

}  // namespace tc::bench
