#pragma once
// Meshes of other cell types on the corners of a first-order mesh: simplices cut out of
// Quad4/Hex8 cells, and second-order cells with nodes added on the edges (and the faces and
// centres of Quad9 and Hex27). Used by the box generator (box.hpp's element).
#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// Every Quad4 cut along its diagonal 0–2 into two Tri3, every Hex8 into six Tet4 around its
/// diagonal 0–6 (Kuhn's subdivision, conforming between cells numbered alike, as a box's
/// are); Tri3 and Tet4 cells are kept. Each boundary facet becomes the faces of the new
/// cells lying on it. Throws MeshError for a mesh with second-order cells.
[[nodiscard]] Mesh split_into_simplices(const Mesh& m);

/// Every first-order cell of m as the second-order type `target` on its corners (Tri6 from
/// Tri3, Quad8 or Quad9 from Quad4, Tet10 from Tet4, Hex20 or Hex27 from Hex8; target names
/// the choice for quadrilaterals and hexahedra, the simplices follow). New nodes sit at the
/// midpoints of straight edges and the centroids of faces and cells, numbered after m's
/// nodes, whose numbers are kept; boundary facets become the second-order faces.
[[nodiscard]] Mesh to_second_order(const Mesh& m, CellType target);

}  // namespace tc::mesh
