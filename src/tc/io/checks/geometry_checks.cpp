#include "tc/io/checks/geometry_checks.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

#include "tc/contact/mortar_pair.hpp"
#include "tc/contact/search.hpp"
#include "tc/core/error.hpp"
#include "tc/mesh/reference_cell.hpp"

namespace tc::io {

namespace {

double largest_facet(const mesh::Mesh& m, const std::string& where) {
  double h = 0;
  for (const auto& f : m.boundary(where)) {
    const auto nodes = f.node_span();
    for (size_t a = 0; a < nodes.size(); ++a)
      for (size_t b = a + 1; b < nodes.size(); ++b) {
        const auto& p = m.point(nodes[a]);
        const auto& q = m.point(nodes[b]);
        h = std::max(h, std::hypot(p[0] - q[0], p[1] - q[1], p[2] - q[2]));
      }
  }
  return h;
}

std::string describe(const physics::Body& b) {
  return fmt::format("body '{}'", b.name);
}

using contact::cross;
using contact::dot;
using contact::Vec3;
using contact::operator+;
using contact::operator-;
using contact::operator*;

Vec3 point3(const mesh::Point& p) {
  return {p[0], p[1], p[2]};
}

/// The simplices (local node indices) a cell is cut into for a point-in-cell test: Quad4 by
/// one diagonal, Hex8 into six tetrahedra around the diagonal 0–6 (VTK numbering). For a
/// distorted cell that is its shape only approximately, which suffices for what it is used
/// for: finding bodies that overlap by a sizeable part of a cell. A second-order cell is cut
/// as its corners are (its corners come first).
std::vector<std::vector<int>> simplices(mesh::CellType t) {
  switch (mesh::corner_type(t)) {
    case mesh::CellType::Tri3:
      return {{0, 1, 2}};
    case mesh::CellType::Quad4:
      return {{0, 1, 2}, {0, 2, 3}};
    case mesh::CellType::Tet4:
      return {{0, 1, 2, 3}};
    case mesh::CellType::Hex8:
      return {{0, 1, 2, 6}, {0, 2, 3, 6}, {0, 3, 7, 6}, {0, 7, 4, 6}, {0, 4, 5, 6}, {0, 5, 1, 6}};
    default:
      return {};  // corner_type is of first order
  }
  return {};
}

/// Whether p lies inside the simplex x (dim + 1 vertices) with every barycentric coordinate
/// above `margin` (points on its faces do not count).
bool strictly_inside(int dim, const std::vector<Vec3>& x, const Vec3& p, double margin) {
  // Barycentric coordinates by Cramer's rule on the edge vectors from x[0].
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], r = p - x[0];
  if (dim == 2) {
    const double det = e1[0] * e2[1] - e1[1] * e2[0];
    if (det == 0) return false;
    const double b1 = (r[0] * e2[1] - r[1] * e2[0]) / det;
    const double b2 = (e1[0] * r[1] - e1[1] * r[0]) / det;
    return b1 > margin && b2 > margin && 1 - b1 - b2 > margin;
  }
  const Vec3 e3 = x[3] - x[0];
  const double det = dot(e1, cross(e2, e3));
  if (det == 0) return false;
  const double b1 = dot(r, cross(e2, e3)) / det;
  const double b2 = dot(e1, cross(r, e3)) / det;
  const double b3 = dot(e1, cross(e2, r)) / det;
  return b1 > margin && b2 > margin && b3 > margin && 1 - b1 - b2 - b3 > margin;
}

/// The first cell of `body` whose centroid lies inside a cell of `other` (−1 if none), and
/// that cell: two bodies that overlap by more than half a cell. The gap check of the contact
/// pair sees only slave nodes within about one element of the master surface, so deeper
/// overlaps (a body inside the other) passed as "do not face each other".
std::pair<int, int> centroid_inside(const mesh::Mesh& body, const mesh::Mesh& other) {
  const int dim = body.dim();
  std::vector<contact::Aabb> boxes(static_cast<size_t>(other.n_cells()));
  for (int c = 0; c < other.n_cells(); ++c)
    for (const int a : other.cell(c)) boxes[static_cast<size_t>(c)].grow(point3(other.point(a)));
  const contact::AabbTree tree(boxes);
  std::vector<int> hits;
  std::vector<Vec3> x;
  for (int c = 0; c < body.n_cells(); ++c) {
    Vec3 centre{0, 0, 0};
    const auto nodes = body.cell(c);
    for (const int a : nodes)
      centre = centre + (1.0 / static_cast<double>(nodes.size())) * point3(body.point(a));
    contact::Aabb box;
    box.grow(centre);
    hits.clear();
    tree.query(box, hits);
    for (const int h : hits) {
      const auto on = other.cell(h);
      for (const auto& simplex : simplices(other.cell_type(h))) {
        x.clear();
        for (const int i : simplex) x.push_back(point3(other.point(on[static_cast<size_t>(i)])));
        if (strictly_inside(dim, x, centre, 1e-6)) return {c, h};
      }
    }
  }
  return {-1, -1};
}

}  // namespace

