// read_gmsh: libgmsh is used only to parse the file (gmsh_parse.cpp, in a child process);
// everything it returns is copied into plain vectors (RawMesh), and the Mesh is built here
// without gmsh, so that no gmsh state outlives the call whatever happens.
//
// Orientation decisions:
// - 2D: a surface whose normal is −z is meshed by gmsh with clockwise cells. That is a
//   property of the geometry, not a defect, so such cells are reversed to counter-clockwise.
// - 3D: gmsh's Tet4/Hex8 node orderings are VTK's (positive Jacobian for a valid cell) and
//   gmsh's mesher always writes positively oriented cells, so there is no convention to
//   translate: a negative-volume cell in a file is a broken mesh and check_cells rejects it.
// - Second order: Gmsh lists corners, then one node per edge, then face and volume nodes, as
//   VTK does, but in another order of the edges for Tet10 and Hex20 and of the faces for
//   Hex27 (Gmsh reference manual, "Node ordering"). Cells are renumbered to VTK's order once,
//   here (kGmshToVtk), and nowhere else; line, triangle and quadrangle orders agree.
// - Boundary facets take the node order of the matching local face of their (positively
//   oriented) cell, whose normal points outward by construction. This is exact and needs no
//   geometric tolerance, unlike a comparison with the cell centroid, which can fail for
//   strongly distorted cells. The unit tests check the normals geometrically.
#include "tc/mesh/gmsh/gmsh_reader.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <string_view>
#include <unordered_map>

