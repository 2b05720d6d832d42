// The VTKHDF writer (io/vtk/vtkhdf.hpp) on one rank: the file read back through HDF5's C API
// (tests/support/vtk_files.hpp) holds the arrays of the ASCII .vtu of the same mesh and fields
// bit for bit (points, connectivity, offsets, types, every point and cell array), in the
// layout VTK's reader expects (Version, Type, the pieces' sizes); a piece as the .vtu piece;
// a link planted under the file's name is replaced, never followed, and no temporary file is
// left. The 2-rank writes are tests/mpi/io_vtkhdf_ranks_test.cpp.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <limits>

#include "support/cli.hpp"
#include "support/vtk_files.hpp"
#include "tc/core/error.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/io/vtk/vtu.hpp"

using namespace tc;

namespace {

/// A 2D mesh of both cell types: 2 × 12 quads and a row of triangles on top.
mesh::Mesh mixed_mesh() {
  mesh::Mesh m(2);
  const int nx = 12;
  for (int j = 0; j <= 3; ++j)
    for (int i = 0; i <= nx; ++i) m.add_point({i / 3.0, j * 0.1 + 1e-17 * i, 0.0});
  const auto id = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < nx; ++i) {
      const std::array<int, 4> q{id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)};
      m.add_cell(mesh::CellType::Quad4, q);
    }
  for (int i = 0; i < nx; ++i) {
    const std::array<int, 3> t{id(i, 2), id(i + 1, 2), id(i + 1, 3)};
    m.add_cell(mesh::CellType::Tri3, t);
  }
  return m;
}

/// Values that a short decimal form does not hold exactly: thirds, extremes, subnormals, −0.
double awkward(size_t i) {
  switch (i % 6) {
    case 0:
      return 1.0 / 3.0 + static_cast<double>(i);
    case 1:
      return -0.0;
    case 2:
      return std::numeric_limits<double>::denorm_min() * static_cast<double>(i);
    case 3:
      return std::numeric_limits<double>::max() / static_cast<double>(i + 1);
    case 4:
      return -std::exp(-static_cast<double>(i));
    default:
      return std::nextafter(1.0, 2.0) * static_cast<double>(i);
  }
}

io::Field field(const std::string& name, int components, size_t rows) {
  io::Field f{name, components, {}};
  for (size_t i = 0; i < rows * static_cast<size_t>(components); ++i)
    f.values.push_back(awkward(i + name.size()));
  return f;
}

/// Every array of `a` in `b`, same type, components and bytes, and no other.
void expect_same(const test::VtkArrays& a, const test::VtkArrays& b) {
  EXPECT_EQ(a.size(), b.size());
  for (const auto& [key, array] : a) {
    ASSERT_EQ(b.count(key), 1u) << key;
    EXPECT_EQ(array.type, b.at(key).type) << key;
    EXPECT_EQ(array.components, b.at(key).components) << key;
    EXPECT_EQ(array.bytes.size(), b.at(key).bytes.size()) << key;
    EXPECT_TRUE(array.bytes == b.at(key).bytes) << key;  // to the bit
  }
}

struct Frame {
  mesh::Mesh mesh = mixed_mesh();
  std::vector<io::Field> point{field("temperature", 1, static_cast<size_t>(mesh.n_nodes())),
                               field("displacement", 3, static_cast<size_t>(mesh.n_nodes()))};
  std::vector<io::Field> cell{field("von_mises_stress", 1, static_cast<size_t>(mesh.n_cells())),
                              field("stress", 9, static_cast<size_t>(mesh.n_cells()))};
};

std::vector<int> all_cells(const mesh::Mesh& m) {
  std::vector<int> c(static_cast<size_t>(m.n_cells()));
  for (size_t i = 0; i < c.size(); ++i) c[i] = static_cast<int>(i);
  return c;
}

#if TC_HAVE_HDF5