InitialContact initial_contact(const physics::Problem& p, size_t index) {
  const auto& c = p.contacts.at(index);
  const auto& slave = p.bodies[c.slave_body].mesh;
  const auto& master = p.bodies[c.master_body].mesh;
  const contact::MortarPair pair(slave, c.slave_where, master, c.master_where);
  InitialContact out;
  out.tolerance =
      1e-6 * std::max(largest_facet(slave, c.slave_where), largest_facet(master, c.master_where));
  const auto& gap = pair.gap();
  const auto& weights = pair.weights();
  out.contact_nodes = static_cast<int>(gap.size());
  for (size_t k = 0; k < gap.size(); ++k) {
    if (!(weights[k] > 0)) continue;
    const double g = gap[k] / weights[k];  // the weighted gap over ∫ψ_k: a distance
    if (out.deepest_node < 0 || g < out.smallest_gap) {
      out.smallest_gap = g;
      out.deepest_node = pair.contact_nodes()[k];
    }
  }
  return out;
}

std::vector<std::string> check_geometry(const physics::Problem& p) {
  std::vector<std::string> warnings;
  const std::string file = p.case_file.string();
  for (const auto& b : p.bodies) {
    const auto pairs = mesh::find_duplicate_nodes(b.mesh);
    if (pairs.empty()) continue;
    const auto& x = b.mesh.point(pairs[0].first);
    warnings.push_back(fmt::format(
        "{}: {}: {} pair{} of coincident nodes (first: nodes {} and {} at ({:g}, {:g}, {:g})): "
        "the cells on either side are not connected there; merge them (Gmsh: Coherence Mesh) "
        "unless the parts are meant to come apart",
        file, describe(b), pairs.size(), pairs.size() == 1 ? "" : "s", pairs[0].first,
        pairs[0].second, x[0], x[1], x[2]));
  }
  // Bodies overlapping by half a cell: once per pair of bodies, whatever their surfaces.
  std::set<std::pair<int, int>> overlap_checked;
  for (size_t i = 0; i < p.contacts.size(); ++i) {
    const auto& c = p.contacts[i];
    // "contact" alone with one pair, as the case file reads; the pair's name with several.
    const auto label =
        p.contacts.size() == 1 ? std::string("contact") : fmt::format("contact '{}'", c.name);
    const auto& slave = p.bodies[c.slave_body];
    const auto& master = p.bodies[c.master_body];
    if (overlap_checked.insert(std::minmax(c.slave_body, c.master_body)).second)
      for (const auto& [body, other] : {std::pair{&slave, &master}, std::pair{&master, &slave}}) {
        const auto [cell, inside] = centroid_inside(body->mesh, other->mesh);
        if (cell < 0) continue;
        throw MeshError(fmt::format(
            "{}: {}: {} and {} overlap at t = 0: the centre of cell {} of {} lies inside cell {} "
            "of {}; contact (2.6) needs the bodies apart or touching at the start: move them "
            "apart and prescribe the approach instead",
            file, label, describe(slave), describe(master), cell, describe(*body), inside,
            describe(*other)));
      }
    const auto ic = initial_contact(p, i);
    if (ic.deepest_node < 0) {
      warnings.push_back(fmt::format(
          "{}: {}: the slave surface '{}' of {} and the master surface '{}' of {} do not face "
          "each other at t = 0 (no slave node within one element of the master): contact "
          "starts only when the bodies come that close",
          file, label, c.slave_where, describe(slave), c.master_where, describe(master)));
      continue;
    }
    if (ic.smallest_gap < -ic.tolerance) {
      const auto& x = slave.mesh.point(ic.deepest_node);
      throw MeshError(fmt::format(
          "{}: {}: {} and {} overlap at t = 0: slave node {} at ({:g}, {:g}, {:g}) is {:.3g} m "
          "inside the master surface '{}' (tolerance {:.3g} m); contact (2.6) needs the bodies "
          "apart or touching at the start: move them apart and prescribe the approach instead",
          file, label, describe(slave), describe(master), ic.deepest_node, x[0], x[1], x[2],
          -ic.smallest_gap, c.master_where, ic.tolerance));
    }
  }
  return warnings;
}

}  // namespace tc::io