#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::mesh {
namespace {

using detail::RawBlock;
using detail::RawGroup;
using detail::RawMesh;

// ---- Element types -------------------------------------------------------------------------

// gmsh element type numbers (gmsh reference manual, "MSH file format").
struct GmshType {
  int gmsh, dim;  // dim: of the mesh whose cells (or facets) these are
  bool cell;
  int type;  // CellType or FacetType
};
constexpr GmshType kGmshTypes[] = {
    {2, 2, true, int(CellType::Tri3)},     {3, 2, true, int(CellType::Quad4)},
    {9, 2, true, int(CellType::Tri6)},     {16, 2, true, int(CellType::Quad8)},
    {10, 2, true, int(CellType::Quad9)},   {4, 3, true, int(CellType::Tet4)},
    {5, 3, true, int(CellType::Hex8)},     {11, 3, true, int(CellType::Tet10)},
    {17, 3, true, int(CellType::Hex20)},   {12, 3, true, int(CellType::Hex27)},
    {1, 2, false, int(FacetType::Line2)},  {8, 2, false, int(FacetType::Line3)},
    {2, 3, false, int(FacetType::Tri3)},   {3, 3, false, int(FacetType::Quad4)},
    {9, 3, false, int(FacetType::Tri6)},   {16, 3, false, int(FacetType::Quad8)},
    {10, 3, false, int(FacetType::Quad9)},
};

const GmshType* find_type(int gmsh_type, int dim, bool cell) {
  for (const auto& g : kGmshTypes)
    if (g.gmsh == gmsh_type && g.dim == dim && g.cell == cell) return &g;
  return nullptr;
}

/// "Tri3 (2), Quad4 (3), …": the supported types for messages.
std::string supported(int dim, bool cell) {
  std::string out;
  for (const auto& g : kGmshTypes)
    if (g.dim == dim && g.cell == cell)
      out += std::string(out.empty() ? "" : ", ") +
             (cell ? name(CellType(g.type)) : name(FacetType(g.type))) + " (" +
             std::to_string(g.gmsh) + ")";
  return out;
}

bool to_cell_type(int gmsh_type, int dim, CellType& t) {
  const auto* g = find_type(gmsh_type, dim, true);
  if (g) t = CellType(g->type);
  return g != nullptr;
}

bool to_facet_type(int gmsh_type, int dim, FacetType& t) {
  const auto* g = find_type(gmsh_type, dim, false);
  if (g) t = FacetType(g->type);
  return g != nullptr;
}

/// kGmshToVtk[t][a]: the Gmsh node that is VTK node a of a cell of type t, where they differ.
/// Tet10: VTK's edges 1–3 and 2–3 are Gmsh's 9 and 8. Hex20: Gmsh orders the edges 01 03 04
/// 12 15 23 26 37 45 47 56 67, VTK 01 12 23 30 45 56 67 74 04 15 26 37. Hex27: Gmsh's face
/// nodes are z− y− x− x+ y+ z+ (20–25), VTK's x− x+ y− y+ z− z+.
constexpr int kTet10[] = {0, 1, 2, 3, 4, 5, 6, 7, 9, 8};
constexpr int kHex27[] = {0,  1,  2,  3,  4,  5,  6,  7,  8,  11, 13, 9,  16, 18,
                          19, 17, 10, 12, 14, 15, 22, 23, 21, 24, 20, 25, 26};

int gmsh_node(CellType t, int a) {
  if (t == CellType::Tet10) return kTet10[a];
  if (t == CellType::Hex20 || t == CellType::Hex27) return kHex27[a];
  return a;
}

std::string describe_type(const RawMesh& raw, int type) {
  const auto it = raw.type_names.find(type);
  return "gmsh type " + std::to_string(type) +
         (it != raw.type_names.end() ? " (" + it->second + ")" : "");
}

// ---- Nodes and cells -----------------------------------------------------------------------

using TagMap = std::unordered_map<std::size_t, int>;  // gmsh node tag → index

/// Adds to m only the nodes used by cells, numbered 0..n-1 in increasing gmsh tag.
TagMap add_used_nodes(const RawMesh& raw, Mesh& m, const std::string& where) {
  std::vector<std::size_t> used;
  for (const auto& b : raw.cells) used.insert(used.end(), b.nodes.begin(), b.nodes.end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());

  TagMap all;
  all.reserve(raw.node_tags.size());
  for (std::size_t i = 0; i < raw.node_tags.size(); ++i)
    all.emplace(raw.node_tags[i], static_cast<int>(i));

  TagMap compact;
  compact.reserve(used.size());
  for (const std::size_t tag : used) {
    const auto it = all.find(tag);
    if (it == all.end())
      throw MeshError(where + ": a cell uses node " + std::to_string(tag) + ", which has no " +
                      "coordinates");
    const double* x = &raw.coords[3 * static_cast<std::size_t>(it->second)];
    compact.emplace(tag, m.add_point({x[0], x[1], x[2]}));
  }
  return compact;
}

/// The 2D solver works in the plane z = 0; a mesh elsewhere would give zero or wrong areas.
void check_plane(const Mesh& m, const std::string& where) {
  double extent = 0, z_max = 0;
  for (const auto& p : m.points()) {
    extent = std::max({extent, std::abs(p[0]), std::abs(p[1])});
    z_max = std::max(z_max, std::abs(p[2]));
  }
  if (z_max > 1e-12 * extent) {
    std::ostringstream msg;
    msg << where << ": a 2D mesh must lie in the plane z = 0 (found |z| = " << z_max << ")";
    throw MeshError(msg.str());
  }
}

/// Twice the signed area of a 2D polygon (shoelace).
double twice_area(const Mesh& m, std::span<const int> v) {
  double a = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Point& p = m.point(v[i]);
    const Point& q = m.point(v[(i + 1) % v.size()]);
    a += p[0] * q[1] - q[0] * p[1];
  }
  return a;
}

/// A cell's gmsh node tags, sorted and padded with 0 (gmsh's tags start at 1).
using CellKey = std::array<std::size_t, 8>;
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    std::size_t h = 0;
    for (const auto i : k) h = h * 1000003u ^ std::hash<std::size_t>{}(i);
    return h;
  }
};
CellKey cell_key(const std::size_t* tags, std::size_t n) {
  CellKey k{};
  std::copy(tags, tags + std::min<std::size_t>(n, 8), k.begin());
  std::sort(k.begin(), k.begin() + static_cast<long>(std::min<std::size_t>(n, 8)));
  return k;
}

