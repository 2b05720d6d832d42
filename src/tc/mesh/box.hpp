#pragma once
// Structured box meshes: Quad4 in 2D, Hex8 in 3D by default, or any other cell type of the
// dimension (simplices cut out of the boxes, second-order nodes added on the straight edges);
// boundaries named xmin xmax ymin ymax (zmin zmax in 3D).
#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// [min, max] cut into `cells` per axis; in 2D the z entries are ignored.
[[nodiscard]] Mesh make_box(int dim, const Point& min, const Point& max,
                            const std::array<int, 3>& cells);
/// The same box of `element` cells: Quad4, Quad8, Quad9, Tri3, Tri6 in 2D (each triangle pair
/// a cut box), Hex8, Hex20, Hex27, Tet4, Tet10 in 3D (six Kuhn tetrahedra per box). The corner
/// nodes keep make_box's numbers; MeshError when the element is not of the dimension.
[[nodiscard]] Mesh make_box(int dim, const Point& min, const Point& max,
                            const std::array<int, 3>& cells, CellType element);

}  // namespace tc::mesh
