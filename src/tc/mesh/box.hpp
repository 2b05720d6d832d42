#pragma once
// Structured box meshes: Quad4 in 2D, Hex8 in 3D, boundaries named xmin xmax ymin ymax
// (zmin zmax in 3D).
#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// [min, max] cut into `cells` per axis; in 2D the z entries are ignored.
[[nodiscard]] Mesh make_box(int dim, const Point& min, const Point& max,
                            const std::array<int, 3>& cells);

}  // namespace tc::mesh