void add_cells(const RawMesh& raw, const TagMap& ids, Mesh& m, const std::string& where) {
  const int dim = m.dim();
  // The physical group of each cell of a cell group (the lowest tag when it is in several):
  // the groups list the same elements as the whole model, found again by their nodes.
  std::unordered_map<CellKey, int, CellKeyHash> group_of;
  for (const auto& g : raw.cell_groups)
    for (const auto& b : g.blocks) {
      CellType t{};
      if (!to_cell_type(b.type, dim, t)) continue;
      const std::size_t n = static_cast<std::size_t>(n_nodes(t));
      for (std::size_t e = 0; e + n <= b.nodes.size(); e += n) {
        const auto [it, added] = group_of.emplace(cell_key(&b.nodes[e], n), g.tag);
        if (!added) it->second = std::min(it->second, g.tag);
      }
    }
  for (const auto& b : raw.cells) {
    CellType t{};
    if (!to_cell_type(b.type, dim, t))
      throw MeshError(where + ": unsupported element " + describe_type(raw, b.type) + " in a " +
                      std::to_string(dim) + "D mesh; supported: " + supported(dim, true) +
                      " (elements of order 1 and 2; order 3 and above are not supported)");
    const std::size_t n = static_cast<std::size_t>(n_nodes(t));
    for (std::size_t e = 0; e + n <= b.nodes.size(); e += n) {
      std::array<int, kMaxCellNodes> v{};
      for (std::size_t a = 0; a < n; ++a)
        v[a] = ids.at(b.nodes[e + static_cast<std::size_t>(gmsh_node(t, static_cast<int>(a)))]);
      const std::span<int> nodes(v.data(), n);
      // Clockwise 2D cells come from surfaces with normal −z (see the top of this file):
      // reversing the corners after node 0 turns the cell counter-clockwise; the edges, and so
      // their nodes, then come in the reverse order (the centre of a Quad9 stays last).
      const auto nc = static_cast<std::size_t>(n_corners(t));
      if (dim == 2 && twice_area(m, nodes.first(nc)) < 0) {
        std::reverse(nodes.begin() + 1, nodes.begin() + static_cast<long>(nc));
        std::reverse(nodes.begin() + static_cast<long>(nc),
                     nodes.begin() + static_cast<long>(2 * nc));
      }
      const auto group = group_of.find(cell_key(&b.nodes[e], n));
      m.add_cell(t, nodes, group == group_of.end() ? -1 : group->second);
    }
  }
}

// ---- Boundaries ----------------------------------------------------------------------------

using Key = std::array<int, 4>;  // sorted node ids, padded with −1

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::size_t h = 0;
    for (const int i : k) h = h * 1000003u ^ std::hash<int>{}(i);
    return h;
  }
};

Key key_of(std::span<const int> nodes) {
  // Insertion sort of at most 4 ids (std::sort here trips a false -Warray-bounds in GCC 12).
  Key k{-1, -1, -1, -1};
  for (std::size_t a = 0; a < nodes.size(); ++a) {
    std::size_t b = a;
    for (; b > 0 && k[b - 1] > nodes[a]; --b) k[b] = k[b - 1];
    k[b] = nodes[a];
  }
  return k;
}

struct PendingFacet {
  std::string boundary;
  Facet facet;
  std::vector<std::size_t> tags;  // gmsh node tags, for messages
  int n_cells = 0;                // how many cells have this facet as a face
};

std::string tag_list(const std::vector<std::size_t>& tags) {
  std::ostringstream s;
  for (std::size_t i = 0; i < tags.size(); ++i) s << (i ? " " : "") << tags[i];
  return s.str();
}

/// The facets of every named group, not yet attached to cells. A facet with a node that no
/// cell uses cannot bound a cell: it gets node id −1 and is reported later.
std::vector<PendingFacet> collect_facets(const RawMesh& raw, const TagMap& ids, int dim,
                                         const std::string& where) {
  std::vector<PendingFacet> out;
  for (const auto& g : raw.groups) {
    for (const auto& b : g.blocks) {
      FacetType t{};
      if (!to_facet_type(b.type, dim, t))
        throw MeshError(where + ": boundary '" + g.name + "' has unsupported element " +
                        describe_type(raw, b.type) + "; supported: " + supported(dim, false));
      const std::size_t n = static_cast<std::size_t>(n_nodes(t));
      for (std::size_t e = 0; e + n <= b.nodes.size(); e += n) {
        PendingFacet p{g.name, Facet{}, {b.nodes.begin() + e, b.nodes.begin() + e + n}, 0};
        p.facet.type = t;
        for (std::size_t a = 0; a < n; ++a) {
          const auto it = ids.find(b.nodes[e + a]);
          p.facet.nodes[a] = it == ids.end() ? -1 : it->second;
        }
        out.push_back(std::move(p));
      }
    }
  }
  return out;
}

