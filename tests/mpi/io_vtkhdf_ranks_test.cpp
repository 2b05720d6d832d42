// The VTKHDF writer (io/vtk/vtkhdf.hpp) on every rank at once (label mpi, 1 and 2 ranks):
// each rank writes its block of a mesh's cells into one file collectively; read back (HDF5's C
// API, serially, tests/support/vtk_files.hpp), the file has one piece per rank with cells,
// in rank order, and every piece's points, cells and point and cell values are those of the
// whole mesh at the same points and cells, bit for bit (matched by coordinates, not by the
// writer's numbering). A rank without cells takes part and writes no piece.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <map>
#include <set>

#include "support/cli.hpp"
#include "support/vtk_files.hpp"
#include "tc/core/error.hpp"
#include "tc/core/numeric/petsc.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/mesh/box.hpp"

namespace tc::test {
namespace {

#if TC_HAVE_HDF5

int rank() {
  return core::PetscSession::rank();
}
int size() {
  return core::PetscSession::size();
}

/// A directory every rank writes into: rank 0's fresh one, its name sent to the others.
std::filesystem::path shared_dir(const std::string& name) {
  std::string path = rank() == 0 ? fresh_dir(name).string() : "";
  int length = static_cast<int>(path.size());
  MPI_Bcast(&length, 1, MPI_INT, 0, PETSC_COMM_WORLD);
  path.resize(static_cast<size_t>(length));
  MPI_Bcast(path.data(), length, MPI_CHAR, 0, PETSC_COMM_WORLD);
  return path;
}

/// Values that differ at every point and cell and that a decimal form would round.
double value_at(const std::array<double, 3>& x, int k) {
  return (x[0] + 1.0 / 3.0) * (k + 1) - x[1] / 7.0 + 1e-300 * x[2] * k;
}

struct Frame {
  mesh::Mesh mesh = mesh::make_box(3, {0.0, 0.0, 0.0}, {1.0, 0.7, 0.4}, {5, 4, 3});
  std::vector<io::Field> point, cell;
  Frame() {
    io::Field t{"temperature", 1, {}}, u{"displacement", 3, {}};
    for (int a = 0; a < mesh.n_nodes(); ++a) {
      t.values.push_back(value_at(mesh.point(a), 7));
      for (int k = 0; k < 3; ++k) u.values.push_back(value_at(mesh.point(a), k));
    }
    io::Field s{"stress", 9, {}}, id{"subdomain", 1, {}};
    for (int c = 0; c < mesh.n_cells(); ++c) {
      for (int k = 0; k < 9; ++k) s.values.push_back(c * 10.0 + k / 3.0);
      id.values.push_back(c);
    }
    point = {t, u};
    cell = {s, id};
  }
};

/// The coordinates' bytes: the key a point is matched by.
std::string key(const double* x) {
  return std::string(reinterpret_cast<const char*>(x), 24);
}

/// Every piece of `file` against the whole mesh: each point's and cell's values equal to the
/// mesh's at the same coordinates (cells by their sorted point keys), every cell in one piece.
void expect_pieces_hold_the_mesh(const std::filesystem::path& file, const Frame& f, size_t pieces) {
  const auto h = read_vtkhdf(file);
  ASSERT_EQ(h.n_cells.size(), pieces);
  std::map<std::string, int> node;
  for (int a = 0; a < f.mesh.n_nodes(); ++a) node[key(f.mesh.point(a).data())] = a;
  std::map<std::string, int> cell;
  const auto cell_key = [](std::vector<std::string> keys) {
    std::sort(keys.begin(), keys.end());
    std::string k;
    for (const auto& s : keys) k += s;
    return k;
  };
  for (int c = 0; c < f.mesh.n_cells(); ++c) {
    std::vector<std::string> keys;
    for (const int a : f.mesh.cell(c)) keys.push_back(key(f.mesh.point(a).data()));
    cell[cell_key(keys)] = c;
  }
  std::set<int> seen;
  for (size_t p = 0; p < pieces; ++p) {
    const auto piece = h.piece(p);
    const auto& x = piece.at("Points");
    std::vector<int> global;  // the piece's points in the mesh
    for (size_t i = 0; i < x.rows(); ++i) {
      const auto it = node.find(std::string(reinterpret_cast<const char*>(&x.bytes[24 * i]), 24));
      ASSERT_NE(it, node.end()) << "piece " << p << " point " << i;
      global.push_back(it->second);
      for (const auto& fd : f.point) {
        const auto& mine = piece.at("PointData/" + fd.name);
        EXPECT_EQ(std::memcmp(&mine.bytes[8 * fd.components * i],
                              &fd.values[static_cast<size_t>(fd.components * it->second)],
                              8 * static_cast<size_t>(fd.components)),
                  0)
            << fd.name << " piece " << p << " point " << i;
      }
    }
    const auto& conn = piece.at("Cells/connectivity");
    const auto& ends = piece.at("Cells/offsets");
    size_t begin = 0;
    for (size_t c = 0; c < ends.rows(); ++c) {
      std::vector<std::string> keys;
      const auto end = static_cast<size_t>(ends.value(c));
      for (size_t i = begin; i < end; ++i)
        keys.push_back(key(f.mesh.point(global[static_cast<size_t>(conn.value(i))]).data()));
      begin = end;
      const auto it = cell.find(cell_key(keys));
      ASSERT_NE(it, cell.end()) << "piece " << p << " cell " << c;
      EXPECT_TRUE(seen.insert(it->second).second) << "cell " << it->second << " twice";
      EXPECT_EQ(piece.at("Cells/types").value(c), 12.0);  // VTK_HEXAHEDRON
      for (const auto& fd : f.cell) {
        const auto& mine = piece.at("CellData/" + fd.name);
        EXPECT_EQ(std::memcmp(&mine.bytes[8 * fd.components * c],
                              &fd.values[static_cast<size_t>(fd.components * it->second)],
                              8 * static_cast<size_t>(fd.components)),
                  0)
            << fd.name << " piece " << p << " cell " << c;
      }
    }
  }
  EXPECT_EQ(seen.size(), static_cast<size_t>(f.mesh.n_cells()));
}

TEST(VtkHdfRanks, EveryRankWritesItsPieceOfOneFile) {
  const Frame f;
  const auto dir = shared_dir("vtkhdf-ranks");
  const int n = f.mesh.n_cells();
  std::vector<int> mine;  // contiguous blocks, as FETI deals subdomains
  for (int c = n * rank() / size(); c < n * (rank() + 1) / size(); ++c) mine.push_back(c);
  io::write_vtkhdf(dir / "f.vtkhdf", f.mesh, mine, f.point, f.cell, PETSC_COMM_WORLD);
  if (rank() == 0) expect_pieces_hold_the_mesh(dir / "f.vtkhdf", f, static_cast<size_t>(size()));
  MPI_Barrier(PETSC_COMM_WORLD);
}

TEST(VtkHdfRanks, ARankWithoutCellsWritesNoPiece) {
  const Frame f;
  const auto dir = shared_dir("vtkhdf-ranks-empty");
  std::vector<int> mine;
  if (rank() == size() - 1)  // the last rank has all of them (an undecomposed body)
    for (int c = 0; c < f.mesh.n_cells(); ++c) mine.push_back(c);
  io::write_vtkhdf(dir / "f.vtkhdf", f.mesh, mine, f.point, f.cell, PETSC_COMM_WORLD);
  if (rank() == 0) expect_pieces_hold_the_mesh(dir / "f.vtkhdf", f, 1);
  MPI_Barrier(PETSC_COMM_WORLD);
}

TEST(VtkHdfRanks, AFailureIsEveryRanksError) {
  // A directory that does not exist: the creation fails on every rank, and every rank throws
  // (none is left waiting in a collective call).
  const Frame f;
  const auto dir = shared_dir("vtkhdf-ranks-fail");
  std::vector<int> mine;
  if (rank() == 0)
    for (int c = 0; c < f.mesh.n_cells(); ++c) mine.push_back(c);
  EXPECT_THROW(io::write_vtkhdf(dir / "missing" / "f.vtkhdf", f.mesh, mine, f.point, f.cell,
                                PETSC_COMM_WORLD),
               OutputError);
  MPI_Barrier(PETSC_COMM_WORLD);
}

#else

TEST(VtkHdfRanks, NotBuilt) {
  GTEST_SKIP() << "built without HDF5";
}

#endif

}  // namespace
}  // namespace tc::test
