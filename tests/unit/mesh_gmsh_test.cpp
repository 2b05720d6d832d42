// read_gmsh on meshes generated here with the gmsh API (MSH 4.1) or written by hand (MSH 2.2),
// and the geometric checks of checks.cpp (cell_measure, check_cells, find_duplicate_nodes).
//
// Tolerances: every fixture has straight edges/planar faces, or (quarter disc) nodes exactly on
// the arc, so measures and normals are exact up to rounding. Sums over ≤ 10⁴ cells of O(1)
// terms lose at most ~1e-16 · 10⁴ relative, hence the 1e-12 bounds, which any real error
// (a missing, duplicated or inverted cell, a wrong normal) exceeds by orders of magnitude.
#include <gmsh.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <set>

#include "support/cli.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"
#include "tc/mesh/mesh.hpp"

namespace fs = std::filesystem;
using namespace tc::mesh;
// Vec3, not Vec: PETSc names its vector type Vec in the global namespace (the tests'
// precompiled header includes it).
using Vec3 = std::array<double, 3>;

namespace {

// ---- Fixtures --------------------------------------------------------------------------------

// One directory for the process, removed when it ends (tests/support/cli.hpp).
fs::path temp_dir() {
  static const fs::path dir = tc::test::fresh_dir("mesh-gmsh");
  return dir;
}

/// A gmsh session of the test's own, closed before read_gmsh opens its own (libgmsh is a
/// global singleton).
class GmshSession {
 public:
  GmshSession() {
    gmsh::initialize(0, nullptr, false);
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() { gmsh::finalize(); }
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

/// Builds a model with `build` (which synchronizes and sets options), meshes it in `dim` and
/// writes it as MSH 4.1.
fs::path generate(const std::string& name, int dim, const std::function<void()>& build) {
  const fs::path file = temp_dir() / (name + ".msh");
  const GmshSession session;
  gmsh::model::add(name);
  build();
  gmsh::model::mesh::generate(dim);
  gmsh::option::setNumber("Mesh.MshFileVersion", 4.1);
  gmsh::write(file.string());
  return file;
}

fs::path write_text(const std::string& name, const std::string& text) {
  const fs::path file = temp_dir() / name;
  std::ofstream(file) << text;
  return file;
}

int named_group(int dim, const std::vector<int>& tags, const std::string& name) {
  const int g = gmsh::model::addPhysicalGroup(dim, tags);
  gmsh::model::setPhysicalName(dim, g, name);
  return g;
}

/// [x0, x0+lx] × [0, ly] with nx × ny boundary segments; sides bottom/right/top/left.
struct Rect {
  double x0 = 0, lx = 2, ly = 1;
  int nx = 8, ny = 4;
  bool quads = false;      // transfinite + recombine: nx·ny Quad4
  bool clockwise = false;  // curve loop with normal −z: gmsh writes clockwise cells
};

/// Adds the rectangle to the geo kernel and returns {surface, bottom, right, top, left}.
std::array<int, 5> add_rect(const Rect& r) {
  namespace geo = gmsh::model::geo;
  const int p1 = geo::addPoint(r.x0, 0, 0), p2 = geo::addPoint(r.x0 + r.lx, 0, 0);
  const int p3 = geo::addPoint(r.x0 + r.lx, r.ly, 0), p4 = geo::addPoint(r.x0, r.ly, 0);
  // Clockwise: the lines themselves run clockwise too, so gmsh's facets point inward and the
  // reader must turn them.
  const bool cw = r.clockwise;
  const int b = cw ? geo::addLine(p2, p1) : geo::addLine(p1, p2);
  const int rt = cw ? geo::addLine(p3, p2) : geo::addLine(p2, p3);
  const int t = cw ? geo::addLine(p4, p3) : geo::addLine(p3, p4);
  const int l = cw ? geo::addLine(p1, p4) : geo::addLine(p4, p1);
  const int loop = cw ? geo::addCurveLoop({l, t, rt, b}) : geo::addCurveLoop({b, rt, t, l});
  const int s = geo::addPlaneSurface({loop});
  // Mesh constraints through the geo kernel: a later geo::synchronize() would reset those set
  // on the model.
  for (const auto& [c, n] : {std::pair{b, r.nx}, {rt, r.ny}, {t, r.nx}, {l, r.ny}})
    geo::mesh::setTransfiniteCurve(c, n + 1);
  if (r.quads) {
    geo::mesh::setTransfiniteSurface(s);
    geo::mesh::setRecombine(2, s);
  }
  geo::synchronize();
  return {s, b, rt, t, l};
}

/// One rectangle with named sides, a named body and an isolated named point (its node is in
/// the file but in no cell, so the reader must drop it).
std::function<void()> rectangle(const Rect& r) {
  return [r] {
    const auto [s, b, rt, t, l] = add_rect(r);
    const int probe = gmsh::model::geo::addPoint(5, 5, 0);
    gmsh::model::geo::synchronize();
    named_group(0, {probe}, "probe");
    named_group(1, {b}, "bottom");
    named_group(1, {rt}, "right");
    named_group(1, {t}, "top");
    named_group(1, {l}, "left");
    gmsh::model::addPhysicalGroup(1, {b, t});  // unnamed: ignored
    named_group(2, {s}, "body");
  };
}

// ---- Geometry helpers ------------------------------------------------------------------------

Vec3 sub(const Point& a, const Point& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

Vec3 centroid(const Mesh& m, std::span<const int> nodes) {
  Vec3 c{};
  for (const int n : nodes)
    for (int k = 0; k < 3; ++k) c[k] += m.point(n)[k] / static_cast<double>(nodes.size());
  return c;
}

/// Unit normal of a facet, computed from its node order only (mesh.hpp's convention).
Vec3 unit_normal(const Mesh& m, const Facet& f) {
  const auto v = f.node_span();
  const auto p = [&](int a) { return m.point(v[a]); };
  Vec3 n{};
  switch (f.type) {
    case FacetType::Line2: {
      const Vec3 t = sub(p(1), p(0));
      n = {t[1], -t[0], 0};
      break;
    }
    case FacetType::Tri3:
      n = cross(sub(p(1), p(0)), sub(p(2), p(0)));
      break;
    case FacetType::Quad4:
      n = cross(sub(p(2), p(0)), sub(p(3), p(1)));
      break;
    default:  // this file's meshes are of first order (second order: its own test file)
      ADD_FAILURE() << "a second-order facet";
  }
  const double len = std::sqrt(dot(n, n));
  for (auto& x : n) x /= len;
  return n;
}

double total_measure(const Mesh& m) {
  double sum = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const double a = cell_measure(m, c);
    EXPECT_GT(a, 0) << "cell " << c;
    sum += a;
  }
  return sum;
}

int count_cells(const Mesh& m, CellType t) {
  int n = 0;
  for (int c = 0; c < m.n_cells(); ++c) n += m.cell_type(c) == t;
  return n;
}

/// Every facet of boundary `name` lies on its cell and points out of it (facet centroid on
/// the positive side from the cell centroid); with `expected` given, its normal is that vector.
void expect_boundary(const Mesh& m, const std::string& name, std::size_t n_facets,
                     const std::function<Vec3(const Vec3&)>& expected = {}) {
  ASSERT_TRUE(m.has_boundary(name)) << name;
  const auto& facets = m.boundary(name);
  EXPECT_EQ(facets.size(), n_facets) << name;
  for (const auto& f : facets) {
    ASSERT_GE(f.cell, 0);
    ASSERT_LT(f.cell, m.n_cells());
    const auto cell = m.cell(f.cell);
    for (const int v : f.node_span())
      EXPECT_NE(std::find(cell.begin(), cell.end(), v), cell.end()) << name << ": not a face";
    const Vec3 n = unit_normal(m, f);
    const Vec3 fc = centroid(m, f.node_span());
    EXPECT_GT(dot(n, sub(fc, centroid(m, cell))), 0) << name << ": normal points inward";
    if (expected) {
      EXPECT_NEAR(dot(n, expected(fc)), 1.0, 1e-12) << name;
    }
  }
}

Vec3 constant(double x, double y, double z) {
  return {x, y, z};
}

/// Every node is used by a cell (the reader numbers only those).
void expect_nodes_compact(const Mesh& m) {
  std::vector<bool> used(static_cast<std::size_t>(m.n_nodes()), false);
  for (int c = 0; c < m.n_cells(); ++c)
    for (const int v : m.cell(c)) {
      ASSERT_GE(v, 0);
      ASSERT_LT(v, m.n_nodes());
      used[static_cast<std::size_t>(v)] = true;
    }
  EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
}

template <class F>
std::string mesh_error(F&& f) {
  try {
    f();
  } catch (const tc::MeshError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a MeshError";
  return "";
}

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "in: " << (text)

void expect_rectangle_sides(const Mesh& m, const Rect& r) {
  expect_boundary(m, "bottom", r.nx, [](const Vec3&) { return constant(0, -1, 0); });
  expect_boundary(m, "right", r.ny, [](const Vec3&) { return constant(1, 0, 0); });
  expect_boundary(m, "top", r.nx, [](const Vec3&) { return constant(0, 1, 0); });
  expect_boundary(m, "left", r.ny, [](const Vec3&) { return constant(-1, 0, 0); });
}

// ---- 2D ------------------------------------------------------------------------------------

TEST(GmshReader, RectangleOfTriangles) {
  const Rect r;
  const Mesh m = read_gmsh(generate("rect_tri", 2, rectangle(r)), 2);
  EXPECT_EQ(m.dim(), 2);
  EXPECT_GT(m.n_cells(), 0);
  EXPECT_EQ(count_cells(m, CellType::Tri3), m.n_cells());
  EXPECT_NEAR(total_measure(m), r.lx * r.ly, 1e-12);
  expect_rectangle_sides(m, r);
  // Only named groups of dimension 1 are boundaries: not the point, the body or the unnamed.
  EXPECT_EQ(m.boundary_names(), (std::vector<std::string>{"bottom", "left", "right", "top"}));
  expect_nodes_compact(m);
  for (const auto& p : m.points()) EXPECT_LT(p[0], 4.0) << "the isolated node was kept";
}

TEST(GmshReader, RectangleOfQuads) {
  const Rect r{.quads = true};
  const Mesh m = read_gmsh(generate("rect_quad", 2, rectangle(r)), 2);
  EXPECT_EQ(count_cells(m, CellType::Quad4), r.nx * r.ny);
  EXPECT_EQ(m.n_cells(), r.nx * r.ny);
  EXPECT_EQ(m.n_nodes(), (r.nx + 1) * (r.ny + 1));
  EXPECT_NEAR(total_measure(m), r.lx * r.ly, 1e-12);
  expect_rectangle_sides(m, r);
  expect_nodes_compact(m);
}

/// Signed area of the first cell as gmsh wrote it, to show the fixture really is clockwise.
double first_raw_cell_area(const fs::path& file) {
  const GmshSession session;
  gmsh::open(file.string());
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> tags, nodes;
  gmsh::model::mesh::getElements(types, tags, nodes, 2);
  std::vector<double> x, u;
  std::array<Vec3, 3> p{};
  for (int a = 0; a < 3; ++a) {
    gmsh::model::mesh::getNode(nodes.at(0).at(static_cast<std::size_t>(a)), x, u);
    p[static_cast<std::size_t>(a)] = {x[0], x[1], x[2]};
  }
  return 0.5 * cross(sub(p[1], p[0]), sub(p[2], p[0]))[2];
}

TEST(GmshReader, ClockwiseCellsAreReversed) {
  for (const bool quads : {false, true}) {
    const Rect r{.quads = quads, .clockwise = true};
    const auto file = generate(quads ? "rect_cw_quad" : "rect_cw_tri", 2, rectangle(r));
    ASSERT_LT(first_raw_cell_area(file), 0) << "the fixture should have clockwise cells";
    const Mesh m = read_gmsh(file, 2);
    EXPECT_NEAR(total_measure(m), r.lx * r.ly, 1e-12);  // every cell positive (checked inside)
    expect_rectangle_sides(m, r);
  }
}

/// [0,1]×[0,1] of 4×4 quads glued to [1,2]×[0,1] of triangles along x = 1, in the gmsh model
/// being built: the tags of its curves and surfaces.
struct TwoSquares {
  int b1, b2, r, t2, t1, l, mid, s1, s2;
};
TwoSquares two_squares() {
  namespace geo = gmsh::model::geo;
  const int p[6] = {geo::addPoint(0, 0, 0), geo::addPoint(1, 0, 0), geo::addPoint(2, 0, 0),
                    geo::addPoint(2, 1, 0), geo::addPoint(1, 1, 0), geo::addPoint(0, 1, 0)};
  const int b1 = geo::addLine(p[0], p[1]), b2 = geo::addLine(p[1], p[2]);
  const int r = geo::addLine(p[2], p[3]), t2 = geo::addLine(p[3], p[4]);
  const int t1 = geo::addLine(p[4], p[5]), l = geo::addLine(p[5], p[0]);
  const int mid = geo::addLine(p[1], p[4]);
  const int s1 = geo::addPlaneSurface({geo::addCurveLoop({b1, mid, t1, l})});
  const int s2 = geo::addPlaneSurface({geo::addCurveLoop({b2, r, t2, -mid})});
  geo::synchronize();
  for (const int c : {b1, b2, r, t2, t1, l, mid}) gmsh::model::mesh::setTransfiniteCurve(c, 5);
  gmsh::model::mesh::setTransfiniteSurface(s1);
  gmsh::model::mesh::setRecombine(2, s1);
  return {b1, b2, r, t2, t1, l, mid, s1, s2};
}

TEST(GmshReader, MixedTrianglesAndQuads) {
  // [0,1]×[0,1] of quads glued to [1,2]×[0,1] of triangles along x = 1.
  const auto file = generate("rect_mixed", 2, [] {
    const auto [b1, b2, r, t2, t1, l, mid, s1, s2] = two_squares();
    named_group(1, {b1, b2}, "bottom");
    named_group(1, {r}, "right");
    named_group(1, {t1, t2}, "top");
    named_group(1, {l}, "left");
    named_group(2, {s1, s2}, "body");
  });
  const Mesh m = read_gmsh(file, 2);
  EXPECT_EQ(count_cells(m, CellType::Quad4), 16);
  EXPECT_GT(count_cells(m, CellType::Tri3), 0);
  EXPECT_NEAR(total_measure(m), 2.0, 1e-12);
  expect_rectangle_sides(m, Rect{.nx = 8, .ny = 4});
  expect_nodes_compact(m);
  // The interface nodes are shared, not duplicated: Euler's formula V − E + F = 1 would also
  // do, but the duplicate finder is the direct check.
  EXPECT_TRUE(find_duplicate_nodes(m).empty());
}

TEST(GmshReader, CellsKeepTheirPhysicalGroup) {
  // Two surfaces, each its own physical group (tags given by gmsh), one cell group unnamed:
  // every cell carries its group's tag (the .vtu's physical_group), −1 for a box mesh.
  int quads = -1, triangles = -1;
  const auto file = generate("rect_groups", 2, [&] {
    const auto [b1, b2, r, t2, t1, l, mid, s1, s2] = two_squares();
    named_group(1, {b1, b2, r, t1, t2, l}, "outline");
    quads = named_group(2, {s1}, "left_part");
    triangles = gmsh::model::addPhysicalGroup(2, {s2}, 7);  // unnamed, tag 7
  });
  const Mesh m = read_gmsh(file, 2);
  ASSERT_EQ(triangles, 7);
  int seen_quads = 0, seen_triangles = 0;
  for (int c = 0; c < m.n_cells(); ++c) {
    const bool quad = m.cell_type(c) == CellType::Quad4;
    EXPECT_EQ(m.cell_group(c), quad ? quads : triangles) << "cell " << c;
    (quad ? seen_quads : seen_triangles) += 1;
  }
  EXPECT_EQ(seen_quads, 16);
  EXPECT_GT(seen_triangles, 0);
  const auto box = tc::mesh::make_box(2, {0, 0, 0}, {1, 1, 0}, {2, 2, 1});
  for (int c = 0; c < box.n_cells(); ++c) EXPECT_EQ(box.cell_group(c), -1);
}

TEST(GmshReader, QuarterDiscOfMostlyQuads) {
  // The setting of the Hertz test: Mesh.Algorithm = 6 with RecombineAll (8 crashes in 4.8.4).
  const double radius = 2.0;
  // An odd number of boundary segments (25 + 12 + 12) forbids an all-quad mesh: some
  // triangles remain: a mixed mesh, as the Hertz test will have.
  const int n_arc = 25;
  const auto file = generate("quarter_disc", 2, [&] {
    namespace geo = gmsh::model::geo;
    const int o = geo::addPoint(0, 0, 0), a = geo::addPoint(radius, 0, 0);
    const int b = geo::addPoint(0, radius, 0);
    const int bottom = geo::addLine(o, a), arc = geo::addCircleArc(a, o, b);
    const int left = geo::addLine(b, o);
    const int s = geo::addPlaneSurface({geo::addCurveLoop({bottom, arc, left})});
    geo::synchronize();
    gmsh::model::mesh::setTransfiniteCurve(arc, n_arc + 1);
    gmsh::model::mesh::setTransfiniteCurve(bottom, 13);
    gmsh::model::mesh::setTransfiniteCurve(left, 13);
    gmsh::option::setNumber("Mesh.Algorithm", 6);
    gmsh::option::setNumber("Mesh.RecombineAll", 1);
    named_group(1, {bottom}, "bottom");
    named_group(1, {arc}, "arc");
    named_group(1, {left}, "left");
    named_group(2, {s}, "body");
  });
  const Mesh m = read_gmsh(file, 2);
  const int n_quads = count_cells(m, CellType::Quad4);
  EXPECT_GT(count_cells(m, CellType::Tri3), 0);
  // gmsh 4.8.4 gives 153 quads and 49 triangles; a mixed mesh is what matters here.
  EXPECT_GT(n_quads, m.n_cells() / 2) << "quads " << n_quads << " of " << m.n_cells();
  // The arc nodes lie on the circle, so the mesh covers exactly the inscribed polygon: the
  // quarter disc minus n_arc circular segments of angle θ, each r²(θ − sin θ)/2.
  const double theta = std::numbers::pi / 2 / n_arc;
  const double deficit = n_arc * radius * radius * (theta - std::sin(theta)) / 2;
  const double exact = std::numbers::pi * radius * radius / 4;
  EXPECT_GT(deficit, 1e-4 * exact);  // so the check below is not just "close to the disc"
  EXPECT_NEAR(total_measure(m), exact - deficit, 1e-12 * exact);
  expect_boundary(m, "bottom", 12, [](const Vec3&) { return constant(0, -1, 0); });
  expect_boundary(m, "left", 12, [](const Vec3&) { return constant(-1, 0, 0); });
  // The outward normal of a chord is the radial direction at its midpoint.
  expect_boundary(m, "arc", n_arc, [](const Vec3& c) {
    const double r = std::hypot(c[0], c[1]);
    return constant(c[0] / r, c[1] / r, 0);
  });
  expect_nodes_compact(m);
}

// ---- 3D ------------------------------------------------------------------------------------

/// [0,2]×[0,1]×[0,1] with n segments on every edge; faces named xmin … zmax.
std::function<void()> box(int n, bool hex) {
  return [n, hex] {
    const int v = gmsh::model::occ::addBox(0, 0, 0, 2, 1, 1);
    gmsh::model::occ::synchronize();
    gmsh::vectorpair curves, surfaces;
    gmsh::model::getEntities(curves, 1);
    gmsh::model::getEntities(surfaces, 2);
    for (const auto& [d, c] : curves) gmsh::model::mesh::setTransfiniteCurve(c, n + 1);
    const double hi[3] = {2, 1, 1};
    for (const auto& [d, s] : surfaces) {
      gmsh::model::mesh::setTransfiniteSurface(s);
      if (hex) gmsh::model::mesh::setRecombine(2, s);
      double lo_x[3], hi_x[3];
      gmsh::model::getBoundingBox(2, s, lo_x[0], lo_x[1], lo_x[2], hi_x[0], hi_x[1], hi_x[2]);
      for (int k = 0; k < 3; ++k) {
        if (hi_x[k] - lo_x[k] > 1e-6) continue;  // the face is normal to axis k
        const std::string axis(1, static_cast<char>('x' + k));
        named_group(2, {s}, axis + (lo_x[k] > 0.5 * hi[k] ? "max" : "min"));
      }
    }
    if (hex) gmsh::model::mesh::setTransfiniteVolume(v);
    named_group(3, {v}, "body");
  };
}

void expect_box_faces(const Mesh& m, std::size_t per_face) {
  const std::pair<const char*, Vec3> faces[] = {{"xmin", {-1, 0, 0}}, {"xmax", {1, 0, 0}},
                                                {"ymin", {0, -1, 0}}, {"ymax", {0, 1, 0}},
                                                {"zmin", {0, 0, -1}}, {"zmax", {0, 0, 1}}};
  for (const auto& [name, n] : faces)
    expect_boundary(m, name, per_face, [n = n](const Vec3&) { return n; });
  EXPECT_EQ(m.boundary_names().size(), 6u);
}

TEST(GmshReader, BoxOfTetrahedra) {
  const int n = 4;
  const Mesh m = read_gmsh(generate("box_tet", 3, box(n, false)), 3);
  EXPECT_EQ(m.dim(), 3);
  EXPECT_GT(m.n_cells(), 0);
  EXPECT_EQ(count_cells(m, CellType::Tet4), m.n_cells());
  EXPECT_NEAR(total_measure(m), 2.0, 1e-12);
  expect_box_faces(m, 2 * n * n);  // transfinite faces: two triangles per square
  expect_nodes_compact(m);
}

TEST(GmshReader, BoxOfHexahedra) {
  const int n = 4;
  const Mesh m = read_gmsh(generate("box_hex", 3, box(n, true)), 3);
  EXPECT_EQ(count_cells(m, CellType::Hex8), n * n * n);
  EXPECT_EQ(m.n_cells(), n * n * n);
  EXPECT_EQ(m.n_nodes(), (n + 1) * (n + 1) * (n + 1));
  EXPECT_NEAR(total_measure(m), 2.0, 1e-12);
  expect_box_faces(m, n * n);
  expect_nodes_compact(m);
}

// ---- Errors ----------------------------------------------------------------------------------

TEST(GmshReader, MissingOrUnreadableFile) {
  const auto missing = temp_dir() / "no_such_mesh.msh";
  EXPECT_CONTAINS(mesh_error([&] { (void)read_gmsh(missing, 2); }), "no_such_mesh.msh");
  const auto garbage = write_text("garbage.msh", "this is not a mesh\n");
  EXPECT_CONTAINS(mesh_error([&] { (void)read_gmsh(garbage, 2); }), "garbage.msh");
}

// Second-order elements, and the refusal of third-order ones: mesh_gmsh_second_order_test.

TEST(GmshReader, WrongDimensionHasNoCells) {
  const auto file = generate("rect_for_3d", 2, rectangle(Rect{}));
  EXPECT_CONTAINS(mesh_error([&] { (void)read_gmsh(file, 3); }), "no cells of dimension 3");
}

/// One tetrahedron (gmsh nodes 1..4) and a named triangle on face 1 2 3, in MSH 2.2.
std::string one_tet(const std::string& tet_nodes) {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n2\n2 1 \"base\"\n3 2 \"body\"\n$EndPhysicalNames\n"
         "$Nodes\n4\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n$EndNodes\n"
         "$Elements\n2\n1 2 2 1 1 1 2 3\n2 4 2 2 1 " +
         tet_nodes + "\n$EndElements\n";
}

TEST(GmshReader, InvertedTetrahedronIsAnError) {
  const Mesh good = read_gmsh(write_text("tet_good.msh", one_tet("1 2 3 4")), 3);
  ASSERT_EQ(good.n_cells(), 1);
  EXPECT_NEAR(cell_measure(good, 0), 1.0 / 6.0, 1e-15);
  expect_boundary(good, "base", 1, [](const Vec3&) { return constant(0, 0, -1); });

  const auto bad = write_text("tet_inverted.msh", one_tet("1 3 2 4"));
  const std::string what = mesh_error([&] { (void)read_gmsh(bad, 3); });
  EXPECT_CONTAINS(what, "tet_inverted.msh");
  EXPECT_CONTAINS(what, "cell 0 (Tet4)");
  EXPECT_CONTAINS(what, "inverted");
}

/// The unit square as two triangles (1 2 3) and (1 3 4), a named group of one line, MSH 2.2.
std::string square_with_line(const std::string& line_nodes, double z = 0) {
  const std::string zs = std::to_string(z);
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
         "$PhysicalNames\n2\n1 1 \"edge\"\n2 2 \"body\"\n$EndPhysicalNames\n"
         "$Nodes\n4\n1 0 0 " +
         zs + "\n2 1 0 " + zs + "\n3 1 1 " + zs + "\n4 0 1 " + zs +
         "\n$EndNodes\n"
         "$Elements\n3\n1 1 2 1 1 " +
         line_nodes + "\n2 2 2 2 1 1 2 3\n3 2 2 2 1 1 3 4\n$EndElements\n";
}

TEST(GmshReader, BoundaryFacetsMustBoundExactlyOneCell) {
  // Control: the edge 2→1 of the bottom is found and turned to run counter-clockwise.
  const Mesh m = read_gmsh(write_text("square_ok.msh", square_with_line("2 1")), 2);
  expect_boundary(m, "edge", 1, [](const Vec3&) { return constant(0, -1, 0); });

  const auto off = write_text("square_off.msh", square_with_line("2 4"));  // not an edge
  const std::string what = mesh_error([&] { (void)read_gmsh(off, 2); });
  EXPECT_CONTAINS(what, "square_off.msh");
  EXPECT_CONTAINS(what, "boundary 'edge'");
  EXPECT_CONTAINS(what, "bounds no cell");

  const auto inner = write_text("square_inner.msh", square_with_line("1 3"));  // the diagonal
  EXPECT_CONTAINS(mesh_error([&] { (void)read_gmsh(inner, 2); }), "interior");
}

TEST(GmshReader, TwoDimensionalMeshMustLieInPlaneZ0) {
  const auto file = write_text("square_z1.msh", square_with_line("1 2", 1.0));
  EXPECT_CONTAINS(mesh_error([&] { (void)read_gmsh(file, 2); }), "plane z = 0");
}

// ---- cell_measure, check_cells, find_duplicate_nodes on hand-built meshes -------------------

Mesh hex_mesh(const std::array<Point, 8>& p) {
  Mesh m(3);
  std::array<int, 8> v{};
  for (int a = 0; a < 8; ++a) v[static_cast<std::size_t>(a)] = m.add_point(p[a]);
  m.add_cell(CellType::Hex8, v);
  return m;
}

TEST(GmshMeshChecks, HexVolumeIsExactForTrilinearCells) {
  // A square frustum (bottom side a at z = 0, top side b at z = h) is the image of a trilinear
  // map with a non-constant Jacobian: V = h (a² + ab + b²) / 3 exactly.
  const double a = 2, b = 1, h = 1.5;
  const Mesh frustum = hex_mesh({Point{-a / 2, -a / 2, 0},
                                 {a / 2, -a / 2, 0},
                                 {a / 2, a / 2, 0},
                                 {-a / 2, a / 2, 0},
                                 {-b / 2, -b / 2, h},
                                 {b / 2, -b / 2, h},
                                 {b / 2, b / 2, h},
                                 {-b / 2, b / 2, h}});
  EXPECT_NEAR(cell_measure(frustum, 0), h * (a * a + a * b + b * b) / 3, 1e-14);
  EXPECT_NO_THROW(check_cells(frustum, "frustum"));

  // Swapping bottom and top turns it inside out: negative volume, every corner negative.
  const Mesh inverted = hex_mesh({Point{-b / 2, -b / 2, h},
                                  {b / 2, -b / 2, h},
                                  {b / 2, b / 2, h},
                                  {-b / 2, b / 2, h},
                                  {-a / 2, -a / 2, 0},
                                  {a / 2, -a / 2, 0},
                                  {a / 2, a / 2, 0},
                                  {-a / 2, a / 2, 0}});
  EXPECT_NEAR(cell_measure(inverted, 0), -h * (a * a + a * b + b * b) / 3, 1e-14);
  const std::string what = mesh_error([&] { check_cells(inverted, "inverted.msh"); });
  EXPECT_CONTAINS(what, "inverted.msh");
  EXPECT_CONTAINS(what, "cell 0 (Hex8): volume");
}

TEST(GmshMeshChecks, NonConvexQuadIsCaughtAtItsCorner) {
  // An arrowhead: positive area, but node 2 is a reflex corner (Jacobian −2 there).
  Mesh m(2);
  for (const Point& p : {Point{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}}) m.add_point(p);
  const std::array<int, 4> quad{0, 1, 2, 3};
  m.add_cell(CellType::Quad4, quad);
  EXPECT_NEAR(cell_measure(m, 0), 1.0, 1e-15);  // shoelace: ½|d02 × d13| = ½·2
  const std::string what = mesh_error([&] { check_cells(m, "arrow"); });
  EXPECT_CONTAINS(what, "cell 0 (Quad4): Jacobian");
  EXPECT_CONTAINS(what, "at corner 2");
}

TEST(GmshMeshChecks, DegenerateAndManyInvertedCells) {
  Mesh flat(2);
  for (const Point& p : {Point{0, 0, 0}, {1, 1, 0}, {2, 2, 0}}) flat.add_point(p);
  const std::array<int, 3> tri{0, 1, 2};
  flat.add_cell(CellType::Tri3, tri);
  EXPECT_CONTAINS(mesh_error([&] { check_cells(flat, "flat"); }), "degenerate");

  // 15 clockwise triangles (and one good one first): 15 reported, 10 listed.
  Mesh many(2);
  for (const Point& p : {Point{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}) many.add_point(p);
  const std::array<int, 3> good{0, 1, 2}, bad{0, 2, 1};
  many.add_cell(CellType::Tri3, good);
  for (int i = 0; i < 15; ++i) many.add_cell(CellType::Tri3, bad);
  const std::string what = mesh_error([&] { check_cells(many, "many"); });
  EXPECT_CONTAINS(what, "15 inverted or degenerate cells");
  int listed = 0;
  for (std::size_t at = what.find("\n  cell "); at != std::string::npos;
       at = what.find("\n  cell ", at + 1))
    ++listed;
  EXPECT_EQ(listed, 10);
  EXPECT_EQ(what.find("cell 0 "), std::string::npos) << "the good cell is not listed";
}

std::vector<std::pair<int, int>> brute_force_duplicates(const Mesh& m, double tol) {
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < m.n_nodes(); ++i)
    for (int j = i + 1; j < m.n_nodes(); ++j) {
      const Vec3 d = sub(m.point(i), m.point(j));
      if (std::abs(d[0]) <= tol && std::abs(d[1]) <= tol && std::abs(d[2]) <= tol)
        out.emplace_back(i, j);
    }
  return out;
}

TEST(GmshMeshChecks, DuplicateNodesMatchBruteForce) {
  // Random points in the unit cube (diagonal √3, tolerance 1e-12·√3) plus copies moved by 0.3
  // tolerance (duplicates) and by 10 tolerances (not duplicates).
  std::mt19937 gen(42);
  std::uniform_real_distribution<double> u(0, 1), sign(-1, 1);
  Mesh m(3);
  m.add_point({0, 0, 0});
  m.add_point({1, 1, 1});
  const double tol = 1e-12 * std::sqrt(3.0);
  for (int i = 0; i < 1500; ++i) {
    const Point p{u(gen), u(gen), u(gen)};
    m.add_point(p);
    if (i % 3 == 0) m.add_point({p[0] + 0.3 * tol * sign(gen), p[1], p[2] - 0.3 * tol});
    if (i % 5 == 0) m.add_point({p[0], p[1] + 10 * tol, p[2]});
  }
  // A pair straddling a bin face of the finder (bins of 1000 tolerances from the minimum), so
  // that the search of neighbour bins is exercised.
  m.add_point({0.5, 0.5, 1000 * tol * 7 - 0.4 * tol});
  m.add_point({0.5, 0.5, 1000 * tol * 7 + 0.4 * tol});
  const auto found = find_duplicate_nodes(m);
  EXPECT_EQ(found, brute_force_duplicates(m, tol));
  EXPECT_EQ(found.size(), 500u + 1u);

  Mesh same(2);
  same.add_point({1, 1, 0});
  same.add_point({1, 1, 0});
  EXPECT_EQ(find_duplicate_nodes(same), (std::vector<std::pair<int, int>>{{0, 1}}));
}

}  // namespace
