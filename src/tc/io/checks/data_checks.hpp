#pragma once
// Checks of a read case's time data against the time scheme that will integrate it: warnings
// only, for data the scheme follows but whose response a user would not expect.
#include <string>
#include <vector>

#include "tc/model/problem.hpp"

namespace tc::io {

/// With the dynamic scheme, each prescribed displacement whose velocity jumps: Newmark's average
/// acceleration updates u̇^{k+1} = 2Δu/τ − u̇^k, so after a jump Δv the prescribed dofs take
/// the step-to-step alternation ±Δv for ever (no numerical damping), and the body's stiff modes
/// and its reactions ring with them (docs/choices.md, "A jump in a prescribed velocity rings").
/// One warning per boundary component whose alternation exceeds 5 % of its largest speed.
[[nodiscard]] std::vector<std::string> check_time_data(const physics::Problem& p);

/// Each body whose M_θ is lumped by HRZ (heat_capacity = "lumped" on Tri6, Quad8, Tet10 or Hex20
/// cells) with a step short against its cells' conduction time, κτ/(ρc h²) < 1 for its largest
/// such cell: a source's heat then sits as f_a/m_a on nodes whose capacities m_a are not the
/// integrals ∫N_a the mechanics interpolates θ with, so the thermal expansion it drives is up to
/// Σ(∫N_a)²/m_a / Σ∫N_a times the heat's for a uniform source (on one reference cell: Hex20 9.6,
/// Quad8 2.8, Tet10 2.0, Tri6 1.2) until conduction evens the nodes out (docs/choices.md, "Mass of
/// second-order cells"). One warning per body.
[[nodiscard]] std::vector<std::string> check_lumped_capacity(const physics::Problem& p);

/// The alternation the trapezoidal velocity update leaves in the data d(t) over steps of τ from
/// u̇(0) = v0: max_k of |u̇^k − s_{k−1}| − |s_{k−1} − s_{k−2}| (s_k = the mean speed of step
/// k), which a smooth d(t) keeps ≤ 0 and a jump Δv at a step raises to |Δv|, two steps after
/// the jump; with the time t_{k+1} where it first appears, and the largest |s_k|. Stops two
/// steps past the table's last point, beyond which nothing changes.
struct RingingData {
  double alternation = 0;
  double at_time = 0;
  double max_speed = 0;
};
[[nodiscard]] RingingData trapezoidal_ringing(const core::TimeTable& d, double v0, double tau,
                                              int steps);

}  // namespace tc::io
