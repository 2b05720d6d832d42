// CaseReader: [[bodies]] and their meshes (box or Gmsh file), loads, subdomains.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "tc/core/numeric/petsc.hpp"
#include "tc/io/case/auto_subdomains.hpp"
#include "tc/io/case/case_reader_detail.hpp"
#include "tc/io/checks/case_checks.hpp"
#include "tc/io/files/files.hpp"
#include "tc/linalg/cholesky_solver.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/gmsh/gmsh_reader.hpp"
#include "tc/mesh/partition.hpp"

namespace tc::io::detail {

namespace {

/// The most cells a box mesh may have (far beyond what a run on one machine can hold).
constexpr long kMaxBoxCells = 100'000'000;

}  // namespace

void CaseReader::read_bodies(const TableReader& root) {
  const auto* a = tables(root, "bodies");
  if (!a) return;
  std::set<std::string> names;
  for (size_t i = 0; i < a->size(); ++i) {
    read_body(*a->get(i)->as_table(), i);
    const auto& name = p_.bodies.back().name;
    if (!name.empty() && !names.insert(name).second)
      issues_.add(line_of(*a->get(i)->as_table()->get("name")), join(at("bodies", i), "name"),
                  fmt::format("found \"{}\" again, expected a unique body name", printable(name)));
  }
}

int CaseReader::factor_ranks(const TableReader& root) const {
  // [solver] is read after the bodies, so its key is looked at here directly.
  std::string package;
  if (const auto* solver = root.table().get_as<toml::table>("solver"))
    package = (*solver)["factorization"].value_or(std::string());
  return linalg::ranks_sharing_a_factor(package == "auto" ? std::string() : package);
}

void CaseReader::resolve_auto_subdomains(const TableReader& root) {
  const auto* node = root.get("bodies");  // read_bodies said what is wrong with it, if anything
  const auto* bodies = node ? node->as_array() : nullptr;
  if (!bodies || bodies->size() != p_.bodies.size()) return;
  // One budget for all bodies: they are in memory together. The cost model and its
  // measurements: docs/choices.md.
  const int ranks = factor_ranks(root);
  // A contact body's compliance has a right-hand side per multiplier of its pairs: the slave
  // surface's nodes, dim each (what FETI pays block solves for at each sliding step).
  std::vector<double> columns(p_.bodies.size(), 0.0);
  for (const auto& c : p_.contacts) {
    const auto s = static_cast<size_t>(c.slave_body), m = static_cast<size_t>(c.master_body);
    if (s >= p_.bodies.size() || m >= p_.bodies.size() || !mesh_built_[s] ||
        !p_.bodies[s].mesh.has_boundary(c.slave_where))
      continue;
    const double rows =
        dim_ * static_cast<double>(p_.bodies[s].mesh.boundary_nodes(c.slave_where).size());
    columns[s] += rows;
    if (m != s) columns[m] += rows;
  }
  for (auto& body : p_.bodies)  // E(θ), ν(θ): A_u refactorised, which FETI's factors are not
    if (body.subdomains == 0 && body.material.nonlinear_moduli()) {
      body.subdomains = 1;
      body.subdomains_reason = "E(θ) or ν(θ): a direct factor, refactorised when θ moves them";
    }
  if (std::none_of(p_.bodies.begin(), p_.bodies.end(),
                   [](const physics::Body& b) { return b.subdomains == 0; }))
    return;  // every count set by the case: nothing to estimate
  std::vector<size_t> automatic;
  std::vector<BodyCosts> costs;
  double fixed = 0;  // the bodies with one subdomain set take their share first
  for (size_t i = 0; i < p_.bodies.size(); ++i) {
    const auto& body = p_.bodies[i];
    if (!mesh_built_[i] || (body.subdomains != 0 && body.subdomains != 1)) continue;
    auto c = body_costs(body.mesh, dim_, ranks, columns[i]);
    if (body.subdomains == 1)
      fixed += c.direct_bytes;
    else
      automatic.push_back(i), costs.push_back(std::move(c));
  }
  // The steps weigh the factorisations against the steps' costs; [time] may be invalid here
  // (reported with the other issues at the end of the reading): one step then.
  const double steps = p_.time.step > 0 && p_.time.end > 0 ? p_.time.end / p_.time.step : 1.0;
  const int n_steps =
      std::isfinite(steps) ? static_cast<int>(std::clamp(std::round(steps), 1.0, 1e8)) : 1;
  const auto chosen = choose_subdomains(costs, auto_budget(fixed), n_steps);
  for (auto& body : p_.bodies)
    if (body.subdomains == 0) body.subdomains = 1;  // a body whose mesh failed: left as 1
  for (size_t k = 0; k < automatic.size(); ++k) {
    const size_t i = automatic[k];
    auto& body = p_.bodies[i];
    body.subdomains_reason = chosen.reasons[k];
    if (chosen.subdomains[k] == 1) continue;
    body.subdomains = std::min(chosen.subdomains[k], body.mesh.n_cells());
    try {
      (void)mesh::partition_cells(body.mesh, body.subdomains);
    } catch (const MeshError& e) {
      issues_.add(line_of(*bodies->get(i)->as_table()), join(at("bodies", i), "subdomains"),
                  fmt::format("\"auto\" chose {} subdomains ({}), which the body's mesh cannot "
                              "be cut into: {}; expected a number that it can",
                              body.subdomains, chosen.reasons[k], e.what()));
    }
  }
}

void CaseReader::read_body(const toml::table& t, size_t index) {
  const TableReader b(t, at("bodies", index), issues_, schema::section("bodies"));
  physics::Body body;
  mesh_built_.push_back(false);
  if (const auto name = b.string("name")) {
    check_name(b, "name", *name, "output file names and history.csv columns");
    body.name = *name;
  }
  if (const auto mat = b.string("material")) {
    body.material_name = *mat;
    if (const auto it = materials_.find(*mat); it != materials_.end()) {
      if (it->second) body.material = *it->second;
    } else {
      std::vector<std::string> known;
      for (const auto& [k, v] : materials_) known.push_back(k);
      b.issue("material", fmt::format("found \"{}\", expected a material defined under "
                                      "[materials]: {}",
                                      *mat, quoted_list(known)));
    }
  }
  read_mesh(b, body);
  read_body_loads(b, body);
  body.material.evaluate_laws_at(body.initial_temperature);
  body.subdomains = 0;  // "auto", resolved by read_bodies once every body is known
  if (const auto* n = b.get("subdomains");
      n && !(n->is_string() && n->as_string()->get() == "auto")) {
    if (n->is_string())
      b.issue("subdomains", fmt::format("found \"{}\", expected \"auto\" or a whole number "
                                        "of subdomains",
                                        printable(n->as_string()->get())));
    else if (const auto s = b.integer("subdomains")) {
      body.subdomains = *s;
      check_subdomains(b, body, mesh_built_.back());
    }
  }
  p_.bodies.push_back(std::move(body));
}

void CaseReader::read_body_loads(const TableReader& b, physics::Body& body) {
  body.initial_temperature = p_.physics.reference_temperature;
  if (const auto v = b.number("initial_temperature")) body.initial_temperature = *v;
  if (const auto* n = b.get("initial_velocity"))
    if (const auto v = read_vector(*n, b.key("initial_velocity"), issues_, dim_))
      body.initial_velocity = *v;
  if (const auto s = b.choice("initial_state")) body.start_in_equilibrium = *s == "equilibrium";
  if (const auto* n = b.get("body_force"))
    if (const auto f = read_components(*n, b.key("body_force"), issues_, dim_, false))
      for (int k = 0; k < 3; ++k)
        if ((*f)[k]) body.body_force[k] = *(*f)[k];
  if (const auto* n = b.get("heat_source"))
    if (const auto r = read_time_table(*n, b.key("heat_source"), issues_)) body.heat_source = *r;
}

void CaseReader::read_mesh(const TableReader& b, physics::Body& body) {
  const auto mesh = b.sub_table("mesh");
  if (!mesh) return;
  if (mesh->has("box") == mesh->has("file")) {
    issues_.add(mesh->line(), mesh->path(),
                fmt::format("found {}, expected exactly one of box = {{ min, max, cells }} or "
                            "file = \"NAME.msh\"",
                            mesh->has("box") ? "both box and file" : "neither box nor file"));
    return;
  }
  if (mesh->has("file")) return read_mesh_file(*mesh, body);
  if (const auto box = mesh->sub_table("box")) read_box(*box, body);
}

void CaseReader::read_box(const TableReader& box, physics::Body& body) {
  const auto* lo_node = box.get("min");
  const auto* hi_node = box.get("max");
  const auto* cells_node = box.get("cells");
  const auto lo = lo_node ? read_vector(*lo_node, box.key("min"), issues_, dim_) : std::nullopt;
  const auto hi = hi_node ? read_vector(*hi_node, box.key("max"), issues_, dim_) : std::nullopt;
  const auto cells =
      cells_node ? read_counts(*cells_node, box.key("cells"), issues_, dim_) : std::nullopt;
  const auto element = box.choice("element");
  if (!lo || !hi || !cells || dim_ == 0) return;
  // The cell type of the name (the choices are the mesh's names of the types).
  std::optional<mesh::CellType> type;
  for (int t = 0; element && t <= static_cast<int>(mesh::CellType::Hex27); ++t)
    if (*element == mesh::name(mesh::CellType(t))) type = mesh::CellType(t);
  if (type && mesh::dimension(*type) != dim_) {
    box.issue("element", fmt::format("found \"{}\", a {}D cell, expected a cell of the case's "
                                     "dimension {}",
                                     *element, mesh::dimension(*type), dim_));
    return;
  }
  bool good = true;
  for (int k = 0; k < dim_; ++k)
    if (!((*hi)[k] > (*lo)[k])) {
      box.issue("max", fmt::format("found max[{}] = {} ≤ min[{}] = {}, expected max > min on "
                                   "every axis",
                                   k, (*hi)[k], k, (*lo)[k]));
      good = false;
    }
  if (!good || !box_size_ok(box, *cells)) return;
  try {
    body.mesh = type ? mesh::make_box(dim_, *lo, *hi, *cells, *type)
                     : mesh::make_box(dim_, *lo, *hi, *cells);
    // Boxes whose cells round to nothing (max = [1e-320, …], or coordinates near 1e20 with a
    // width below their precision): reported here, at the key, not as "K_u not finite" or a
    // Jacobian without a file later (issue 20, #14).
    mesh::check_cells(body.mesh, fmt::format("body \"{}\"", body.name));
    mesh_built_.back() = true;
  } catch (const MeshError& e) {
    issues_.add(box.line(), box.path(), fmt::format("cannot build the box: {}", e.what()));
  }
}

bool CaseReader::box_size_ok(const TableReader& box, const std::array<int, 3>& cells) const {
  // Each count is at most 10⁹, their product is not: make_box counts cells and nodes in int
  // (cells = [100000, 100000] overflowed it), and memory runs out long before.
  double total = 1;
  for (int k = 0; k < dim_; ++k) total *= cells[k];
  if (total > static_cast<double>(kMaxBoxCells)) {
    box.issue("cells", fmt::format("found {:.0f} cells in all, which is too many; expected at "
                                   "most {} cells in a box",
                                   total, kMaxBoxCells));
    return false;
  }
  const double need = box_memory(dim_, cells), have = memory_per_rank();
  if (have <= 0 || need <= have) return true;
  box.issue("cells", fmt::format("found {:.0f} cells, whose mesh and matrices alone need about "
                                 "{:.1f} GiB (before any factorisation), expected a box that "
                                 "fits in this machine's {:.1f} GiB{}",
                                 total, need / kGiB, physical_memory() / kGiB, shared_by_ranks()));
  return false;
}

void CaseReader::read_mesh_file(const TableReader& mesh, physics::Body& body) {
  const auto name = mesh.string("file", Need::required);
  if (!name || dim_ == 0) return;
  const auto path = resolve(*name);
  if (const auto why = not_a_file(path); !why.empty()) {
    mesh.issue("file", fmt::format("found \"{}\" ({}), which {}; expected a Gmsh 4 file, "
                                   "relative to the case file",
                                   *name, path.string(), why));
    return;
  }
  try {
    body.mesh = mesh::read_gmsh(path, dim_);
    body.mesh_file = path;
    mesh_built_.back() = true;
  } catch (const MeshError& e) {
    mesh.issue("file", fmt::format("found a mesh that cannot be used: {}", e.what()));
  }
}

}  // namespace tc::io::detail
