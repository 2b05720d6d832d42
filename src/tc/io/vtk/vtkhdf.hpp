#pragma once
// VTKHDF unstructured grids (`[output] format = "vtkhdf"`): one HDF5 file per body and output
// step, written collectively by every rank through parallel HDF5 (MPI-IO), each rank's cells
// one piece of it, in the layout VTK's vtkHDFReader reads (ParaView ≥ 5.11; VTK's
// "VTKHDF File Format", version 1.0):
//   /VTKHDF                      attributes Version = [1, 0], Type = "UnstructuredGrid"
//     NumberOfPoints, NumberOfCells, NumberOfConnectivityIds    Int64 [pieces]
//     Points                     Float64 [points, 3]
//     Connectivity               Int64 [ids]       each piece's cells in its own point numbers
//     Offsets                    Int64 [cells + pieces]  each piece's cell starts, 0 first
//     Types                      UInt8 [cells]
//     PointData/<name>, CellData/<name>   Float64 [rows] or [rows, components]
// the pieces' rows one after the other in rank order (a rank without cells has no piece).
// The arrays are those of the .vtu (vtk_grid.hpp), so the two formats hold the same values.
#include <mpi.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tc/io/vtk/vtu.hpp"
#include "tc/mesh/mesh.hpp"

namespace tc::io {

/// The files of the fields (`[output] format`): a .vtu per body and written step (a .pvtu and
/// a piece per rank on more ranks), or one VTKHDF file per body and written step from all
/// ranks (write_vtkhdf).
enum class FieldFiles { vtu, vtkhdf };

/// True when this build has parallel HDF5 (found at configure time): `format = "vtkhdf"` is
/// refused by the case reader otherwise.
[[nodiscard]] bool vtkhdf_available();

/// The HDF5 library this build writes with ("HDF5 1.10.8, parallel"), or "none".
[[nodiscard]] std::string vtkhdf_library();

/// Writes `file` from the cells `cells` of m that this rank owns (its piece; may be empty),
/// with the fields given on the whole mesh. Collective over `comm`: every rank calls it with
/// the same file and field names. The file is written as `file`.tmp and renamed to `file`
/// once every rank's piece is in it and it is closed, so `file` is whole whenever it exists;
/// whatever had either name before (a file of a killed run, a planted link) is removed first
/// and the temporary file created exclusively. Throws OutputError (on every rank) when the
/// file cannot be written, or when the build has no HDF5.
void write_vtkhdf(const std::filesystem::path& file, const mesh::Mesh& m,
                  const std::vector<int>& cells, const std::vector<Field>& point_data,
                  const std::vector<Field>& cell_data, MPI_Comm comm);

}  // namespace tc::io
