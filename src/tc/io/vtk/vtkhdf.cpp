#include "tc/io/vtk/vtkhdf.hpp"

#include <fmt/format.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "tc/core/error.hpp"
#include "tc/io/files/files.hpp"
#include "tc/io/vtk/vtk_grid.hpp"

#if TC_HAVE_HDF5
#include <hdf5.h>
#ifndef H5_HAVE_PARALLEL
#error "VTKHDF output needs a parallel HDF5 (H5_HAVE_PARALLEL): every rank writes its piece"
#endif
#endif

namespace tc::io {

#if !TC_HAVE_HDF5

bool vtkhdf_available() {
  return false;
}

std::string vtkhdf_library() {
  return "none";
}

void write_vtkhdf(const std::filesystem::path& file, const mesh::Mesh&, const std::vector<int>&,
                  const std::vector<Field>&, const std::vector<Field>&, MPI_Comm) {
  throw OutputError(
      fmt::format("cannot write {}: this thermocontact was built without HDF5", printable(file)));
}

#else

bool vtkhdf_available() {
  return true;
}

std::string vtkhdf_library() {
  return fmt::format("HDF5 {}.{}.{}, parallel (MPI-IO)", H5_VERS_MAJOR, H5_VERS_MINOR,
                     H5_VERS_RELEASE);
}

namespace {

/// An HDF5 identifier, closed by its own function when it goes out of scope. In parallel
/// HDF5 closing a file, a group or a data set is collective: every rank unwinds the same
/// handles in the same order, since every rank throws at the same point (Writer::check).
class Handle {
 public:
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  ~Handle() {
    if (id_ >= 0) (void)close_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  [[nodiscard]] hid_t id() const { return id_; }
  [[nodiscard]] bool valid() const { return id_ >= 0; }
  /// Closes it now; false when that fails (a file's last writes are reported here).
  [[nodiscard]] bool close() {
    const hid_t id = id_;
    id_ = -1;
    return id >= 0 && close_(id) >= 0;
  }

 private:
  hid_t id_;
  herr_t (*close_)(hid_t);
};

/// The innermost message of HDF5's error stack (its automatic printing is off), then cleared.
std::string hdf5_message() {
  std::string message;
  const auto walk = [](unsigned n, const H5E_error2_t* e, void* out) -> herr_t {
    if (n == 0 && e->desc) *static_cast<std::string*>(out) = e->desc;
    return 0;
  };
  (void)H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk, &message);
  (void)H5Eclear2(H5E_DEFAULT);
  return message.empty() ? "no reason given" : message;
}

/// The piece of every rank: its rows' counts and where they start in the file's data sets.
struct Layout {
  std::int64_t pieces = 0, piece = -1;                         // piece: this rank's, −1 if none
  std::int64_t points = 0, cells = 0, ids = 0;                 // totals over the pieces
  std::int64_t first_point = 0, first_cell = 0, first_id = 0;  // this rank's first rows
};

Layout layout_of(const VtkGrid& g, MPI_Comm comm) {
  int size = 1, rank = 0;
  MPI_Comm_size(comm, &size);
  MPI_Comm_rank(comm, &rank);
  const std::array<std::int64_t, 3> mine{static_cast<std::int64_t>(g.points.size() / 3),
                                         static_cast<std::int64_t>(g.types.size()),
                                         static_cast<std::int64_t>(g.connectivity.size())};
  std::vector<std::int64_t> all(3 * static_cast<size_t>(size));
  if (MPI_Allgather(mine.data(), 3, MPI_INT64_T, all.data(), 3, MPI_INT64_T, comm) != MPI_SUCCESS)
    throw OutputError("MPI_Allgather of the VTKHDF pieces' sizes failed");
  Layout l;
  for (int r = 0; r < size; ++r) {
    const auto* n = &all[3 * static_cast<size_t>(r)];
    if (n[1] == 0) continue;  // no cells, no piece (as in a .pvtu)
    if (r == rank) {
      l.piece = l.pieces;
      l.first_point = l.points;
      l.first_cell = l.cells;
      l.first_id = l.ids;
    }
    ++l.pieces;
    l.points += n[0];
    l.cells += n[1];
    l.ids += n[2];
  }
  return l;
}

/// One file being written collectively: every HDF5 call's failure is made every rank's
/// (check), so that no rank goes on into a collective call that the others have left.
class Writer {
 public:
  Writer(std::filesystem::path file, MPI_Comm comm) : file_(std::move(file)), comm_(comm) {}

