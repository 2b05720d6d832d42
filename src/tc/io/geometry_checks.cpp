#include "tc/io/geometry_checks.hpp"

#include <fmt/format.h>

#include <cmath>

#include "tc/contact/mortar_pair.hpp"
#include "tc/core/error.hpp"

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

}  // namespace

InitialContact initial_contact(const physics::Problem& p) {
  const auto& c = *p.contact;
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
  if (!p.contact) return warnings;
  const auto& c = *p.contact;
  const auto ic = initial_contact(p);
  const auto& slave = p.bodies[c.slave_body];
  const auto& master = p.bodies[c.master_body];
  if (ic.deepest_node < 0) {
    warnings.push_back(fmt::format(
        "{}: contact: the slave surface '{}' of {} and the master surface '{}' of {} do not face "
        "each other at t = 0 (no slave node within one element of the master): contact starts "
        "only when the bodies come that close",
        file, c.slave_where, describe(slave), c.master_where, describe(master)));
    return warnings;
  }
  if (ic.smallest_gap < -ic.tolerance) {
    const auto& x = slave.mesh.point(ic.deepest_node);
    throw MeshError(fmt::format(
        "{}: contact: {} and {} overlap at t = 0: slave node {} at ({:g}, {:g}, {:g}) is {:.3g} m "
        "inside the master surface '{}' (tolerance {:.3g} m); contact (2.6) needs the bodies "
        "apart or touching at the start: move them apart and prescribe the approach instead",
        file, describe(slave), describe(master), ic.deepest_node, x[0], x[1], x[2],
        -ic.smallest_gap, c.master_where, ic.tolerance));
  }
  return warnings;
}

}  // namespace tc::io
