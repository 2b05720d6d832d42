#pragma once
// Gmsh 4 (.msh) meshes through libgmsh: Tri3/Quad4 (2D) and Tet4/Hex8 (3D) cells, possibly
// mixed; every named physical group of dimension dim-1 becomes a boundary of that name.
#include <filesystem>

#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// Throws MeshError (naming the file) for unreadable files, unsupported element types,
/// boundary facets that bound no cell, and inverted or degenerate cells.
[[nodiscard]] Mesh read_gmsh(const std::filesystem::path& file, int dim);

}  // namespace tc::mesh
