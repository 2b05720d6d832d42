#pragma once
// The arrays of a VTK unstructured grid as both field formats write them (.vtu, vtu.hpp, and
// VTKHDF, vtkhdf.hpp): the points, the cells as point numbers with their end offsets and VTK
// types, and the point and cell fields, for a whole mesh or for the piece of it that some of
// its cells make. One builder, so that the two formats hold the same arrays by construction.
#include <cstdint>
#include <deque>
#include <vector>

#include "tc/io/vtk/vtu.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::io {

/// VTK's cell type number of `t` (VTK_HEXAHEDRON = 12, …; the quadratic cells in the node
/// order mesh/ keeps, reference_cell.hpp).
[[nodiscard]] int vtk_type(mesh::CellType t);

struct VtkGrid {
  std::vector<double> points;  // 3 per point (z = 0 in 2D)
  /// The cells' points in the grid's numbering; offsets[c] is where cell c ends (VTK XML's
  /// "offsets": the first cell starts at 0).
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  /// The fields as given, or their rows of a piece (kept in `owned`): the whole grid's fields
  /// are not copied (at 10⁶ dofs a frame's copy was a fifth of a GiB at the run's memory
  /// peak). Valid while the given fields live.
  std::vector<const Field*> point_data, cell_data;
  std::deque<Field> owned;
};

/// The whole mesh m with its fields.
[[nodiscard]] VtkGrid whole_grid(const mesh::Mesh& m, const std::vector<Field>& point_data,
                                 const std::vector<Field>& cell_data);

/// The cells `cells` of m as one piece: the points they use, renumbered in ascending order,
/// and the fields (given on the whole mesh) restricted to those points and cells.
[[nodiscard]] VtkGrid piece_grid(const mesh::Mesh& m, const std::vector<int>& cells,
                                 const std::vector<Field>& point_data,
                                 const std::vector<Field>& cell_data);

}  // namespace tc::io