TEST(VtkHdf, HoldsTheAsciiVtuArraysToTheBit) {
  ASSERT_TRUE(io::vtkhdf_available());
  const Frame f;
  const auto dir = test::fresh_dir("vtkhdf");
  io::write_vtu(dir / "a.vtu", f.mesh, f.point, f.cell, io::VtuEncoding::ascii);
  io::write_vtkhdf(dir / "a.vtkhdf", f.mesh, all_cells(f.mesh), f.point, f.cell, MPI_COMM_WORLD);
  const auto h = test::read_vtkhdf(dir / "a.vtkhdf");
  EXPECT_EQ(h.version, (std::vector<long long>{1, 0}));
  EXPECT_EQ(h.type, "UnstructuredGrid");
  const auto n = static_cast<std::int64_t>(f.mesh.n_nodes());
  const auto c = static_cast<std::int64_t>(f.mesh.n_cells());
  EXPECT_EQ(h.n_points, (std::vector<std::int64_t>{n}));
  EXPECT_EQ(h.n_cells, (std::vector<std::int64_t>{c}));
  EXPECT_EQ(h.n_ids, (std::vector<std::int64_t>{4 * 24 + 3 * 12}));
  // The offsets are VTKHDF's: c + 1 of them, from 0.
  ASSERT_EQ(h.arrays.at("Cells/offsets").rows(), static_cast<size_t>(c + 1));
  EXPECT_EQ(h.arrays.at("Cells/offsets").value(0), 0.0);
  expect_same(test::read_ascii_vtu(dir / "a.vtu"), h.piece(0));
  // And the values are the ones given, not only the same in both files.
  const auto& u = h.arrays.at("PointData/displacement");
  EXPECT_EQ(u.components, 3);
  EXPECT_EQ(std::memcmp(u.bytes.data(), f.point[1].values.data(), u.bytes.size()), 0);
  EXPECT_EQ(h.arrays.at("PointData/temperature").components, 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "a.vtkhdf.tmp"));
}

TEST(VtkHdf, APieceHoldsTheAsciiPiece) {
  const Frame f;
  const std::vector<int> cells{3, 7, 20, 30, 35};  // quads and triangles, points not contiguous
  const auto dir = test::fresh_dir("vtkhdf-piece");
  io::write_vtu_piece(dir / "p.vtu", f.mesh, cells, f.point, f.cell, io::VtuEncoding::ascii);
  io::write_vtkhdf(dir / "p.vtkhdf", f.mesh, cells, f.point, f.cell, MPI_COMM_WORLD);
  const auto h = test::read_vtkhdf(dir / "p.vtkhdf");
  ASSERT_EQ(h.n_cells, (std::vector<std::int64_t>{5}));
  expect_same(test::read_ascii_vtu(dir / "p.vtu"), h.piece(0));
  EXPECT_EQ(h.arrays.at("CellData/stress").rows(), 5u);
}

TEST(VtkHdf, ALinkUnderItsNameIsReplacedNotFollowed) {
  const Frame f;
  const auto dir = test::fresh_dir("vtkhdf-link");
  const auto outside = dir / "outside.txt";
  std::ofstream(outside) << "not to be overwritten\n";
  std::filesystem::create_symlink(outside, dir / "f.vtkhdf");
  std::filesystem::create_symlink(outside, dir / "f.vtkhdf.tmp");  // a killed run's, or planted
  io::write_vtkhdf(dir / "f.vtkhdf", f.mesh, all_cells(f.mesh), f.point, f.cell, MPI_COMM_WORLD);
  EXPECT_EQ(test::read_file(outside), "not to be overwritten\n");
  EXPECT_TRUE(std::filesystem::is_regular_file(std::filesystem::symlink_status(dir / "f.vtkhdf")));
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(dir / "f.vtkhdf.tmp")));
  EXPECT_EQ(test::read_vtkhdf(dir / "f.vtkhdf").n_cells.size(), 1u);
}

TEST(VtkHdf, AFileThatCannotBeCreatedIsAnOutputErrorNamingIt) {
  const Frame f;
  const auto file = test::fresh_dir("vtkhdf-missing") / "no-such-dir" / "f.vtkhdf";
  try {
    io::write_vtkhdf(file, f.mesh, all_cells(f.mesh), f.point, f.cell, MPI_COMM_WORLD);
    FAIL() << "written into a directory that does not exist";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(file.parent_path()));
}

#else

TEST(VtkHdf, RefusedWithoutHdf5) {
  EXPECT_FALSE(io::vtkhdf_available());
  const Frame f;
  EXPECT_THROW(io::write_vtkhdf(test::fresh_dir("vtkhdf-none") / "a.vtkhdf", f.mesh,
                                all_cells(f.mesh), f.point, f.cell, MPI_COMM_WORLD),
               OutputError);
}

#endif

}  // namespace
