#include "tc/io/checks/case_checks.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>

#include "tc/core/error.hpp"
#include "tc/mesh/partition.hpp"
#include "tc/mesh/reference_cell.hpp"
#include "tc/model/checks.hpp"
#include "tc/record/history.hpp"

namespace tc::io::detail {

using physics::Problem;

std::optional<int> body_index(const TableReader& t, std::string_view k,
                              const std::vector<physics::Body>& bodies) {
  const auto name = t.string(k);
  if (!name) return std::nullopt;
  std::vector<std::string> known;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == *name) return static_cast<int>(i);
    known.push_back(bodies[i].name);
  }
  t.issue(k,
          fmt::format("found \"{}\", expected the name of a body: {}", *name, quoted_list(known)));
  return std::nullopt;
}

void check_boundary_name(const TableReader& t, std::string_view k, const physics::Body& body,
                         bool mesh_built, const std::string& where) {
  if (!mesh_built || body.mesh.has_boundary(where)) return;
  t.issue(k, fmt::format("found \"{}\", expected a boundary of body \"{}\": {}", where, body.name,
                         quoted_list(body.mesh.boundary_names())));
}

void check_subdomains(const TableReader& b, const physics::Body& body, bool mesh_built) {
  if (!mesh_built || body.subdomains <= 1) return;
  const int cells = body.mesh.n_cells();
  if (body.subdomains > cells) {
    b.issue("subdomains", fmt::format("found {}, more than the {} cells of the body's mesh; "
                                      "expected 1 to {} (at least one cell per subdomain)",
                                      body.subdomains, cells, cells));
    return;
  }
  // The run cuts the mesh with METIS (seeded: the same cut), which leaves parts empty on small
  // meshes (10 cells into 7): cut it here too so that `check` reports what `run` would.
  try {
    (void)mesh::partition_cells(body.mesh, body.subdomains);
  } catch (const MeshError& e) {
    b.issue("subdomains", fmt::format("found {}, which the body's mesh cannot be cut into: {}",
                                      body.subdomains, e.what()));
  }
}