/// Finds the cell of every facet through a map keyed on sorted node ids, and copies the
/// outward node order of the matching local face.
void attach_to_cells(std::vector<PendingFacet>& facets, const Mesh& m) {
  std::unordered_map<Key, std::vector<int>, KeyHash> by_key;
  for (std::size_t i = 0; i < facets.size(); ++i) {
    const auto& f = facets[i].facet;
    const auto s = f.node_span();
    // Keyed by the corners, which a face's other nodes follow.
    if (std::find(s.begin(), s.end(), -1) == s.end())
      by_key[key_of(s.first(static_cast<std::size_t>(n_nodes(corner_type(f.type)))))].push_back(
          static_cast<int>(i));
  }
  for (int c = 0; c < m.n_cells(); ++c) {
    const auto cell = m.cell(c);
    for (const auto& lf : local_faces(m.cell_type(c))) {
      Facet face;
      face.type = lf.type;
      face.cell = c;
      for (int a = 0; a < n_nodes(lf.type); ++a) face.nodes[a] = cell[lf.v[a]];
      const auto corners = static_cast<std::size_t>(n_nodes(corner_type(lf.type)));
      const auto it = by_key.find(key_of(face.node_span().first(corners)));
      if (it == by_key.end()) continue;
      for (const int i : it->second) {
        auto& p = facets[i];
        if (++p.n_cells > 1) continue;
        // A facet of another type than its cell's face (a Line2 on a Tri6) or with other
        // mid-edge nodes is not that face: it is reported as bounding no cell.
        auto mine = p.facet.nodes, theirs = face.nodes;
        std::sort(mine.begin(), mine.end());
        std::sort(theirs.begin(), theirs.end());
        if (p.facet.type != face.type || mine != theirs) {
          p.n_cells = 0;
          continue;
        }
        p.facet = face;
      }
    }
  }
}

/// A facet must bound exactly one cell: none means it is not part of this body's mesh, two
/// means it is interior and has no outward normal.
void check_attached(const std::vector<PendingFacet>& facets, const std::string& where) {
  std::ostringstream msg;
  int n_bad = 0;
  for (const auto& p : facets) {
    if (p.n_cells == 1) continue;
    if (++n_bad > 10) continue;
    msg << "\n  boundary '" << p.boundary << "', facet with gmsh nodes " << tag_list(p.tags)
        << (p.n_cells == 0 ? ": bounds no cell" : ": is interior (shared by two cells)");
  }
  if (n_bad > 0)
    throw MeshError(
        where + ": " + std::to_string(n_bad) +
        " boundary facets do not bound exactly one cell (first ones listed):" + msg.str());
}

void add_boundaries(const RawMesh& raw, const TagMap& ids, Mesh& m, const std::string& where) {
  auto facets = collect_facets(raw, ids, m.dim(), where);
  attach_to_cells(facets, m);
  check_attached(facets, where);
  for (const auto& p : facets) m.add_facet(p.boundary, p.facet);
}

}  // namespace

Mesh read_gmsh(const std::filesystem::path& file, int dim) {
  const std::string where = "mesh file '" + file.string() + "'";
  if (dim != 2 && dim != 3)
    throw MeshError(where + ": dimension must be 2 or 3, not " + std::to_string(dim));
  // gmsh 4.8 does not fail on a missing file (it logs and returns an empty model).
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec))
    throw MeshError("cannot read " + where + ": no such file");
  detail::check_header(file, where);

  return detail::build_mesh(detail::read_raw_isolated(file, dim), dim, file.string());
}

Mesh detail::build_mesh(const RawMesh& raw, int dim, const std::string& file) {
  const std::string where = "mesh file '" + file + "'";
  if (dim != 2 && dim != 3)
    throw MeshError(where + ": dimension must be 2 or 3, not " + std::to_string(dim));
  if (raw.coords.size() != 3 * raw.node_tags.size())
    throw MeshError(where + ": " + std::to_string(raw.node_tags.size()) + " nodes but " +
                    std::to_string(raw.coords.size()) + " coordinates");
  if (raw.cells.empty())
    throw MeshError(where + ": no cells of dimension " + std::to_string(dim) +
                    " (when a file has physical groups, gmsh saves only the elements in them: "
                    "add a physical group for the body or set Mesh.SaveAll = 1)");

  Mesh m(dim);
  const TagMap ids = add_used_nodes(raw, m, where);
  if (dim == 2) check_plane(m, where);
  add_cells(raw, ids, m, where);
  check_cells(m, file);    // before boundaries: their orientation relies on the cells'
  check_no_fold(m, file);  // cells turned one by one must not overlap (issue 42 D5)
  add_boundaries(raw, ids, m, where);
  return m;
}

}  // namespace tc::mesh
