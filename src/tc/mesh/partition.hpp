#pragma once
// Non-overlapping decomposition of a body's mesh into subdomains (6.2): the cells are split
// by METIS on the dual graph (cells adjacent through a facet), each part kept contiguous so
// that a floating subdomain has exactly the kernel of the whole operator (rigid motions,
// constants). Nodes on part boundaries belong to every part that has a cell at them.
#include <vector>

#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// One subdomain: its own mesh (cells only, no boundaries) and the maps to the body's.
struct SubMesh {
  Mesh mesh;
  std::vector<int> global_node;  // local node → body node
  std::vector<int> global_cell;  // local cell → body cell
};

/// The part (0 … parts − 1) of every cell. `parts` = 1 gives all zeros; otherwise METIS
/// (PartMeshDual, contiguous parts). Throws MeshError when a part would be empty.
[[nodiscard]] std::vector<int> partition_cells(const Mesh& m, int parts);

/// The subdomains of a cell partition, in part order.
[[nodiscard]] std::vector<SubMesh> split(const Mesh& m, const std::vector<int>& cell_part,
                                         int parts);

}  // namespace tc::mesh
