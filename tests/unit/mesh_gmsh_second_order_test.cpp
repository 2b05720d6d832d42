// read_gmsh on second-order meshes made here with the gmsh API: Tri6, Quad8, Quad9 (2D),
// Tet10, Hex20, Hex27 (3D), each written as MSH 4.1 and MSH 2.2 and read to the same mesh.
// Gmsh's node order differs from VTK's (Tet10, Hex20, Hex27): the test checks every node of
// every cell geometrically. On straight-edged cells node a of a second-order cell is where the
// cell's corners put reference node a (x_a = Σ_j L_j(ξ_a) x_j with the first-order functions
// L_j), which holds for one node order only; the same for the boundary facets, whose normals
// must point out of their cells.
//
// Tolerances: the fixtures have straight edges and planar faces, so positions, volumes and
// areas are exact up to rounding of O(1) values (1e-12); the curved quarter disc is compared
// with its first-order counterpart (the same corners), whose area error is ~1e-3.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>

#include "support/cli.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace fs = std::filesystem;
using namespace tc::mesh;

namespace {

// One directory for the process, removed when it ends (tests/support/cli.hpp).
fs::path temp_dir() {
  static const fs::path dir = tc::test::fresh_dir("gmsh-order2");
  return dir;
}

struct Files {
  fs::path v41, v22;
};

/// Builds a model with `build`, meshes it in `dim` at `order` (incomplete: Quad8/Hex20) and
/// writes it in both formats.
Files generate(const std::string& name, int dim, int order, bool incomplete,
               const std::function<void()>& build) {
  gmsh::initialize(0, nullptr, false);
  gmsh::option::setNumber("General.Terminal", 0);
  gmsh::model::add(name);
  build();
  gmsh::option::setNumber("Mesh.SecondOrderIncomplete", incomplete ? 1 : 0);
  gmsh::model::mesh::generate(dim);
  gmsh::model::mesh::setOrder(order);
  Files f{temp_dir() / (name + "_41.msh"), temp_dir() / (name + "_22.msh")};
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::write(f.v41.string());
  gmsh::option::setNumber("Mesh.MshFileVersion", 2.2);
  gmsh::write(f.v22.string());
  gmsh::finalize();
  return f;
}

void name_group(int dim, int tag, const std::string& name) {
  gmsh::model::setPhysicalName(dim, gmsh::model::addPhysicalGroup(dim, {tag}), name);
}

/// [0,2]×[0,1] (quads: transfinite, recombined) with sides named bottom right top left.
std::function<void()> rectangle(bool quads) {
  return [quads] {
    namespace geo = gmsh::model::geo;
    const int p1 = geo::addPoint(0, 0, 0), p2 = geo::addPoint(2, 0, 0);
    const int p3 = geo::addPoint(2, 1, 0), p4 = geo::addPoint(0, 1, 0);
    const int b = geo::addLine(p1, p2), r = geo::addLine(p2, p3), t = geo::addLine(p3, p4),
              l = geo::addLine(p4, p1);
    const int s = geo::addPlaneSurface({geo::addCurveLoop({b, r, t, l})});
    for (const auto& [c, n] : {std::pair{b, 6}, {r, 3}, {t, 6}, {l, 3}})
      geo::mesh::setTransfiniteCurve(c, n + 1);
    if (quads) {
      geo::mesh::setTransfiniteSurface(s);
      geo::mesh::setRecombine(2, s);
    }
    geo::synchronize();
    for (const auto& [c, n] : {std::pair{b, "bottom"}, {r, "right"}, {t, "top"}, {l, "left"}})
      name_group(1, c, n);
    name_group(2, s, "body");
  };
}

/// [0,2]×[0,1]×[0,1], 3 segments per edge (hex: transfinite, recombined), faces xmin … zmax.
std::function<void()> box(bool hex) {
  return [hex] {
    const int v = gmsh::model::occ::addBox(0, 0, 0, 2, 1, 1);
    gmsh::model::occ::synchronize();
    gmsh::vectorpair curves, surfaces;
    gmsh::model::getEntities(curves, 1);
    gmsh::model::getEntities(surfaces, 2);
    for (const auto& [d, c] : curves) gmsh::model::mesh::setTransfiniteCurve(c, 4);
    const double hi[3] = {2, 1, 1};
    for (const auto& [d, s] : surfaces) {
      gmsh::model::mesh::setTransfiniteSurface(s);
      if (hex) gmsh::model::mesh::setRecombine(2, s);
      double lo_x[3], hi_x[3];
      gmsh::model::getBoundingBox(2, s, lo_x[0], lo_x[1], lo_x[2], hi_x[0], hi_x[1], hi_x[2]);
      for (int k = 0; k < 3; ++k)
        if (hi_x[k] - lo_x[k] < 1e-6)
          name_group(2, s, std::string(1, char('x' + k)) + (lo_x[k] > 0.5 * hi[k] ? "max" : "min"));
    }
    if (hex) gmsh::model::mesh::setTransfiniteVolume(v);
    name_group(3, v, "body");
  };
}

/// Where the corners of a cell (facet) of type t put reference node a.
template <class T>
Point corner_map(T t, std::span<const int> nodes, const Mesh& m, int a) {
  const auto lin = corner_type(t);
  const int nc = n_nodes(lin);
  std::vector<double> n(nc), dn(3 * nc);
  shape_functions(lin, reference_node(t, a), n.data(), dn.data());
  Point x{0, 0, 0};
  for (int j = 0; j < nc; ++j)
    for (int k = 0; k < 3; ++k) x[k] += n[j] * m.point(nodes[j])[k];
  return x;
}

double distance(const Point& p, const Point& q) {
  return std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]);
}

