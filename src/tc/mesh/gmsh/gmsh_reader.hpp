#pragma once
// Gmsh 4 (.msh) meshes through libgmsh: Tri3/Quad4 (2D) and Tet4/Hex8 (3D) cells, possibly
// mixed; every named physical group of dimension dim-1 becomes a boundary of that name.
#include <cstddef>
#include <filesystem>
#include <string>
#include <unordered_map>
#include <vector>

#include "tc/mesh/mesh.hpp"

namespace tc::mesh {

/// Throws MeshError (naming the file) for unreadable files, unsupported element types,
/// boundary facets that bound no cell, and inverted or degenerate cells.
[[nodiscard]] Mesh read_gmsh(const std::filesystem::path& file, int dim);

namespace detail {

/// What read_gmsh copies out of libgmsh before building the Mesh without it.
struct RawBlock {
  int type = 0;                    // gmsh element type
  std::vector<std::size_t> nodes;  // gmsh node tags, n_nodes(type) per element
};

struct RawGroup {
  std::string name;
  std::vector<RawBlock> blocks;
  int tag = -1;  // gmsh's physical tag (kept for the cell groups)
};

struct RawMesh {
  std::vector<std::size_t> node_tags;
  std::vector<double> coords;  // 3 per node tag
  std::vector<RawBlock> cells;
  std::vector<RawGroup> groups;                     // named groups of dimension dim − 1
  std::vector<RawGroup> cell_groups;                // groups of dimension dim, named or not
  std::unordered_map<int, std::string> type_names;  // gmsh's name of every type seen
};

/// The first half of read_gmsh (gmsh_parse.cpp): refuses a file whose first line is not
/// `$MeshFormat` (MeshError naming `where`) without reading more than 4 KiB ...
void check_header(const std::filesystem::path& file, const std::string& where);
/// ... then parses it with libgmsh in a forked child and returns what libgmsh saw (MeshError
/// when the child fails, crashes or is stopped).
[[nodiscard]] RawMesh read_raw_isolated(const std::filesystem::path& file, int dim);

/// The second half of read_gmsh, our own code: numbering, cells, checks, boundaries (exposed
/// for tests/fuzz/fuzz_gmsh_layer, which fuzzes it without libgmsh). Throws MeshError.
[[nodiscard]] Mesh build_mesh(const RawMesh& raw, int dim, const std::string& file);

}  // namespace detail

}  // namespace tc::mesh
