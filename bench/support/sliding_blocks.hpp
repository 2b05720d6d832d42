#pragma once
// The supports of the benchmarks' two-block sliding problems: the master (body 0) clamped at
// its lower face, the slave's (body 1) upper face held in x, pressed down by `depth` over
// [0, t_press] and then dragged along y by `slide` until `end`.
#include <utility>

#include "tc/core/table.hpp"
#include "tc/physics/problem.hpp"

namespace tc::bench {

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