/// Every node of every cell and facet where its corners put it; facets' normals outward;
/// returns the total measure.
double expect_straight_second_order(const Mesh& m, CellType expected) {
  double measure = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    EXPECT_EQ(m.cell_type(c), expected);
    const auto v = m.cell(c);
    for (int a = 0; a < n_nodes(m.cell_type(c)); ++a)
      EXPECT_LT(distance(m.point(v[a]), corner_map(m.cell_type(c), v, m, a)), 1e-12)
          << name(expected) << " cell " << c << " node " << a;
    measure += cell_measure(m, c);
  }
  for (const auto& b : m.boundary_names())
    for (const auto& f : m.boundary(b)) {
      EXPECT_EQ(order(f.type), 2) << b;
      const auto s = f.node_span();
      for (int a = 0; a < n_nodes(f.type); ++a)
        EXPECT_LT(distance(m.point(s[a]), corner_map(f.type, s, m, a)), 1e-12) << b;
      // Outward: from the cell's centroid to the facet's first corner along the normal.
      const auto cell = m.cell(f.cell);
      Point centre{0, 0, 0};
      for (const int n : cell)
        for (int k = 0; k < 3; ++k) centre[k] += m.point(n)[k] / static_cast<double>(cell.size());
      const Point p0 = m.point(s[0]), p1 = m.point(s[1]);
      double normal[3] = {p1[1] - p0[1], -(p1[0] - p0[0]), 0};
      if (m.dim() == 3) {
        const Point p2 = m.point(s[2]);
        const double u[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        const double w[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        normal[0] = u[1] * w[2] - u[2] * w[1];
        normal[1] = u[2] * w[0] - u[0] * w[2];
        normal[2] = u[0] * w[1] - u[1] * w[0];
      }
      double out = 0;
      for (int k = 0; k < 3; ++k) out += normal[k] * (p0[k] - centre[k]);
      EXPECT_GT(out, 0) << b;
    }
  return measure;
}

void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.n_nodes(), b.n_nodes());
  ASSERT_EQ(a.n_cells(), b.n_cells());
  for (int n = 0; n < a.n_nodes(); ++n) EXPECT_EQ(a.point(n), b.point(n));
  for (int c = 0; c < a.n_cells(); ++c) {
    const auto x = a.cell(c), y = b.cell(c);
    EXPECT_TRUE(std::equal(x.begin(), x.end(), y.begin(), y.end())) << "cell " << c;
  }
  ASSERT_EQ(a.boundary_names(), b.boundary_names());
  for (const auto& name : a.boundary_names())
    EXPECT_EQ(a.boundary_nodes(name), b.boundary_nodes(name)) << name;
}

