#pragma once
// A contact pair's analytic rigid master (RigidTool) as the solver meets it: a held body of one
// cell whose face lies in the tool's plane (docs/choices.md, "A rigid tool as a held body").
// Every node of that cell is held on the tool's motion and temperature, so its rows are the
// mortar rows of a plane, B_m u_m = −(M1)_k n·d(t) = −D_kk n·d(t) where the face covers
// the slave (the dual basis' row sums), and the gap n·(x + u − p(t)) weighted by D alone; it
// has no mass and no heat capacity, so it adds nothing to the energies, and its supports'
// reaction is the force of the tool: its work is external work.
#include <string>

#include "tc/model/problem.hpp"

namespace tc::physics {

/// The name of the body that stands for pair c's rigid tool: "tool", or "tool_<name>".
[[nodiscard]] std::string rigid_tool_name(const ContactSettings& c);
/// The boundaries of that body: its face in the plane (the pair's master surface) and every
/// node (held on the motion and temperature; its reaction_<tool>_held_* columns are the force
/// of the drive on the tool).
inline constexpr const char* kRigidToolFace = "face";
inline constexpr const char* kRigidToolHeld = "held";

/// The unit normal of a tool's plane, from the case's `normal` (≠ 0; z ignored in 2D).
[[nodiscard]] std::array<double, 3> unit_normal(const std::array<double, 3>& normal, int dim);

/// The tool's sliding velocity at time t, its motion along its plane [m/s]: the slope of its
/// motion's tables on the segment that begins at or before t (the motion from t on), zero
/// beyond their ends (a `velocity` runs to time.end).
[[nodiscard]] std::array<double, 3> sliding_velocity(const RigidTool& tool, int dim, double t);

/// For every pair with a rigid master not placed yet (master_body < 0): appends its body and
/// its boundary condition to `p`, and points the pair's master at the body's face. The face is
/// a square (a segment in 2D) in the plane around the slave surface's shadow, its half-width
/// four times the shadow's radius plus the largest travel of the tool and of the slave body's
/// supports, so that it covers the slave throughout (a plane has no edge). An adiabatic tool
/// takes no heat: δ_C = 1 (γ_C^s = 1, γ_C^m = 0), no conduction.
void place_rigid_tools(Problem& p);

}  // namespace tc::physics