  /// Throws OutputError on every rank when `ok` is false on any, with this rank's reason
  /// (`reason`, or HDF5's message when it is empty) where it failed.
  void check(bool ok, const char* what, std::string reason = "") const {
    if (!ok && reason.empty()) reason = hdf5_message();
    int mine = ok ? 1 : 0, all = 0;
    if (MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, comm_) != MPI_SUCCESS)
      throw OutputError(fmt::format("cannot write {}: MPI_Allreduce failed", printable(file_)));
    if (all == 1) return;
    if (ok) reason = "it failed on another rank";
    throw OutputError(fmt::format("cannot write {}: {}: {}", printable(file_), what, reason));
  }

  /// `n_rows` rows of `columns` values (0: a 1-D data set) at row `first` of the data set
  /// `name` of `total` rows in `group`, which every rank creates; this rank's rows written
  /// collectively (a rank without rows takes part with none).
  template <class T>
  void rows(hid_t group, const char* name, hid_t file_type, hid_t memory_type, const T* data,
            std::int64_t n_rows, std::int64_t first, std::int64_t total, int columns = 0) const {
    const int rank = columns > 0 ? 2 : 1;
    const std::array<hsize_t, 2> dims{static_cast<hsize_t>(total), static_cast<hsize_t>(columns)};
    const Handle space(H5Screate_simple(rank, dims.data(), nullptr), H5Sclose);
    check(space.valid(), name);
    // No fill value written before the data: every row is written once, by its rank.
    const Handle create(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
    check(create.valid() && H5Pset_fill_time(create.id(), H5D_FILL_TIME_NEVER) >= 0, name);
    const Handle set(
        H5Dcreate2(group, name, file_type, space.id(), H5P_DEFAULT, create.id(), H5P_DEFAULT),
        H5Dclose);
    check(set.valid(), name);
    const std::array<hsize_t, 2> start{static_cast<hsize_t>(first), 0},
        count{static_cast<hsize_t>(n_rows), static_cast<hsize_t>(columns)};
    const Handle selected(H5Dget_space(set.id()), H5Sclose);
    const std::array<hsize_t, 2> one{1, 1};
    const Handle memory(H5Screate_simple(rank, n_rows > 0 ? count.data() : one.data(), nullptr),
                        H5Sclose);
    bool ok = selected.valid() && memory.valid();
    if (ok && n_rows > 0)
      ok = H5Sselect_hyperslab(selected.id(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                               nullptr) >= 0;
    else if (ok)
      ok = H5Sselect_none(selected.id()) >= 0 && H5Sselect_none(memory.id()) >= 0;
    check(ok, name);
    const Handle transfer(H5Pcreate(H5P_DATASET_XFER), H5Pclose);
    check(transfer.valid() && H5Pset_dxpl_mpio(transfer.id(), H5FD_MPIO_COLLECTIVE) >= 0, name);
    const T none{};
    check(H5Dwrite(set.id(), memory_type, memory.id(), selected.id(), transfer.id(),
                   n_rows > 0 ? data : &none) >= 0,
          name);
  }

 private:
  std::filesystem::path file_;
  MPI_Comm comm_;
};

void write_attributes(const Writer& w, hid_t group) {
  // Version [1, 0]: every VTKHDF reader since ParaView 5.11 reads it (2.x adds time steps,
  // which the .pvd gives here); Type names the data set, as the 2.x readers look for it.
  const std::array<std::int64_t, 2> version{1, 0};
  const hsize_t two = 2;
  const Handle pair(H5Screate_simple(1, &two, nullptr), H5Sclose);
  const Handle v(H5Acreate2(group, "Version", H5T_STD_I64LE, pair.id(), H5P_DEFAULT, H5P_DEFAULT),
                 H5Aclose);
  w.check(v.valid() && H5Awrite(v.id(), H5T_NATIVE_INT64, version.data()) >= 0, "Version");
  const std::string type = "UnstructuredGrid";
  const Handle text(H5Tcopy(H5T_C_S1), H5Tclose);
  w.check(text.valid() && H5Tset_size(text.id(), type.size()) >= 0 &&
              H5Tset_strpad(text.id(), H5T_STR_NULLPAD) >= 0 &&
              H5Tset_cset(text.id(), H5T_CSET_ASCII) >= 0,
          "Type");
  const Handle scalar(H5Screate(H5S_SCALAR), H5Sclose);
  const Handle t(H5Acreate2(group, "Type", text.id(), scalar.id(), H5P_DEFAULT, H5P_DEFAULT),
                 H5Aclose);
  w.check(t.valid() && H5Awrite(t.id(), text.id(), type.c_str()) >= 0, "Type");
}

void write_fields(const Writer& w, hid_t parent, const char* group_name,
                  const std::vector<const Field*>& fields, std::int64_t rows, std::int64_t first,
                  std::int64_t total) {
  const Handle group(H5Gcreate2(parent, group_name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                     H5Gclose);
  w.check(group.valid(), group_name);
  for (const auto* f : fields)  // scalars as 1-D data sets, as VTK's own writer has them
    w.rows(group.id(), f->name.c_str(), H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, f->values.data(), rows,
           first, total, f->components == 1 ? 0 : f->components);
}

void write_grid(const Writer& w, hid_t file, const VtkGrid& g, const Layout& l) {
  const Handle root(H5Gcreate2(file, "VTKHDF", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  w.check(root.valid(), "VTKHDF");
  write_attributes(w, root.id());
  const hid_t at = root.id();
  const bool piece = l.piece >= 0;
  const std::int64_t n_points = piece ? static_cast<std::int64_t>(g.points.size() / 3) : 0;
  const std::int64_t n_cells = piece ? static_cast<std::int64_t>(g.types.size()) : 0;
  const std::int64_t n_ids = piece ? static_cast<std::int64_t>(g.connectivity.size()) : 0;
  const std::int64_t one = piece ? 1 : 0;
  w.rows(at, "NumberOfPoints", H5T_STD_I64LE, H5T_NATIVE_INT64, &n_points, one, l.piece, l.pieces);
  w.rows(at, "NumberOfCells", H5T_STD_I64LE, H5T_NATIVE_INT64, &n_cells, one, l.piece, l.pieces);
  w.rows(at, "NumberOfConnectivityIds", H5T_STD_I64LE, H5T_NATIVE_INT64, &n_ids, one, l.piece,
         l.pieces);
  w.rows(at, "Points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, g.points.data(), n_points, l.first_point,
         l.points, 3);
  w.rows(at, "Connectivity", H5T_STD_I64LE, H5T_NATIVE_INT64, g.connectivity.data(), n_ids,
         l.first_id, l.ids);
  // A piece's offsets begin with its first cell's start, 0 (the .vtu's list each cell's end).
  std::vector<std::int64_t> offsets;
  if (piece) {
    offsets.reserve(g.offsets.size() + 1);
    offsets.push_back(0);
    offsets.insert(offsets.end(), g.offsets.begin(), g.offsets.end());
  }
  w.rows(at, "Offsets", H5T_STD_I64LE, H5T_NATIVE_INT64, offsets.data(),
         static_cast<std::int64_t>(offsets.size()), l.first_cell + l.piece * one,
         l.cells + l.pieces);
  w.rows(at, "Types", H5T_STD_U8LE, H5T_NATIVE_UINT8, g.types.data(), n_cells, l.first_cell,
         l.cells);
  write_fields(w, at, "PointData", g.point_data, n_points, l.first_point, l.points);
  write_fields(w, at, "CellData", g.cell_data, n_cells, l.first_cell, l.cells);
}

}  // namespace

void write_vtkhdf(const std::filesystem::path& file, const mesh::Mesh& m,
                  const std::vector<int>& cells, const std::vector<Field>& point_data,
                  const std::vector<Field>& cell_data, MPI_Comm comm) {
  (void)H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are thrown, with their message
  // Open MPI's shared-file-pointer component "sm" (which HDF5 never uses) prints an error on
  // every open of a process started without mpirun (no session directory): the others are
  // taken instead. Read when the first file is opened; a user's own setting is kept.
  (void)::setenv("OMPI_MCA_sharedfp", "^sm", 0);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  const auto tmp = std::filesystem::path(file.string() + ".tmp");
  const Writer w(file, comm);
  // Created exclusively (MPI_MODE_EXCL, O_EXCL: a link planted under the name is refused, not
  // followed) once rank 0 has removed what had the name.
  if (rank == 0) remove_file(tmp);
  w.check(MPI_Barrier(comm) == MPI_SUCCESS, "MPI_Barrier");
  // All of the mesh in one piece is the whole grid, as the .vtu has it (with any point that no
  // cell uses); a part of it, the points of its cells (as a .pvtu piece).
  const auto grid = cells.size() == static_cast<size_t>(m.n_cells())
                        ? whole_grid(m, point_data, cell_data)
                        : piece_grid(m, cells, point_data, cell_data);
  const auto layout = layout_of(grid, comm);
  try {
    const Handle access(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    w.check(access.valid() && H5Pset_fapl_mpio(access.id(), comm, MPI_INFO_NULL) >= 0,
            "the MPI-IO file access");
    Handle out(H5Fcreate(tmp.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, access.id()), H5Fclose);
    w.check(out.valid(), "create");
    write_grid(w, out.id(), grid, layout);
    w.check(out.close(), "close");  // collective: every piece is in the file
  } catch (const OutputError&) {
    if (rank == 0) remove_file(tmp);  // a partial file is not left to be taken for a frame
    throw;
  }
  w.check(MPI_Barrier(comm) == MPI_SUCCESS, "MPI_Barrier");
  std::string failed;
  if (rank == 0) try {
      rename_file(tmp, file);
    } catch (const OutputError& e) {
      failed = e.what();
    }
  w.check(failed.empty(), "rename", failed);
}

#endif

}  // namespace tc::io