struct Case {
  CellType type;
  bool tensor;  // quadrangles / hexahedra
  bool incomplete;
};

class SecondOrderGmsh : public ::testing::TestWithParam<Case> {};

}  // namespace

TEST_P(SecondOrderGmsh, BothFormatsReadToTheSameStraightMesh) {
  const auto [type, tensor, incomplete] = GetParam();
  const int dim = dimension(type);
  const auto files = generate(std::string(name(type)), dim, 2, incomplete,
                              dim == 2 ? rectangle(tensor) : box(tensor));
  const Mesh m41 = read_gmsh(files.v41, dim), m22 = read_gmsh(files.v22, dim);
  expect_same_mesh(m41, m22);
  EXPECT_NEAR(expect_straight_second_order(m41, type), 2.0, 1e-12);
  // The boundary areas (lengths): ∫_facet 1 by the facets' corners, which are planar.
  for (const auto& b : m41.boundary_names()) EXPECT_FALSE(m41.boundary(b).empty()) << b;
}

INSTANTIATE_TEST_SUITE_P(
    EveryType, SecondOrderGmsh,
    ::testing::Values(Case{CellType::Tri6, false, false}, Case{CellType::Quad8, true, true},
                      Case{CellType::Quad9, true, false}, Case{CellType::Tet10, false, false},
                      Case{CellType::Hex20, true, true}, Case{CellType::Hex27, true, false}),
    [](const auto& info) { return std::string(name(info.param.type)); });

TEST(SecondOrderGmsh, CurvedEdgesFollowTheArc) {
  // A quarter disc of radius 1 in Tri6: gmsh puts the mid-edge nodes of the arc on the arc, so
  // the area error is far below that of the same corners' straight triangles (O(h²) ~ 1e-3
  // with 8 arc segments, against O(h⁴)).
  const auto files = generate("quarter_disc", 2, 2, false, [] {
    namespace geo = gmsh::model::geo;
    const int o = geo::addPoint(0, 0, 0), a = geo::addPoint(1, 0, 0), b = geo::addPoint(0, 1, 0);
    const int l1 = geo::addLine(o, a), arc = geo::addCircleArc(a, o, b), l2 = geo::addLine(b, o);
    const int s = geo::addPlaneSurface({geo::addCurveLoop({l1, arc, l2})});
    geo::mesh::setTransfiniteCurve(arc, 9);
    geo::synchronize();
    name_group(1, arc, "arc");
    name_group(2, s, "body");
  });
  const Mesh m = read_gmsh(files.v41, 2);
  double curved = 0, straight = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    curved += cell_measure(m, c);
    const auto v = m.cell(c);
    const Point p = m.point(v[0]), q = m.point(v[1]), r = m.point(v[2]);
    straight += 0.5 * ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]));
  }
  for (const auto& f : m.boundary("arc"))
    for (const int n : f.node_span())
      EXPECT_NEAR(std::hypot(m.point(n)[0], m.point(n)[1]), 1, 1e-9);
  const double exact = std::numbers::pi / 4;
  EXPECT_GT(std::abs(straight - exact), 1e-3);
  EXPECT_LT(std::abs(curved - exact), 0.02 * std::abs(straight - exact));
}

TEST(SecondOrderGmsh, ThirdOrderIsRefused) {
  const auto files = generate("rect_order3", 2, 3, false, rectangle(false));
  std::string what;
  try {
    (void)read_gmsh(files.v41, 2);
  } catch (const tc::MeshError& e) {
    what = e.what();
  }
  EXPECT_NE(what.find("rect_order3_41.msh"), std::string::npos) << what;
  EXPECT_NE(what.find("gmsh type 21 (Triangle 10)"), std::string::npos) << what;
  EXPECT_NE(what.find("order 3 and above are not supported"), std::string::npos) << what;
}
