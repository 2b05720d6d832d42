#pragma once
// Probes (`[[probe]]`, physics::Probe): the point fields θ, u and v at a point of a body's
// reference configuration, interpolated by the shape functions of the cell that holds it, or
// averaged over the nodes of a boundary, one row per step in probes.csv (OutputWriter).
#include <optional>
#include <string>
#include <vector>

#include "tc/mesh/mesh.hpp"
#include "tc/model/problem.hpp"

namespace tc::physics {
class Simulation;
}

namespace tc::io {

/// Which nodes a probe reads and with what weights (Σ weights = 1).
struct ProbeStencil {
  int body = 0;
  std::vector<int> nodes;
  std::vector<double> weights;
};

/// The stencil of the point x of mesh m: the shape functions N_a(ξ) of the first cell whose
/// reference coordinates ξ(x) lie in the reference cell to 1e-10 (ξ by Newton's method on
/// x(ξ) = Σ_a N_a(ξ) x_a, exact in one step for simplices); nullopt when no cell holds it.
[[nodiscard]] std::optional<ProbeStencil> locate_point(const mesh::Mesh& m,
                                                       const std::array<double, 3>& x);

/// The stencils of a problem's probes, in order (a point no cell holds is an input error that
/// the case reader reports first; here it is an InternalError).
[[nodiscard]] std::vector<ProbeStencil> probe_stencils(const physics::Problem& p);

/// probes.csv's header: step, time, then per probe <name>_temperature, <name>_displacement_x
/// … and <name>_velocity_x … (x, y in 2D; z too in 3D).
[[nodiscard]] std::vector<std::string> probe_columns(const physics::Problem& p);

/// The row of the simulation's current step, matching probe_columns.
[[nodiscard]] std::vector<double> probe_row(const physics::Simulation& sim,
                                            const std::vector<ProbeStencil>& stencils);

}  // namespace tc::io
