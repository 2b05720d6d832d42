// make_box (and the simplex splits of tests/support/test_meshes.hpp): counts, lexicographic
// numbering, VTK cell orientation, outward boundary facets with the right owner cell, total
// measures, and conformity of the splits.
//
// Tolerances: box coordinates are i·h with h a ratio of small numbers, so every measure and
// normal is exact up to rounding; sums over ≤ 10³ O(1) terms lose ≲ 1e-13 relative, hence
// 1e-12, which any missing, duplicated or inverted cell or facet exceeds by far.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "support/test_meshes.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/box.hpp"

using namespace tc::mesh;
using V3 = std::array<double, 3>;

namespace {

V3 sub(const Point& a, const Point& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
V3 cross(const V3& a, const V3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const V3& a, const V3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
double norm(const V3& a) {
  return std::sqrt(dot(a, a));
}

Point centroid(const Mesh& m, std::span<const int> nodes) {
  Point c{0, 0, 0};
  for (const int n : nodes)
    for (int k = 0; k < 3; ++k) c[k] += m.point(n)[k] / static_cast<double>(nodes.size());
  return c;
}

/// Area-weighted normal of a facet (length = its measure): n = (t_y, −t_x)·|t|/|t| for Line2,
/// ½ Σ x_i × x_{i+1} for a planar polygon.
V3 facet_normal(const Mesh& m, const Facet& f) {
  const auto s = f.node_span();
  if (f.type == FacetType::Line2) {
    const V3 t = sub(m.point(s[1]), m.point(s[0]));
    return {t[1], -t[0], 0};
  }
  V3 n{0, 0, 0};
  for (size_t i = 0; i < s.size(); ++i) {
    const V3 c = cross(m.point(s[i]), m.point(s[(i + 1) % s.size()]));
    for (int k = 0; k < 3; ++k) n[k] += 0.5 * c[k];
  }
  return n;
}

const std::map<std::string, V3> kOutward = {{"xmin", {-1, 0, 0}}, {"xmax", {1, 0, 0}},
                                            {"ymin", {0, -1, 0}}, {"ymax", {0, 1, 0}},
                                            {"zmin", {0, 0, -1}}, {"zmax", {0, 0, 1}}};

/// Every facet: its owner contains its nodes, its normal is the boundary's outward unit axis
/// and points away from the owner's centroid; returns the total boundary measure.
double check_boundaries(const Mesh& m) {
  double total = 0;
  for (const auto& name : m.boundary_names()) {
    const V3 axis = kOutward.at(name);
    for (const auto& f : m.boundary(name)) {
      EXPECT_GE(f.cell, 0);
      const auto cell = m.cell(f.cell);
      for (const int n : f.node_span())
        EXPECT_NE(std::find(cell.begin(), cell.end(), n), cell.end()) << name;
      const V3 n = facet_normal(m, f);
      const double measure = norm(n);
      EXPECT_NEAR(dot(n, axis), measure, 1e-12 * measure) << name;  // parallel and outward
      EXPECT_GT(dot(n, sub(centroid(m, f.node_span()), centroid(m, cell))), 0) << name;
      total += measure;
    }
  }
  return total;
}

double total_measure(const Mesh& m) {
  double v = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const double mc = cell_measure(m, c);
    EXPECT_GT(mc, 0) << "cell " << c;
    v += mc;
  }
  return v;
}

/// Each facet of each cell, by its sorted nodes, with how many cells share it.
std::map<std::vector<int>, int> cell_faces(const Mesh& m) {
  std::map<std::vector<int>, int> count;
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto v = m.cell(c);
    std::vector<std::vector<int>> faces;
    if (m.cell_type(c) == CellType::Tri3) {
      faces = {{v[0], v[1]}, {v[1], v[2]}, {v[2], v[0]}};
    } else {
      faces = {{v[0], v[1], v[2]}, {v[0], v[1], v[3]}, {v[0], v[2], v[3]}, {v[1], v[2], v[3]}};
    }
    for (auto& f : faces) {
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  }
  return count;
}

/// Conforming: every simplex face is shared by two cells or is exactly one boundary facet.
void check_conforming(const Mesh& m) {
  std::set<std::vector<int>> boundary;
  for (const auto& name : m.boundary_names())
    for (const auto& f : m.boundary(name)) {
      std::vector<int> s(f.node_span().begin(), f.node_span().end());
      std::sort(s.begin(), s.end());
      EXPECT_TRUE(boundary.insert(s).second) << "facet listed twice";
    }
  for (const auto& [face, n] : cell_faces(m)) {
    EXPECT_LE(n, 2);
    EXPECT_EQ(n == 1, boundary.count(face) == 1);
  }
}

}  // namespace

TEST(MakeBox, Quad4CountsNumberingAndOrientation) {
  const int nx = 4, ny = 3;
  const auto m = make_box(2, {-1, 2, 0}, {3, 3.5, 0}, {nx, ny, 0});
  EXPECT_EQ(m.dim(), 2);
  ASSERT_EQ(m.n_nodes(), (nx + 1) * (ny + 1));
  ASSERT_EQ(m.n_cells(), nx * ny);
  // Lexicographic, x fastest.
  EXPECT_DOUBLE_EQ(m.point(1)[0], 0.0);
  EXPECT_DOUBLE_EQ(m.point(nx + 1)[1], 2.5);
  EXPECT_EQ(m.point(m.n_nodes() - 1), (Point{3, 3.5, 0}));
  // First cell: (0,0) (1,0) (1,1) (0,1), counter-clockwise.
  const auto c0 = m.cell(0);
  EXPECT_EQ(std::vector<int>(c0.begin(), c0.end()), (std::vector<int>{0, 1, nx + 2, nx + 1}));
  for (int c = 0; c < m.n_cells(); ++c) EXPECT_EQ(m.cell_type(c), CellType::Quad4);
  EXPECT_EQ(m.boundary_names(), (std::vector<std::string>{"xmax", "xmin", "ymax", "ymin"}));
  EXPECT_EQ(m.boundary("xmin").size(), size_t(ny));
  EXPECT_EQ(m.boundary("ymax").size(), size_t(nx));
  EXPECT_EQ(m.boundary_nodes("xmax").size(), size_t(ny + 1));
  EXPECT_NEAR(total_measure(m), 4.0 * 1.5, 1e-12);
  EXPECT_NEAR(check_boundaries(m), 2 * (4.0 + 1.5), 1e-12);  // perimeter
}

TEST(MakeBox, Hex8CountsNumberingAndOrientation) {
  const int nx = 3, ny = 2, nz = 4;
  const auto m = make_box(3, {0, 0, 0}, {1.5, 1, 2}, {nx, ny, nz});
  EXPECT_EQ(m.dim(), 3);
  ASSERT_EQ(m.n_nodes(), (nx + 1) * (ny + 1) * (nz + 1));
  ASSERT_EQ(m.n_cells(), nx * ny * nz);
  const int layer = (nx + 1) * (ny + 1);
  EXPECT_DOUBLE_EQ(m.point(layer)[2], 0.5);
  EXPECT_DOUBLE_EQ(m.point(nx + 1)[1], 0.5);
  // First cell: bottom face counter-clockwise (seen from +z), then the top face above it.
  const auto c0 = m.cell(0);
  const std::vector<int> bottom{0, 1, nx + 2, nx + 1};
  std::vector<int> expected = bottom;
  for (const int b : bottom) expected.push_back(b + layer);
  EXPECT_EQ(std::vector<int>(c0.begin(), c0.end()), expected);
  EXPECT_EQ(m.boundary_names().size(), 6u);
  EXPECT_EQ(m.boundary("xmin").size(), size_t(ny * nz));
  EXPECT_EQ(m.boundary("ymax").size(), size_t(nx * nz));
  EXPECT_EQ(m.boundary("zmin").size(), size_t(nx * ny));
  EXPECT_EQ(m.boundary_nodes("zmax").size(), size_t((nx + 1) * (ny + 1)));
  EXPECT_NEAR(total_measure(m), 3.0, 1e-12);
  EXPECT_NEAR(check_boundaries(m), 2 * (1.5 + 3.0 + 2.0), 1e-12);  // surface area
}

TEST(MakeBox, RejectsBadInput) {
  EXPECT_THROW((void)make_box(1, {0, 0, 0}, {1, 1, 1}, {1, 1, 1}), tc::MeshError);
  EXPECT_THROW((void)make_box(2, {0, 0, 0}, {1, 1, 1}, {0, 1, 1}), tc::MeshError);
  EXPECT_THROW((void)make_box(3, {0, 0, 1}, {1, 1, 1}, {1, 1, 1}), tc::MeshError);
}

TEST(SplitMeshes, TrianglesAreConformingOrientedAndKeepBoundaries) {
  const auto q = make_box(2, {0, 0, 0}, {2, 1, 0}, {3, 2, 0});
  const auto m = tc::test::split_quads(q);
  EXPECT_EQ(m.n_cells(), 2 * q.n_cells());
  EXPECT_EQ(m.boundary("ymin").size(), q.boundary("ymin").size());
  EXPECT_NEAR(total_measure(m), 2.0, 1e-12);
  EXPECT_NEAR(check_boundaries(m), 6.0, 1e-12);
  check_conforming(m);
}

TEST(SplitMeshes, TetrahedraAreConformingOrientedAndKeepBoundaries) {
  const auto h = make_box(3, {0, 0, 0}, {1, 2, 1}, {2, 3, 2});
  const auto m = tc::test::split_hexes(h);
  EXPECT_EQ(m.n_cells(), 6 * h.n_cells());
  for (const auto& name : h.boundary_names())
    EXPECT_EQ(m.boundary(name).size(), 2 * h.boundary(name).size()) << name;
  EXPECT_NEAR(total_measure(m), 2.0, 1e-12);
  EXPECT_NEAR(check_boundaries(m), 2 * (2.0 + 1.0 + 2.0), 1e-12);
  check_conforming(m);
}

TEST(SplitMeshes, PerturbationMovesOnlyInteriorNodesAndKeepsCellsValid) {
  const auto h = make_box(3, {0, 0, 0}, {1, 1, 1}, {4, 4, 4});
  const auto m = tc::test::perturb(tc::test::split_hexes(h), 0.05);
  const auto boundary = tc::test::all_boundary_nodes(m);
  int moved = 0;
  for (int i = 0; i < m.n_nodes(); ++i) {
    const bool on_boundary = std::binary_search(boundary.begin(), boundary.end(), i);
    if (m.point(i) != h.point(i)) {
      ++moved;
      EXPECT_FALSE(on_boundary) << i;
    }
  }
  EXPECT_EQ(moved, 27);                       // the 3³ interior nodes
  EXPECT_NEAR(total_measure(m), 1.0, 1e-12);  // the box is unchanged, cells stay positive
}