namespace {

/// The diagonal of a mesh's bounding box [m].
double diameter(const mesh::Mesh& m) {
  if (m.n_nodes() == 0) return 0;
  mesh::Point lo = m.point(0), hi = lo;
  for (const auto& p : m.points())
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

double largest(const core::TimeTable& t) {
  return *std::max_element(t.values().begin(), t.values().end());
}

/// The largest Biot number h·ℓ/κ a film (or radiation, h = 4εσθ³) may have, ℓ the body's
/// diameter. The film's heat h(θ − θ∞) is taken from a face held within ~q/h of θ∞, whose
/// round-off ε·θ the product multiplies by h: the heat ledger's relative error grew as
/// ~5e-18·Bi (measured: 1.4e-9 at Bi = 2.8e8, 2e-8 at 2.8e9, 5.7e-5 at 2.8e12), and from
/// ~1e150 the products overflow. At 1e8 the ledger stays within the 1e-9 it is tested to,
/// and h may still be 10³ times any physical film (docs/choices.md).
constexpr double kMaxBiot = 1e8;

}  // namespace

void check_boundary_heat_scale(const TableReader& b, const physics::BoundaryCondition& bc,
                               const physics::Body& body, bool mesh_built,
                               double reference_temperature) {
  if (!bc.film && !bc.radiation) return;
  const double kappa = body.material.thermal_conductivity;
  if (!mesh_built || !(kappa > 0)) return;
  const double ell = diameter(body.mesh);
  const auto refuse = [&](std::string_view key, double h, std::string_view what) {
    const double biot = h * ell / kappa;
    if (biot <= kMaxBiot) return;
    b.issue(key, fmt::format("found {}, which gives body \"{}\" (size {:.3g} m, κ = {:g} W/(m·K)) "
                             "a Biot number h·ℓ/κ = {:.3g}, expected at most {:.0e}: double "
                             "precision cannot carry the heat through a face held this close "
                             "to the ambient temperature (prescribe temperature = ambient "
                             "instead)",
                             what, body.name, ell, kappa, biot, kMaxBiot));
  };
  if (bc.film) {
    const double h = largest(bc.film->coefficient);
    refuse("film", h, fmt::format("a film coefficient h = {:.3g} W/(m²K)", h));
  }
  if (bc.radiation) {
    // The radiation's conductance 4εσθ³ at the hottest temperature the case names for it.
    constexpr double sigma = 5.670374419e-8;
    const double theta =
        std::max({largest(bc.radiation->ambient), body.initial_temperature, reference_temperature});
    const double h = 4 * largest(bc.radiation->emissivity) * sigma * theta * theta * theta;
    refuse("radiation", h,
           fmt::format("a radiation to an ambient of {:.3g} K (its conductance 4εσθ³ = {:.3g} "
                       "W/(m²K) at {:.3g} K)",
                       largest(bc.radiation->ambient), h, theta));
  }
}

void check_contact_pairs(std::vector<physics::ContactSettings>& cs,
                         const std::vector<TableReader>& pairs,
                         const std::vector<physics::Body>& bodies) {
  if (cs.size() == 1 && !pairs[0].has("name")) cs[0].name = "contact";
  for (size_t j = 0; j < cs.size(); ++j) {
    const auto& t = pairs[j];
    if (cs.size() > 1 && !t.has("name"))
      t.issue("name", fmt::format("missing; expected a name (letters, digits, '_') for each of "
                                  "the {} [[contact]] pairs: it is the suffix of their "
                                  "history.csv columns (contact_normal_force_<name>)",
                                  cs.size()));
    // Each against the first earlier pair with the same name or slave surface.
    const auto earlier = [&](auto same) -> std::optional<std::string> {
      for (size_t i = 0; i < j; ++i)
        if (same(cs[i])) return fmt::format("{} (line {})", pairs[i].path(), pairs[i].line());
      return std::nullopt;
    };
    const auto& c = cs[j];
    if (!c.name.empty())
      if (const auto other = earlier([&](const auto& d) { return d.name == c.name; }))
        t.issue("name", fmt::format("found \"{}\", the name of {} too; expected a unique name "
                                    "per contact pair (it names their history.csv columns)",
                                    printable(c.name), *other));
    if (c.slave_body >= 0 && !c.slave_where.empty())
      if (const auto other = earlier([&](const auto& d) {
            return d.slave_body == c.slave_body && d.slave_where == c.slave_where;
          }))
        t.issue("slave",
                fmt::format("found the slave surface \"{}\" of body \"{}\", the slave surface "
                            "of {} too; expected each slave surface in one pair only (a "
                            "surface that touches two bodies: split it into two boundaries)",
                            c.slave_where, bodies[c.slave_body].name, *other));
    // The same interface with slave and master swapped: the two pairs' multipliers fought over
    // it, normal forces came out negative and the conducted heat reversed (issue 42 D6).
    if (c.slave_body >= 0 && c.master_body >= 0)
      if (const auto other = earlier([&](const auto& d) {
            return d.slave_body == c.master_body && d.slave_where == c.master_where &&
                   d.master_body == c.slave_body && d.master_where == c.slave_where;
          }))
        t.issue("slave",
                fmt::format("found the slave surface \"{}\" of body \"{}\" against the master "
                            "surface \"{}\" of body \"{}\": the interface of {} with slave and "
                            "master swapped; expected each interface in one [[contact]] pair only",
                            c.slave_where, bodies[c.slave_body].name, c.master_where,
                            bodies[c.master_body].name, *other));
  }
  // Distinct names can still give one column: "x" and "sum_x" both wrote
  // contact_tangential_force_sum_x, and "sum" gave the unsuffixed sum's name (issue 42 D7).
  if (cs.size() < 2) return;
  std::map<std::string, size_t> owner;  // column → its pair
  for (size_t j = 0; j < cs.size(); ++j) {
    if (cs[j].name.empty()) continue;
    for (const auto* base : physics::History::pair_columns()) {
      const std::string column = std::string(base) + "_" + cs[j].name;
      const auto standard = physics::History::standard_columns();
      if (std::find_if(standard.begin(), standard.end(),
                       [&](const char* c) { return column == c; }) != standard.end()) {
        pairs[j].issue("name", fmt::format("found \"{}\", which makes the pair's column {} the "
                                           "name of a column of all pairs; expected another "
                                           "name",
                                           printable(cs[j].name), column));
        break;
      }
      const auto [it, fresh] = owner.emplace(column, j);
      if (fresh || it->second == j) continue;
      const auto i = it->second;
      if (cs[i].name == cs[j].name) break;  // reported above as a repeated name
      pairs[j].issue("name", fmt::format("found \"{}\", whose history.csv column {} is also that "
                                         "of {} (line {}, name \"{}\"); expected names whose "
                                         "columns differ",
                                         printable(cs[j].name), column, pairs[i].path(),
                                         pairs[i].line(), printable(cs[i].name)));
      break;
    }
  }
}

namespace {

bool same_table(const core::TimeTable& a, const core::TimeTable& b) {
  return a.times() == b.times() && a.values() == b.values();
}

bool any_of(const std::array<std::optional<core::TimeTable>, 3>& c) {
  return c[0] || c[1] || c[2];
}

/// Two [[boundary]] tables of one body that prescribe a node's displacement component or
/// temperature differently (the later silently won), a traction on a face whose component
/// another table fixes (it did nothing), or two tables with displacements on one face (their
/// history columns reaction_<body>_<where>_… had one name). Equal values where faces share
/// nodes (a corner held by both of its faces) stay allowed.
void check_boundary_conflicts(const Problem& p, const toml::table& root, Issues& issues) {
  const auto* node = root.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  const auto& bcs = p.boundaries;
  const char* axes = "xyz";
  for (size_t j = 0; j < bcs.size(); ++j)
    // Each table against the earlier ones up to its first conflict: 300 equal tables on one
    // face printed 44 851 errors, every pair of them (issue 42 D22); now one per table.
    for (size_t i = 0, before = issues.size(); i < j && issues.size() == before; ++i) {
      const auto& first = bcs[i];
      const auto& later = bcs[j];
      if (first.body != later.body) continue;
      const int line = line_of(*a->get(j));
      const auto here = at("boundary", j);
      const auto other = fmt::format("boundary[{}] (line {})", i, line_of(*a->get(i)));
      const auto& body = p.bodies[static_cast<size_t>(later.body)];
      const bool first_cools = first.film || first.radiation;
      const bool later_cools = later.film || later.radiation;
      if (first.where == later.where &&
          ((first.temperature && later_cools) || (first_cools && later.temperature)))
        issues.add(line,
                   join(here, later.temperature ? "temperature"
                              : later.film      ? "film"
                                                : "radiation"),
                   fmt::format("found a film or radiation and a prescribed temperature on \"{}\" "
                               "of body \"{}\" (with {}); expected one of them: a prescribed "
                               "temperature leaves nothing for the film or radiation to change",
                               later.where, body.name, other));
      if (first.where == later.where &&
          ((first.temperature && later.heat_flux) || (first.heat_flux && later.temperature)))
        issues.add(line, join(here, later.temperature ? "temperature" : "heat_flux"),
                   fmt::format("found a heat flux and a prescribed temperature on \"{}\" of "
                               "body \"{}\" (with {}); expected one of them: a prescribed "
                               "temperature leaves nothing for the heat flux to change",
                               later.where, body.name, other));
      if (first.where == later.where && any_of(first.displacement) && any_of(later.displacement))
        issues.add(line, join(here, "displacement"),
                   fmt::format("found displacements on \"{}\" of body \"{}\", which {} "
                               "prescribes too; expected one [[boundary]] with displacements "
                               "per face (merge them: their reaction columns share a name)",
                               later.where, body.name, other));
      for (int k = 0; k < p.dimension; ++k)
        if (first.where == later.where && ((first.displacement[k] && later.traction[k]) ||
                                           (first.traction[k] && later.displacement[k])))
          issues.add(line, join(here, later.traction[k] ? "traction" : "displacement"),
                     fmt::format("found a traction and a displacement on component {} of "
                                 "\"{}\" of body \"{}\" (with {}); expected one of them (a "
                                 "traction on a fixed component does nothing)",
                                 axes[k], later.where, body.name, other));
      const auto where = first.where == later.where ? fmt::format("on \"{}\"", later.where)
                                                    : fmt::format("\"{}\" and \"{}\" share them",
                                                                  first.where, later.where);
      std::vector<int> shared;
      const auto na = body.mesh.boundary_nodes(first.where);
      const auto nb = body.mesh.boundary_nodes(later.where);
      std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(shared));
      if (shared.empty()) continue;
      for (int k = 0; k < p.dimension; ++k)
        if (first.displacement[k] && later.displacement[k] &&
            !same_table(*first.displacement[k], *later.displacement[k]))
          issues.add(line, at(join(here, "displacement"), k),
                     fmt::format("found another value for component {} of the displacement of "
                                 "{} node(s) that {} prescribes too ({}); expected the same value "
                                 "from both",
                                 axes[k], shared.size(), other, where));
      if (first.temperature && later.temperature &&
          !same_table(*first.temperature, *later.temperature))
        issues.add(line, join(here, "temperature"),
                   fmt::format("found another temperature for {} node(s) that {} prescribes "
                               "too ({}); expected the same value from both",
                               shared.size(), other, where));
    }
}

/// Faces under load control (force): their nodes carry one displacement per loaded component,
/// so no node of one may be prescribed, loaded by another face in that component, or touched by
/// a contact row; the body must be solved directly (not FETI), start at rest, and the contact
/// bodies may have one loaded component in all (a scalar root per QP: rigid_coupling.hpp).
void check_load_control(const Problem& p, const toml::table& root, Issues& issues) {
  const auto* node = root.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  const auto& bcs = p.boundaries;
  const char* axes = "xyz";
  int in_contact = 0;
  for (size_t j = 0; j < bcs.size(); ++j) {
    const auto& bc = bcs[j];
    if (!any_of(bc.force)) continue;
    const int line = line_of(*a->get(j));
    const auto key = join(at("boundary", j), "force");
    const auto& body = p.bodies[static_cast<size_t>(bc.body)];
    if (body.subdomains > 1)
      issues.add(line, key,
                 fmt::format("found a force on body \"{}\", which is cut into {} subdomains; "
                             "expected subdomains = 1 (load control is not implemented with "
                             "FETI bodies)",
                             body.name, body.subdomains));
    if (body.start_in_equilibrium && p.time.scheme == physics::Scheme::dynamic)
      issues.add(line, key,
                 fmt::format("found a force on body \"{}\" with initial_state = "
                             "\"equilibrium\"; expected initial_state = \"rest\" (the static "
                             "start does not solve for a loaded face)",
                             body.name));
    const auto nodes = body.mesh.boundary_nodes(bc.where);
    for (const auto& c : p.contacts)
      for (const auto& [b, where] :
           {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
        if (b != bc.body) continue;
        ++in_contact;
        const auto surface = body.mesh.boundary_nodes(*where);
        std::vector<int> shared;
        std::set_intersection(nodes.begin(), nodes.end(), surface.begin(), surface.end(),
                              std::back_inserter(shared));
        if (!shared.empty())
          issues.add(line, key,
                     fmt::format("found {} node(s) of \"{}\" on the contact surface \"{}\" of "
                                 "body \"{}\"; expected a loaded face apart from the contact "
                                 "surface",
                                 shared.size(), bc.where, *where, body.name));
      }
    for (size_t i = 0; i < bcs.size(); ++i) {
      const auto& other = bcs[i];
      if (i == j || other.body != bc.body) continue;
      std::vector<int> shared;
      const auto on = body.mesh.boundary_nodes(other.where);
      std::set_intersection(nodes.begin(), nodes.end(), on.begin(), on.end(),
                            std::back_inserter(shared));
      if (shared.empty()) continue;
      for (int k = 0; k < p.dimension; ++k)
        if (bc.force[k] && (other.displacement[k] || (other.force[k] && i < j)))
          issues.add(line, at(key, k),
                     fmt::format("found {} node(s) of \"{}\" whose component {} boundary[{}] "
                                 "(line {}) {} too; expected the nodes of a loaded face free "
                                 "of other displacements and forces in that component",
                                 shared.size(), bc.where, axes[k], i, line_of(*a->get(i)),
                                 other.displacement[k] ? "prescribes" : "loads"));
    }
  }
  if (in_contact > 0) {
    int loaded = 0;
    for (const auto& bc : bcs) {
      bool contact_body = false;
      for (const auto& c : p.contacts)
        contact_body = contact_body || c.slave_body == bc.body || c.master_body == bc.body;
      if (contact_body)
        for (int k = 0; k < p.dimension; ++k) loaded += bc.force[k] ? 1 : 0;
    }
    if (loaded > 1)
      issues.add(line_of(*a->get(0)), "boundary",
                 fmt::format("found {} loaded force components on the bodies in contact; "
                             "expected at most one (load control in contact solves for one "
                             "face displacement)",
                             loaded));
  }
}

void check_reaction_columns(const Problem& p, const toml::table& root, Issues& issues) {
  const auto* node = root.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  std::map<std::string, size_t> owner;  // reaction_<body>_<where> → its [[boundary]]
  const auto& bcs = p.boundaries;
  for (size_t j = 0; j < bcs.size(); ++j) {
    if (!any_of(bcs[j].displacement)) continue;
    const auto& body = p.bodies[static_cast<size_t>(bcs[j].body)];
    const auto label = fmt::format("reaction_{}_{}", body.name, bcs[j].where);
    const auto [it, fresh] = owner.emplace(label, j);
    // The same face of the same body in two tables is one support (BodySystem::add_boundary).
    if (fresh || (bcs[it->second].body == bcs[j].body && bcs[it->second].where == bcs[j].where))
      continue;
    const auto& first = bcs[it->second];
    issues.add(line_of(*a->get(j)), join(at("boundary", j), "where"),
               fmt::format("found \"{}\" of body \"{}\", whose history.csv columns {}_x|y|z "
                           "are also those of boundary[{}] (line {}: \"{}\" of body \"{}\"); "
                           "expected body and boundary names whose reaction columns differ",
                           bcs[j].where, body.name, label, it->second, line_of(*a->get(it->second)),
                           first.where, p.bodies[static_cast<size_t>(first.body)].name));
  }
}

void check_massless_cells(const Problem& p, const toml::table& root, Issues& issues) {
  if (p.time.scheme != physics::Scheme::dynamic ||
      p.time.contact_scheme != physics::ContactScheme::modified_mass)
    return;
  // The scheme's nodes: every contact surface of the body, of any pair (BodySystem). A cell
  // with all of them has no massive node to carry its mass (fem::singular_mass_u): the run
  // stopped with exit 1 where this is an input to change (issue 42 D9).
  const auto& bodies = *root.get("bodies")->as_array();
  for (size_t b = 0; b < p.bodies.size(); ++b) {
    std::vector<char> massless;
    std::vector<std::string> surfaces;
    for (const auto& c : p.contacts)
      for (const auto& [body, where] :
           {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
        if (body != static_cast<int>(b)) continue;
        const auto& m = p.bodies[b].mesh;
        massless.resize(static_cast<size_t>(m.n_nodes()), 0);
        for (const int n : m.boundary_nodes(*where)) massless[static_cast<size_t>(n)] = 1;
        surfaces.push_back("\"" + *where + "\"");
      }
    if (massless.empty()) continue;
    const auto& m = p.bodies[b].mesh;
    for (int c = 0; c < m.n_cells(); ++c) {
      const auto nodes = m.cell(c);
      if (!std::all_of(nodes.begin(), nodes.end(),
                       [&](int n) { return massless[static_cast<size_t>(n)] != 0; }))
        continue;
      issues.add(line_of(*bodies.get(b)), at("bodies", b),
                 fmt::format("found body \"{}\" with cell {} (0-based) that has every node on "
                             "its contact surface(s) {}: the modified mass scheme "
                             "(contact_scheme = \"modified_mass\") takes the mass off those "
                             "nodes and leaves that cell none; expected at least two cells "
                             "through the body's thickness under a contact surface (refine the "
                             "mesh across it), or contact_scheme = \"stabilised\"",
                             p.bodies[b].name, c, fmt::join(surfaces, ", ")));
      break;
    }
  }
}

/// A quasistatic body, and one that starts in static equilibrium, must be held against every
/// rigid motion: K_u is singular otherwise.
void check_quasistatic_bodies_held(const Problem& p, const toml::table& root, Issues& issues) {
  const bool quasistatic = p.time.scheme == physics::Scheme::quasistatic;
  const auto& bodies = *root.get("bodies")->as_array();
  for (size_t b = 0; b < p.bodies.size(); ++b) {
    if (!quasistatic && !p.bodies[b].start_in_equilibrium) continue;
    if (const int n = physics::free_rigid_modes(p, static_cast<int>(b)); n > 0)
      issues.add(line_of(*bodies.get(b)), at("bodies", b),
                 quasistatic
                     ? fmt::format("found body \"{}\" with {} rigid-body motion(s) left free by "
                                   "its displacement boundaries, expected a quasistatic body "
                                   "held by [[boundary]] displacements (or scheme = \"dynamic\")",
                                   p.bodies[b].name, n)
                     : fmt::format("found body \"{}\" with initial_state = \"equilibrium\" and "
                                   "{} rigid-body motion(s) left free by its displacement "
                                   "boundaries, expected a body held by [[boundary]] "
                                   "displacements (or initial_state = \"rest\")",
                                   p.bodies[b].name, n));
  }
}

/// E(θ), ν(θ) refactorise A_u when θ moves them (Simulation::refresh_moduli): a direct factor
/// only. FETI's subdomain factors and a face under load control (Φ = A_u⁻¹ formed once) are
/// built once per run, so such a body is refused rather than run with stale moduli.
void check_modulus_tables(const Problem& p, const toml::table& root, Issues& issues) {
  const auto& bodies = *root.get("bodies")->as_array();
  for (size_t b = 0; b < p.bodies.size(); ++b) {
    const auto& body = p.bodies[b];
    if (!body.material.nonlinear_moduli() || body.subdomains <= 1) continue;
    const auto* t = bodies.get(b)->as_table();
    const auto* n = t ? t->get("subdomains") : nullptr;
    issues.add(line_of(n ? *n : *bodies.get(b)), join(at("bodies", b), "subdomains"),
               fmt::format("found {} subdomains for body \"{}\", whose material \"{}\" has "
                           "young_modulus or poisson_ratio as a table in θ; expected "
                           "subdomains = 1 (A_u is refactorised when θ moves E, ν; FETI's "
                           "subdomain factors are built once per run)",
                           body.subdomains, body.name, body.material_name));
  }
  const auto* node = root.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  for (size_t j = 0; j < p.boundaries.size(); ++j) {
    const auto& bc = p.boundaries[j];
    const auto& body = p.bodies[static_cast<size_t>(bc.body)];
    if (!any_of(bc.force) || !body.material.nonlinear_moduli()) continue;
    issues.add(line_of(*a->get(j)), join(at("boundary", j), "force"),
               fmt::format("found a force on body \"{}\", whose material \"{}\" has "
                           "young_modulus or poisson_ratio as a table in θ; expected a "
                           "displacement or a traction (load control forms A_u⁻¹ of the face "
                           "once per run, A_u is refactorised when θ moves E, ν)",
                           body.name, body.material_name));
  }
}

}  // namespace

void check_across_sections(const Problem& p, const toml::table& root, Issues& issues) {
  if (issues.empty()) check_boundary_conflicts(p, root, issues);
  if (issues.empty()) check_load_control(p, root, issues);
  if (issues.empty()) check_modulus_tables(p, root, issues);
  if (issues.empty()) check_reaction_columns(p, root, issues);
  if (issues.empty()) check_quasistatic_bodies_held(p, root, issues);
  if (issues.empty()) check_massless_cells(p, root, issues);
}

}  // namespace tc::io::detail
