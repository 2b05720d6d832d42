#include "tc/io/case_reader.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "tc/core/petsc.hpp"
#include "tc/io/auto_subdomains.hpp"
#include "tc/io/case_overrides.hpp"
#include "tc/io/case_schema.hpp"
#include "tc/io/files.hpp"
#include "tc/mesh/box.hpp"
#include "tc/mesh/gmsh_reader.hpp"
#include "tc/mesh/partition.hpp"
#include "tc/physics/checks.hpp"
#include "tc/physics/history.hpp"

namespace tc::io {

namespace {

namespace fs = std::filesystem;
using detail::Need;
using detail::non_negative;
using detail::positive;
using detail::Range;
using detail::TableReader;
using physics::Problem;

/// The most steps a run may have: well inside the int step counter, and far more than a run
/// that ends in reasonable time (end = 4294967.301, step = 0.001 wrapped round to 5 steps).
constexpr long kMaxSteps = 100'000'000;

/// The most cells a box mesh may have (far beyond what a run on one machine can hold).
constexpr long kMaxBoxCells = 100'000'000;

const Range kTemperature{[](double x) { return x > 0; }, "a temperature > 0 K"};

/// Longest body or boundary name that may reach a file name or a history.csv column.
constexpr size_t kMaxNameLength = 64;

/// Longest `title` (bytes): summary.json holds it and is rewritten after every step.
constexpr size_t kMaxTitleLength = 4096;

/// `s` with control and non-ASCII bytes as \xNN, so that a reported value stays on its line.
std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    out += u < 0x20 || u >= 0x7F ? fmt::format("\\x{:02X}", u) : std::string(1, c);
  }
  return out;
}

/// Why `name` cannot be used as a body or boundary name, or "" when it can. Such names are
/// written unescaped into file names (<body>_<step>.vtu, listed in result.pvd's XML) and into
/// history.csv's header (reaction_<body>_<where>_x): "../../evil" wrote outside the output
/// directory, "a,b" shifted every column after it.
std::string unsafe_name(std::string_view name) {
  if (name.empty()) return "an empty name";
  if (name.size() > kMaxNameLength)
    return fmt::format("a name of {} characters, more than {}", name.size(), kMaxNameLength);
  if (name.front() == '.') return "a name that starts with '.'";
  // A leading '-' reads as an option where the name reaches a command line (`--output_0.vtu`,
  // `-rf`), a leading '_' runs it into the column prefix (reaction__x): the rule of
  // case-format.md, "(not first)", for all three (issue 42 D21).
  if (name.front() == '-' || name.front() == '_')
    return fmt::format("a name that starts with '{}'", name.front());
  for (const char c : name) {
    const bool safe = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '_' || c == '-' || c == '.';
    if (!safe) return fmt::format("a name with the character '{}'", printable({&c, 1}));
  }
  return "";
}

/// An issue at member k when its string value is not a safe name (see unsafe_name).
void check_name(const TableReader& t, std::string_view k, const std::string& name,
                std::string_view used_in) {
  if (const auto why = unsafe_name(name); !why.empty())
    t.issue(k, fmt::format("found \"{}\", {}; expected 1 to {} letters, digits, '_', '-' or '.' "
                           "(not first): it is used in {}",
                           printable(name), why, kMaxNameLength, used_in));
}

/// An issue at a contact pair's `name` when it is not 1 to kMaxNameLength letters,
/// digits or '_': it becomes the suffix of history.csv columns (contact_normal_force_<name>).
void check_pair_name(const TableReader& t, const std::string& name) {
  std::string why;
  if (name.empty())
    why = "an empty name";
  else if (name.size() > kMaxNameLength)
    why = fmt::format("a name of {} characters, more than {}", name.size(), kMaxNameLength);
  for (const char c : name) {
    if (!why.empty()) break;
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_'))
      why = fmt::format("a name with the character '{}'", printable({&c, 1}));
  }
  if (!why.empty())
    t.issue("name", fmt::format("found \"{}\", {}; expected 1 to {} letters, digits or '_': it "
                                "is the suffix of the pair's history.csv columns "
                                "(contact_normal_force_<name>)",
                                printable(name), why, kMaxNameLength));
}

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

/// A lower bound of the memory a box body takes before any factorisation [bytes]: its mesh
/// and the five matrices that BodySystem assembles for the whole body (M_u, K_u, K_uθ, M_θ,
/// K_θ; AIJ, 12 bytes per nonzero, rows of 3^dim nodes). A box that does not fit it was
/// allocated until the OOM killer ended the process without a message (issue 20, #3).
double box_memory(int dim, const std::array<int, 3>& cells) {
  double nodes = 1, n_cells = 1;
  for (int k = 0; k < dim; ++k) nodes *= cells[k] + 1.0, n_cells *= cells[k];
  const double per_row = dim == 3 ? 27 : 9;           // nodes coupled to a node
  const double blocks = 2.0 * dim * dim + dim + 2.0;  // scalar blocks of the five matrices
  const double corners = dim == 3 ? 8 : 4;
  return nodes * (per_row * blocks * 12.0 + per_row * 4.0 + 24.0) + n_cells * (corners + 2) * 4.0;
}

/// This machine's physical memory [bytes] (0 if unknown).
double physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0.0;
}

/// A rank's share of it: every rank holds every body and its direct factors (docs/choices.md,
/// "Replicated state"), so the ranks on one node each need what one rank alone would.
double memory_per_rank() {
  return physical_memory() / static_cast<double>(std::max(core::PetscSession::node_size(), 1));
}

/// " shared by N ranks" when more than one rank of the run is on this node, else "".
std::string shared_by_ranks() {
  const int n = core::PetscSession::node_size();
  return n > 1 ? fmt::format(" shared by {} ranks", n) : std::string();
}

std::string quoted_list(const std::vector<std::string>& names) {
  if (names.empty()) return "(none)";
  std::string out;
  for (const auto& n : names) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", n);
  return out;
}

/// Reads one case file section by section into a Problem, collecting every issue; throws them
/// all at the end. Meshes are built on the way so boundary names can be checked.
class CaseReader {
 public:
  CaseReader(fs::path file, const toml::table& root)
      : file_(std::move(file)), issues_(file_.string()), root_(root) {}

  Problem read();

 private:
  void read_dimension(const TableReader& root);
  void read_time(const TableReader& root);
  void read_physics(const TableReader& root);
  void read_materials(const TableReader& root);
  void read_bodies(const TableReader& root);
  void read_body(const toml::table& t, size_t index);
  void read_body_loads(const TableReader& b, physics::Body& body);
  /// Issue when the body's mesh cannot be cut into its subdomains (as the run would find).
  void check_subdomains(const TableReader& b, const physics::Body& body);
  /// `subdomains = "auto"` (or absent) → 1, or FETI subdomains where the direct factorisation
  /// would not fit comfortably (auto_subdomains).
  void resolve_auto_subdomains(const TableReader& root, const toml::array& bodies);
  /// The ranks a direct body's factor is spread over (1: each rank factorises it).
  [[nodiscard]] int factor_ranks(const TableReader& root) const;
  void read_mesh(const TableReader& b, physics::Body& body);
  void read_box(const TableReader& box, physics::Body& body);
  void read_mesh_file(const TableReader& mesh, physics::Body& body);
  /// Issue when a box has more cells in all than kMaxBoxCells.
  [[nodiscard]] bool box_size_ok(const TableReader& box, const std::array<int, 3>& cells) const;
  void read_boundaries(const TableReader& root);
  void read_boundary(const toml::table& t, size_t index);
  /// film = { coefficient, ambient } and radiation = { emissivity, ambient } of a [[boundary]].
  void read_boundary_heat(const TableReader& b, physics::BoundaryCondition& bc);
  /// `contact`: one [contact] table or an array of [[contact]] tables, one pair each.
  void read_contacts(const TableReader& root);
  /// One pair at `path` ("contact" or "contact[i]"), appended to p_.contacts.
  TableReader read_contact(const toml::table& t, std::string path);
  /// Names (a default for a lone pair, required for several, unique) and slave surfaces (one
  /// pair each) across the pairs; `pairs[i]` is the table of p_.contacts[i].
  void check_contact_pairs(const std::vector<TableReader>& pairs);
  void read_conductance(const TableReader& contact, physics::ContactSettings& c);
  void read_solver(const TableReader& root);
  void read_output(const TableReader& root);
  void check_quasistatic_bodies_held();
  void check_boundary_conflicts();
  void check_load_control();
  /// Issue when a film or radiation on boundary `bc` is so strong against the body's
  /// conduction that double precision cannot carry its heat (docs/choices.md, "Film and
  /// radiation bounded by the Biot number").
  void check_boundary_heat_scale(const TableReader& b, const physics::BoundaryCondition& bc);
  /// Issue for a contact body whose cell has every node on its contact surfaces when the
  /// modified mass scheme makes those nodes massless (the run could not build M_u).
  void check_massless_cells();
  /// Issue for two [[boundary]] tables whose reaction columns reaction_<body>_<where>_x|y|z
  /// have one name (body "a" at "xmin_ymin", body "a_xmin" at "ymin").
  void check_reaction_columns();
  /// Warnings for values that are valid but implausible in SI (unit habits: MPa, °C, g/cm³).
  void warn_unit_habits();
  /// A warning `FILE:LINE: KEY: message` (the line of `key`, a dotted path, if known).
  void warn(const std::string& key, const std::string& message);

  /// The array of tables at `key` ([[key]]), or an issue.
  const toml::array* tables(const TableReader& root, std::string_view key, Need need);
  /// Index of the body named at member k, or an issue listing the bodies.
  std::optional<int> body_index(const TableReader& t, std::string_view k);
  /// Issue when body b's mesh (if built) has no boundary named at member k.
  void check_boundary_name(const TableReader& t, std::string_view k, int b,
                           const std::string& where);
  [[nodiscard]] fs::path resolve(const std::string& path) const {
    const fs::path p(path);
    return p.is_absolute() ? p : file_.parent_path() / p;
  }

  fs::path file_;
  detail::Issues issues_;
  const toml::table& root_;
  Problem p_;
  int dim_ = 0;  // 0 while unknown (missing or invalid): lengths are then checked loosely
  std::map<std::string, std::optional<fem::Material>> materials_;  // nullopt: bad constants
  std::vector<bool> mesh_built_;                                   // per body
};

Problem CaseReader::read() {
  p_.case_file = file_;
  const TableReader root(root_, "", issues_,
                         {"title", "dimension", "time", "physics", "materials", "bodies",
                          "boundary", "contact", "solver", "output"});
  if (const auto t = root.string("title", Need::optional)) {
    // The title is copied into summary.json after every step: a 10 MB title cost 0.25 s a
    // step (issue 42). A title is a line or a paragraph, not a document.
    if (t->size() > kMaxTitleLength)
      root.issue("title", fmt::format("found a title of {} characters, expected at most {}",
                                      t->size(), kMaxTitleLength));
    else
      p_.title = *t;
  }
  read_dimension(root);
  read_time(root);
  read_physics(root);
  read_materials(root);
  read_bodies(root);
  read_boundaries(root);
  read_contacts(root);
  read_solver(root);
  read_output(root);
  if (issues_.empty()) check_boundary_conflicts();
  if (issues_.empty()) check_load_control();
  if (issues_.empty()) check_reaction_columns();
  if (issues_.empty()) check_quasistatic_bodies_held();
  if (issues_.empty()) check_massless_cells();
  if (!issues_.empty()) issues_.raise();
  warn_unit_habits();
  return std::move(p_);
}

void CaseReader::read_dimension(const TableReader& root) {
  const auto* n = root.get("dimension", Need::required, "2 (plane strain) or 3");
  if (!n) return;
  const auto* i = n->as_integer();
  if (!i || (i->get() != 2 && i->get() != 3)) {
    root.issue("dimension",
               fmt::format("found {}, expected 2 or 3 (2: plane strain)", detail::describe(*n)));
    return;
  }
  dim_ = static_cast<int>(i->get());
  p_.dimension = dim_;
}

void CaseReader::read_time(const TableReader& root) {
  const auto t =
      root.sub_table("time", Need::required, {"scheme", "step", "end", "contact_scheme"});
  if (!t) return;
  if (const auto s = t->choice("scheme", Need::optional, {"dynamic", "quasistatic"}))
    p_.time.scheme = *s == "dynamic" ? physics::Scheme::dynamic : physics::Scheme::quasistatic;
  if (const auto s =
          t->choice("contact_scheme", Need::optional, {"stabilised", "plain", "modified_mass"}))
    p_.time.contact_scheme = *s == "plain"           ? physics::ContactScheme::plain
                             : *s == "modified_mass" ? physics::ContactScheme::modified_mass
                                                     : physics::ContactScheme::stabilised;
  const auto step = t->number("step", Need::required, positive("a time step"));
  const auto end = t->number("end", Need::required, positive("an end time"));
  if (!step || !end) return;
  p_.time.step = *step;
  p_.time.end = *end;
  const double n = *end / *step;
  // Negated so that inf (end/step overflowing a double) is refused too.
  if (!(std::round(n) <= static_cast<double>(kMaxSteps)))
    t->issue("step", fmt::format("found step = {} with end = {}, which is {:.10g} steps; expected "
                                 "at most {} steps (time.end / time.step)",
                                 *step, *end, n, kMaxSteps));
  else if (n < 1 - 1e-9)
    t->issue("end", fmt::format("found end = {} < step = {}, expected end ≥ step (at least one "
                                "step)",
                                *end, *step));
  else if (std::abs(n - std::round(n)) > 1e-9 * n)  // the contract: round(end/step) steps
    warn("time.end", fmt::format("found end/step = {:.10g}, not a whole number of steps: the run "
                                 "has round(end/step) = {:.0f} steps and ends at t = {:g} s",
                                 n, std::round(n), std::round(n) * *step));
}

void CaseReader::warn(const std::string& key, const std::string& message) {
  int line = 1;
  if (const auto node = root_.at_path(key); node && node.node()) {
    line = std::max(1, static_cast<int>(node.node()->source().begin.line));
  }
  p_.warnings.push_back(fmt::format("{}:{}: {}: {}", file_.string(), line, key, message));
}

void CaseReader::warn_unit_habits() {
  // Thresholds (case-format.md, "Warnings"): below each, no solid a user is likely to model
  // has the value in SI, and the habit named gives it. A warning only: the case runs.
  constexpr double kModulus = 1e6;      // Pa: soft rubber ~1e6; steel in MPa: 2.1e5
  constexpr double kDensity = 10;       // kg/m³: solid foams ≥ ~20; steel in g/cm³: 7.85
  constexpr double kSpecificHeat = 50;  // J/(kg·K): lead 128; steel in kJ/(kg·K): 0.45
  constexpr double kTemperature = 150;  // K: −123 °C; room temperature in °C: 20
  for (const auto& [name, m] : materials_) {
    if (!m) continue;
    const auto path = detail::join("materials", name);
    if (m->young_modulus < kModulus)
      warn(
          path + ".young_modulus",
          fmt::format("found {:g} Pa, below {:g} Pa, softer than rubber: did you give MPa? (steel: "
                      "2.1e11 Pa)",
                      m->young_modulus, kModulus));
    if (m->density < kDensity)
      warn(path + ".density", fmt::format("found {:g} kg/m³, below {:g} kg/m³: did you give g/cm³? "
                                          "(steel: 7850 kg/m³)",
                                          m->density, kDensity));
    if (m->specific_heat < kSpecificHeat)
      warn(path + ".specific_heat",
           fmt::format("found {:g} J/(kg·K), below {:g} J/(kg·K): did you give kJ/(kg·K)? (steel: "
                       "450 J/(kg·K))",
                       m->specific_heat, kSpecificHeat));
  }
  const auto cold = [&](const std::string& key, const std::vector<double>& values) {
    for (const double v : values)
      if (v < kTemperature) {
        warn(key, fmt::format("found {:g} K, below {:g} K: did you give °C? Temperatures are in "
                              "kelvin ({:g} °C = {:g} K)",
                              v, kTemperature, v, v + 273.15));
        return;
      }
  };
  cold("physics.reference_temperature", {p_.physics.reference_temperature});
  for (size_t i = 0; i < p_.bodies.size(); ++i)
    if (root_.at_path(detail::join(detail::at("bodies", i), "initial_temperature")))
      cold(detail::join(detail::at("bodies", i), "initial_temperature"),
           {p_.bodies[i].initial_temperature});
  for (size_t i = 0; i < p_.boundaries.size(); ++i) {
    const auto& bc = p_.boundaries[i];
    const auto at = detail::at("boundary", i);
    if (bc.temperature) cold(detail::join(at, "temperature"), bc.temperature->values());
    if (bc.film) cold(detail::join(at, "film.ambient"), bc.film->ambient.values());
    if (bc.radiation) cold(detail::join(at, "radiation.ambient"), bc.radiation->ambient.values());
  }
}

void CaseReader::read_physics(const TableReader& root) {
  const auto t = root.sub_table(
      "physics", Need::optional,
      {"reference_temperature", "thermal_expansion", "thermoelastic_heating", "heat_capacity"});
  if (!t) return;
  if (const auto s = t->choice("heat_capacity", Need::optional, {"consistent", "lumped"}))
    p_.physics.lumped_heat_capacity = *s == "lumped";
  if (const auto v = t->number("reference_temperature", Need::optional, kTemperature))
    p_.physics.reference_temperature = *v;
  if (const auto v = t->boolean("thermal_expansion")) p_.physics.thermal_expansion = *v;
  if (const auto v = t->boolean("thermoelastic_heating")) p_.physics.thermoelastic_heating = *v;
}

void CaseReader::read_materials(const TableReader& root) {
  const auto* n = root.get("materials", Need::required, "[materials.NAME] tables");
  if (!n) return;
  const auto* all = n->as_table();
  if (!all || all->empty()) {
    root.issue("materials", fmt::format("found {}, expected one or more [materials.NAME] tables",
                                        all ? "no material" : detail::describe(*n)));
    return;
  }
  for (const auto& [key, value] : *all) {
    const std::string name(key.str());
    const auto path = detail::join("materials", name);
    const auto* t = value.as_table();
    if (!t) {
      issues_.add(
          detail::line_of(value), path,
          fmt::format("found {}, expected a table of material constants", detail::describe(value)));
      continue;
    }
    const TableReader m(*t, path, issues_,
                        {"density", "young_modulus", "poisson_ratio", "thermal_expansion",
                         "specific_heat", "thermal_conductivity"});
    const auto rho = m.number("density", Need::required, positive("a density"));
    const auto e = m.number("young_modulus", Need::required, positive("a modulus"));
    const auto nu = m.number("poisson_ratio", Need::required,
                             {[](double x) { return x >= 0 && x < 0.5; }, "a number in [0, 0.5)"});
    const auto alpha = m.number("thermal_expansion", Need::required, non_negative("a number"));
    const auto cp = m.number("specific_heat", Need::required, positive("a number"));
    const auto kappa = m.number("thermal_conductivity", Need::required, positive("a number"));
    if (rho && e && nu && alpha && cp && kappa)
      materials_[name] = fem::Material{*rho, *e, *nu, *alpha, *cp, *kappa};
    else
      materials_[name] = std::nullopt;  // the name exists; its constants were reported
  }
}

const toml::array* CaseReader::tables(const TableReader& root, std::string_view key, Need need) {
  const auto* n = root.get(key, need, fmt::format("one or more [[{}]] tables", key));
  if (!n) return nullptr;
  const auto* a = n->as_array();
  if (!a || (need == Need::required && a->empty()) || !a->is_array_of_tables()) {
    root.issue(key, fmt::format("found {}, expected one or more [[{}]] tables",
                                detail::describe(*n), key));
    return nullptr;
  }
  return a;
}

void CaseReader::read_bodies(const TableReader& root) {
  const auto* a = tables(root, "bodies", Need::required);
  if (!a) return;
  std::set<std::string> names;
  for (size_t i = 0; i < a->size(); ++i) {
    read_body(*a->get(i)->as_table(), i);
    const auto& name = p_.bodies.back().name;
    if (!name.empty() && !names.insert(name).second)
      issues_.add(detail::line_of(*a->get(i)->as_table()->get("name")),
                  detail::join(detail::at("bodies", i), "name"),
                  fmt::format("found \"{}\" again, expected a unique body name", printable(name)));
  }
  resolve_auto_subdomains(root, *a);
}

int CaseReader::factor_ranks(const TableReader& root) const {
  // [solver] is read after the bodies, so its key is looked at here directly.
  std::string package;
  if (const auto* solver = root.table().get_as<toml::table>("solver"))
    package = (*solver)["factorization"].value_or(std::string());
  return core::ranks_sharing_a_factor(package == "auto" ? std::string() : package);
}

void CaseReader::resolve_auto_subdomains(const TableReader& root, const toml::array& bodies) {
  // One budget for all bodies: they are in memory together. Measured peaks and the rule:
  // docs/choices.md.
  std::vector<double> dofs(p_.bodies.size(), 0.0);
  for (size_t i = 0; i < p_.bodies.size(); ++i)
    if (p_.bodies[i].subdomains == 0 && mesh_built_[i])
      dofs[i] = static_cast<double>(p_.bodies[i].mesh.n_nodes()) * dim_;
  // Bodies with a number set take their share first (approximately: as if direct).
  const int ranks = factor_ranks(root);
  double fixed = 0;
  for (const auto& body : p_.bodies)
    if (body.subdomains == 1)
      fixed += direct_memory(dim_, body.mesh.n_nodes() * double(dim_), ranks);
  const double budget = kMemoryShare * memory_per_rank() - fixed;
  const auto chosen =
      auto_subdomains(dim_, dofs, memory_per_rank() > 0 ? std::max(budget, 1.0) : 0.0, ranks);
  for (size_t i = 0; i < p_.bodies.size(); ++i) {
    auto& body = p_.bodies[i];
    if (body.subdomains != 0) continue;
    body.subdomains = 1;
    if (!mesh_built_[i] || chosen[i] == 1) continue;
    body.subdomains = std::min(chosen[i], body.mesh.n_cells());
    try {
      (void)mesh::partition_cells(body.mesh, body.subdomains);
    } catch (const MeshError& e) {
      issues_.add(
          detail::line_of(*bodies.get(i)->as_table()),
          detail::join(detail::at("bodies", i), "subdomains"),
          fmt::format("\"auto\" chose {} subdomains (the direct factorisation would "
                      "need about {:.1f} GiB), which the body's mesh cannot be cut "
                      "into: {}; expected a number that it can",
                      body.subdomains, direct_memory(dim_, dofs[i], ranks) / kGiB, e.what()));
    }
  }
}

void CaseReader::read_body(const toml::table& t, size_t index) {
  const TableReader b(t, detail::at("bodies", index), issues_,
                      {"name", "material", "mesh", "initial_temperature", "initial_velocity",
                       "initial_state", "body_force", "heat_source", "subdomains"});
  physics::Body body;
  mesh_built_.push_back(false);
  if (const auto name = b.string("name", Need::required)) {
    check_name(b, "name", *name, "output file names and history.csv columns");
    body.name = *name;
  }
  if (const auto mat = b.string("material", Need::required)) {
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
  body.subdomains = 0;  // "auto", resolved by read_bodies once every body is known
  if (const auto* n = b.get("subdomains", Need::optional, "");
      n && !(n->is_string() && n->as_string()->get() == "auto")) {
    if (n->is_string())
      b.issue("subdomains", fmt::format("found \"{}\", expected \"auto\" or a whole number "
                                        "of subdomains",
                                        printable(n->as_string()->get())));
    else if (const auto s = b.integer("subdomains", Need::optional, 1)) {
      body.subdomains = *s;
      check_subdomains(b, body);
    }
  }
  p_.bodies.push_back(std::move(body));
}

void CaseReader::check_subdomains(const TableReader& b, const physics::Body& body) {
  if (!mesh_built_.back() || body.subdomains <= 1) return;
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

void CaseReader::read_body_loads(const TableReader& b, physics::Body& body) {
  body.initial_temperature = p_.physics.reference_temperature;
  if (const auto v = b.number("initial_temperature", Need::optional, kTemperature))
    body.initial_temperature = *v;
  if (const auto* n = b.get("initial_velocity", Need::optional, ""))
    if (const auto v = detail::read_vector(*n, b.key("initial_velocity"), issues_, dim_))
      body.initial_velocity = *v;
  if (const auto s = b.choice("initial_state", Need::optional, {"rest", "equilibrium"}))
    body.start_in_equilibrium = *s == "equilibrium";
  if (const auto* n = b.get("body_force", Need::optional, ""))
    if (const auto f = detail::read_components(*n, b.key("body_force"), issues_, dim_, false))
      for (int k = 0; k < 3; ++k)
        if ((*f)[k]) body.body_force[k] = *(*f)[k];
  if (const auto* n = b.get("heat_source", Need::optional, ""))
    if (const auto r = detail::read_time_table(*n, b.key("heat_source"), issues_))
      body.heat_source = *r;
}

void CaseReader::read_mesh(const TableReader& b, physics::Body& body) {
  const auto mesh = b.sub_table("mesh", Need::required, {"box", "file"});
  if (!mesh) return;
  if (mesh->has("box") == mesh->has("file")) {
    issues_.add(mesh->line(), mesh->path(),
                fmt::format("found {}, expected exactly one of box = {{ min, max, cells }} or "
                            "file = \"NAME.msh\"",
                            mesh->has("box") ? "both box and file" : "neither box nor file"));
    return;
  }
  if (mesh->has("file")) return read_mesh_file(*mesh, body);
  if (const auto box = mesh->sub_table("box", Need::required, {"min", "max", "cells"}))
    read_box(*box, body);
}

void CaseReader::read_box(const TableReader& box, physics::Body& body) {
  const auto* lo_node = box.get("min", Need::required, "an array of numbers");
  const auto* hi_node = box.get("max", Need::required, "an array of numbers");
  const auto* cells_node = box.get("cells", Need::required, "an array of integers ≥ 1");
  const auto lo =
      lo_node ? detail::read_vector(*lo_node, box.key("min"), issues_, dim_) : std::nullopt;
  const auto hi =
      hi_node ? detail::read_vector(*hi_node, box.key("max"), issues_, dim_) : std::nullopt;
  const auto cells =
      cells_node ? detail::read_counts(*cells_node, box.key("cells"), issues_, dim_) : std::nullopt;
  if (!lo || !hi || !cells || dim_ == 0) return;
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
    body.mesh = mesh::make_box(dim_, *lo, *hi, *cells);
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

std::optional<int> CaseReader::body_index(const TableReader& t, std::string_view k) {
  const auto name = t.string(k, Need::required);
  if (!name) return std::nullopt;
  std::vector<std::string> known;
  for (size_t i = 0; i < p_.bodies.size(); ++i) {
    if (p_.bodies[i].name == *name) return static_cast<int>(i);
    known.push_back(p_.bodies[i].name);
  }
  t.issue(k,
          fmt::format("found \"{}\", expected the name of a body: {}", *name, quoted_list(known)));
  return std::nullopt;
}

void CaseReader::check_boundary_name(const TableReader& t, std::string_view k, int b,
                                     const std::string& where) {
  const auto& body = p_.bodies[b];
  if (!mesh_built_[b] || body.mesh.has_boundary(where)) return;
  t.issue(k, fmt::format("found \"{}\", expected a boundary of body \"{}\": {}", where, body.name,
                         quoted_list(body.mesh.boundary_names())));
}

void CaseReader::read_boundaries(const TableReader& root) {
  const auto* a = tables(root, "boundary", Need::optional);
  if (!a) return;
  for (size_t i = 0; i < a->size(); ++i) read_boundary(*a->get(i)->as_table(), i);
}

void CaseReader::read_boundary(const toml::table& t, size_t index) {
  const TableReader b(t, detail::at("boundary", index), issues_,
                      {"body", "where", "displacement", "traction", "force", "temperature",
                       "heat_flux", "film", "radiation"});
  physics::BoundaryCondition bc;
  const auto body = body_index(b, "body");
  if (const auto where = b.string("where", Need::required)) {
    bc.where = *where;
    if (body) check_boundary_name(b, "where", *body, *where);
    if (b.has("displacement"))
      check_name(b, "where", *where, "the history.csv columns reaction_<body>_<where>_x|y|z");
    else if (b.has("force"))
      check_name(b, "where", *where, "the history.csv columns force_<body>_<where>_x|y|z");
  }
  bc.body = body.value_or(0);
  if (const auto* n = b.get("displacement", Need::optional, ""))
    if (const auto d = detail::read_components(*n, b.key("displacement"), issues_, dim_, true))
      bc.displacement = *d;
  // "free" is accepted in a traction too (no traction on that component), so one entry can
  // mix displaced and loaded components: displacement = [0.0, "free"], traction = ["free", p].
  if (const auto* n = b.get("traction", Need::optional, ""))
    if (const auto p = detail::read_components(*n, b.key("traction"), issues_, dim_, true))
      bc.traction = *p;
  for (int k = 0; k < 3; ++k)
    if (bc.displacement[k] && bc.traction[k])
      issues_.add(b.line("traction"), detail::at(b.key("traction"), k),
                  fmt::format("found both a displacement and a traction on component {}, "
                              "expected one of them (\"free\" displacement with a traction)",
                              k));
  // A resultant force per component through a rigid coupling (load control): "free" leaves a
  // component uncoupled, so force = ["free", "free", -200.0] presses along z only.
  if (const auto* n = b.get("force", Need::optional, ""))
    if (const auto f = detail::read_components(*n, b.key("force"), issues_, dim_, true))
      bc.force = *f;
  for (int k = 0; k < 3; ++k)
    if (bc.force[k] && (bc.displacement[k] || bc.traction[k]))
      issues_.add(b.line("force"), detail::at(b.key("force"), k),
                  fmt::format("found both a force and a {} on component {}, expected one of "
                              "them (\"free\" in the other)",
                              bc.displacement[k] ? "displacement" : "traction", k));
  if (const auto* n = b.get("temperature", Need::optional, ""))
    bc.temperature = detail::read_time_table(*n, b.key("temperature"), issues_, kTemperature);
  if (const auto* n = b.get("heat_flux", Need::optional, ""))
    bc.heat_flux = detail::read_time_table(*n, b.key("heat_flux"), issues_);
  if (b.has("temperature") && b.has("heat_flux"))
    b.issue("heat_flux",
            "found both temperature and heat_flux, expected one of them per "
            "[[boundary]] (add another [[boundary]] for the other)");
  read_boundary_heat(b, bc);
  if (body) check_boundary_heat_scale(b, bc);
  for (const auto* k : {"film", "radiation"})
    if (b.has("temperature") && b.has(k))
      b.issue(k, fmt::format("found both temperature and {} on one face, expected one of them: "
                             "a prescribed temperature leaves nothing for the {} to change",
                             k, k));
  if (!b.has("displacement") && !b.has("traction") && !b.has("force") && !b.has("temperature") &&
      !b.has("heat_flux") && !b.has("film") && !b.has("radiation"))
    issues_.add(b.line(), b.path(),
                "prescribes nothing; expected at least one of displacement, traction, force, "
                "temperature, heat_flux, film, radiation");
  p_.boundaries.push_back(std::move(bc));
}

namespace {

/// Member k of a film or radiation table: a number or a time table within `range`.
std::optional<core::TimeTable> table_member(const TableReader& t, std::string_view k,
                                            const Range& range) {
  const auto* n = t.get(k, Need::required, range.expected + " (a number or a time table)");
  return n ? detail::read_time_table(*n, t.key(k), t.issues(), range) : std::nullopt;
}

}  // namespace

void CaseReader::read_boundary_heat(const TableReader& b, physics::BoundaryCondition& bc) {
  if (const auto f = b.sub_table("film", Need::optional, {"coefficient", "ambient"})) {
    const auto h = table_member(*f, "coefficient", positive("a film coefficient h [W/(m²K)]"));
    const auto ambient = table_member(*f, "ambient", kTemperature);
    if (h && ambient) bc.film = physics::Film{*h, *ambient};
  }
  if (const auto r = b.sub_table("radiation", Need::optional, {"emissivity", "ambient"})) {
    const auto e = table_member(
        *r, "emissivity", {[](double x) { return x > 0 && x <= 1; }, "an emissivity in (0, 1]"});
    const auto ambient = table_member(*r, "ambient", kTemperature);
    if (e && ambient) bc.radiation = physics::Radiation{*e, *ambient};
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

void CaseReader::check_boundary_heat_scale(const TableReader& b,
                                           const physics::BoundaryCondition& bc) {
  if (!bc.film && !bc.radiation) return;
  const auto& body = p_.bodies[static_cast<size_t>(bc.body)];
  const double kappa = body.material.thermal_conductivity;
  if (!mesh_built_[static_cast<size_t>(bc.body)] || !(kappa > 0)) return;
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
    const double theta = std::max({largest(bc.radiation->ambient), body.initial_temperature,
                                   p_.physics.reference_temperature});
    const double h = 4 * largest(bc.radiation->emissivity) * sigma * theta * theta * theta;
    refuse("radiation", h,
           fmt::format("a radiation to an ambient of {:.3g} K (its conductance 4εσθ³ = {:.3g} "
                       "W/(m²K) at {:.3g} K)",
                       largest(bc.radiation->ambient), h, theta));
  }
}

void CaseReader::read_contacts(const TableReader& root) {
  const auto* n = root.get("contact", Need::optional, "");
  if (!n) return;
  std::vector<TableReader> pairs;
  if (const auto* t = n->as_table()) {
    pairs.push_back(read_contact(*t, "contact"));
  } else if (const auto* a = n->as_array(); a && a->is_array_of_tables()) {
    for (size_t i = 0; i < a->size(); ++i)
      pairs.push_back(read_contact(*a->get(i)->as_table(), detail::at("contact", i)));
  } else {
    root.issue("contact", fmt::format("found {}, expected a [contact] table (one pair) or one or "
                                      "more [[contact]] tables",
                                      detail::describe(*n)));
    return;
  }
  check_contact_pairs(pairs);
}

TableReader CaseReader::read_contact(const toml::table& table, std::string path) {
  const TableReader t(table, std::move(path), issues_,
                      {"name", "slave", "master", "friction", "conductance", "heat_conduction",
                       "frictional_heating"});
  physics::ContactSettings c;
  if (const auto name = t.string("name", Need::optional)) {
    check_pair_name(t, *name);
    c.name = *name;
  }
  auto side = [&](std::string_view key, int& body, std::string& where) -> bool {
    const auto s = t.sub_table(key, Need::required, {"body", "where"});
    if (!s) return false;
    const auto b = body_index(*s, "body");
    const auto w = s->string("where", Need::required);
    if (b && w) check_boundary_name(*s, "where", *b, *w);
    body = b.value_or(-1);
    where = w.value_or("");
    return b && w;
  };
  const bool slave_ok = side("slave", c.slave_body, c.slave_where);
  const bool master_ok = side("master", c.master_body, c.master_where);
  if (slave_ok && master_ok && c.slave_body == c.master_body)
    issues_.add(t.line("master"), detail::join(t.key("master"), "body"),
                fmt::format("found the slave's body \"{}\", expected a different body",
                            p_.bodies[c.master_body].name));
  if (const auto* n = t.get("friction", Need::optional, ""))
    if (const auto f = detail::read_temperature_table(*n, t.key("friction"), issues_,
                                                      non_negative("a coefficient")))
      c.friction = *f;
  if (const auto v = t.boolean("heat_conduction")) c.heat_conduction = *v;
  if (const auto v = t.boolean("frictional_heating")) c.frictional_heating = *v;
  read_conductance(t, c);
  p_.contacts.push_back(std::move(c));
  return t;
}

void CaseReader::check_contact_pairs(const std::vector<TableReader>& pairs) {
  auto& cs = p_.contacts;
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
                            c.slave_where, p_.bodies[c.slave_body].name, *other));
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
                            c.slave_where, p_.bodies[c.slave_body].name, c.master_where,
                            p_.bodies[c.master_body].name, *other));
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

/// A temperature at which both conductances vanish, if any. Both are ≥ 0, linear between the
/// union of their table points and constant beyond: their sum vanishes somewhere iff it does
/// at one of those points (or anywhere, when both are constants).
std::optional<double> both_conductances_zero(const core::TemperatureTable& gs,
                                             const core::TemperatureTable& gm) {
  std::vector<double> at(gs.temperatures());
  at.insert(at.end(), gm.temperatures().begin(), gm.temperatures().end());
  if (at.empty()) at.push_back(0.0);
  std::sort(at.begin(), at.end());
  for (const double t : at)
    if (gs(t) + gm(t) == 0) return t;
  return std::nullopt;
}

}  // namespace

void CaseReader::read_conductance(const TableReader& contact, physics::ContactSettings& c) {
  if (const auto g = contact.sub_table("conductance", Need::optional, {"slave", "master"})) {
    const auto law = [&](std::string_view k) -> std::optional<core::TemperatureTable> {
      const auto* n = g->get(k, Need::required, "a conductance ≥ 0 (a number or a table in θ)");
      return n ? detail::read_temperature_table(*n, g->key(k), issues_,
                                                non_negative("a conductance"))
               : std::nullopt;
    };
    const auto gs = law("slave");
    const auto gm = law("master");
    if (!gs || !gm) return;
    c.conductance_slave = *gs;
    c.conductance_master = *gm;
  } else if (contact.has("conductance")) {
    return;  // not a table: reported
  }
  const bool needed = c.heat_conduction || (c.frictional_heating && c.friction.max_value() > 0);
  const auto zero = both_conductances_zero(c.conductance_slave, c.conductance_master);
  if (!needed || !zero) return;
  const bool constant = c.conductance_slave.is_constant() && c.conductance_master.is_constant();
  contact.issue("conductance",
                fmt::format("found {}, expected {{ slave = γ_C^s, master = γ_C^m }} with at "
                            "least one > 0{}: with both zero β_C and δ_C of (2.13) are "
                            "undefined (or set heat_conduction = false{})",
                            !contact.has("conductance") ? "none"
                            : constant                  ? "both conductances 0"
                                       : fmt::format("both conductances 0 at θ = {} K", *zero),
                            constant ? "" : " at every temperature",
                            c.friction.max_value() > 0 ? " and frictional_heating = false" : ""));
}

void CaseReader::read_solver(const TableReader& root) {
  const auto s =
      root.sub_table("solver", Need::optional, {"coupling_tolerance",    "max_coupling_iterations",
                                                "coupling_order",        "friction_loop",
                                                "qp_tolerance",          "max_qp_iterations",
                                                "factorization",         "feti_tolerance",
                                                "max_feti_iterations",   "feti_preconditioner",
                                                "contact_dual",          "newton_tolerance",
                                                "max_newton_iterations", "coupling_acceleration",
                                                "conductance_treatment", "qp_forcing",
                                                "qp_forcing_cap",        "loop_forcing",
                                                "max_friction_updates",  "explicit_dual_limit",
                                                "max_cutbacks"});
  if (!s) return;
  const Range unit{[](double x) { return x > 0 && x < 1; }, "a number in (0, 1)"};
  auto& settings = p_.solver;
  if (const auto v = s->number("coupling_tolerance", Need::optional, unit))
    settings.coupling_tolerance = *v;
  if (const auto v = s->integer("max_coupling_iterations", Need::optional, 1))
    settings.max_coupling_iterations = *v;
  if (const auto v = s->choice("friction_loop", Need::optional, {"nested", "staggered"}))
    settings.friction_loop =
        *v == "nested" ? physics::FrictionLoop::nested : physics::FrictionLoop::staggered;
  if (const auto v =
          s->choice("coupling_order", Need::optional, {"auto", "heat_first", "mechanics_first"}))
    settings.coupling_order = *v == "heat_first"        ? physics::CouplingOrder::heat_first
                              : *v == "mechanics_first" ? physics::CouplingOrder::mechanics_first
                                                        : physics::CouplingOrder::automatic;
  if (const auto v = s->number("qp_tolerance", Need::optional, unit)) settings.qp_tolerance = *v;
  if (const auto v = s->boolean("coupling_acceleration")) settings.friction.acceleration = *v;
  if (const auto v = s->choice("conductance_treatment", Need::optional, {"implicit", "lagged"}))
    settings.conductance_treatment = *v == "implicit" ? physics::ConductanceTreatment::implicit
                                                      : physics::ConductanceTreatment::lagged;
  if (const auto v = s->number("qp_forcing", Need::optional, unit))
    settings.friction.qp_forcing = *v;
  if (const auto v = s->number("qp_forcing_cap", Need::optional, unit)) {
    settings.friction.qp_forcing_cap = *v;
    // The forced QP tolerance is clamped to [qp_tolerance, qp_forcing_cap].
    if (*v < settings.qp_tolerance)
      s->issue("qp_forcing_cap", fmt::format("found {:g}, below qp_tolerance = {:g}; expected a "
                                             "number in [qp_tolerance, 1)",
                                             *v, settings.qp_tolerance));
  }
  if (const auto v = s->number("loop_forcing", Need::optional, unit))
    settings.friction.loop_forcing = *v;
  if (const auto v = s->integer("max_friction_updates", Need::optional, 1))
    settings.friction.max_updates = *v;
  if (const auto v = s->integer("max_qp_iterations", Need::optional, 1))
    settings.max_qp_iterations = *v;
  if (const auto v = s->integer("explicit_dual_limit", Need::optional, 0))
    settings.explicit_dual_limit = *v;
  if (const auto v = s->integer("max_cutbacks", Need::optional, 0)) {
    // τ/2^20 ≈ 1e-6 τ: deeper is no longer a cut-back but a different time scale
    if (*v > 20)
      s->issue("max_cutbacks", fmt::format("found {}, expected 0 to 20 halvings of the step", *v));
    else
      settings.max_cutbacks = *v;
  }
  if (const auto v =
          s->choice("factorization", Need::optional, {"auto", "mumps", "cholmod", "petsc"}))
    settings.factorization = *v == "auto" ? "" : *v;
  if (const auto v = s->number("feti_tolerance", Need::optional, unit))
    settings.feti_tolerance = *v;
  if (const auto v = s->integer("max_feti_iterations", Need::optional, 1))
    settings.max_feti_iterations = *v;
  if (const auto v = s->number("newton_tolerance", Need::optional, unit))
    settings.newton_tolerance = *v;
  if (const auto v = s->integer("max_newton_iterations", Need::optional, 1))
    settings.max_newton_iterations = *v;
  if (const auto v =
          s->choice("feti_preconditioner", Need::optional, {"dirichlet", "lumped", "none"}))
    settings.feti_preconditioner = *v == "dirichlet" ? feti::Preconditioner::dirichlet
                                   : *v == "lumped"  ? feti::Preconditioner::lumped
                                                     : feti::Preconditioner::none;
  if (const auto v = s->choice("contact_dual", Need::optional, {"auto", "nested", "combined"})) {
    settings.contact_dual = *v == "auto"     ? physics::ContactDual::automatic
                            : *v == "nested" ? physics::ContactDual::nested
                                             : physics::ContactDual::combined;
    // A cross-key check: read after [time], [[bodies]] and the contact pairs.
    if (settings.contact_dual == physics::ContactDual::combined && issues_.empty())
      if (const auto why = physics::combined_contact_dual_unavailable(p_); !why.empty())
        s->issue("contact_dual",
                 fmt::format("found \"combined\" but {}; expected \"combined\" only with "
                             "one [contact] pair, scheme = \"quasistatic\" and both contact bodies "
                             "decomposed (subdomains > 1), or \"auto\"/\"nested\"",
                             why));
  }
}

void CaseReader::read_output(const TableReader& root) {
  p_.output.directory = resolve("out");
  const auto o = root.sub_table("output", Need::optional,
                                {"directory", "every", "checkpoint_every", "checkpoint_seconds"});
  if (!o) return;
  if (const auto d = o->string("directory", Need::optional)) {
    if (d->empty())
      o->issue("directory", "found \"\", expected a folder name");
    else
      p_.output.directory = resolve(*d);
  }
  if (const auto e = o->integer("every", Need::optional, 1)) p_.output.every = *e;
  if (const auto e = o->integer("checkpoint_every", Need::optional, 0))
    p_.output.checkpoint_every = *e;
  if (const auto t =
          o->number("checkpoint_seconds", Need::optional, non_negative("checkpoint_seconds (s)")))
    p_.output.checkpoint_seconds = *t;
}

namespace {

bool same_table(const core::TimeTable& a, const core::TimeTable& b) {
  return a.times() == b.times() && a.values() == b.values();
}

bool any_of(const std::array<std::optional<core::TimeTable>, 3>& c) {
  return c[0] || c[1] || c[2];
}

}  // namespace

/// Two [[boundary]] tables of one body that prescribe a node's displacement component or
/// temperature differently (the later silently won), a traction on a face whose component
/// another table fixes (it did nothing), or two tables with displacements on one face (their
/// history columns reaction_<body>_<where>_… had one name). Equal values where faces share
/// nodes (a corner held by both of its faces) stay allowed.
void CaseReader::check_boundary_conflicts() {
  const auto* node = root_.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  const auto& bcs = p_.boundaries;
  const char* axes = "xyz";
  for (size_t j = 0; j < bcs.size(); ++j)
    // Each table against the earlier ones up to its first conflict: 300 equal tables on one
    // face printed 44 851 errors, every pair of them (issue 42 D22); now one per table.
    for (size_t i = 0, before = issues_.size(); i < j && issues_.size() == before; ++i) {
      const auto& first = bcs[i];
      const auto& later = bcs[j];
      if (first.body != later.body) continue;
      const int line = detail::line_of(*a->get(j));
      const auto here = detail::at("boundary", j);
      const auto other = fmt::format("boundary[{}] (line {})", i, detail::line_of(*a->get(i)));
      const auto& body = p_.bodies[static_cast<size_t>(later.body)];
      const bool first_cools = first.film || first.radiation;
      const bool later_cools = later.film || later.radiation;
      if (first.where == later.where &&
          ((first.temperature && later_cools) || (first_cools && later.temperature)))
        issues_.add(line,
                    detail::join(here, later.temperature ? "temperature"
                                       : later.film      ? "film"
                                                         : "radiation"),
                    fmt::format("found a film or radiation and a prescribed temperature on \"{}\" "
                                "of body \"{}\" (with {}); expected one of them: a prescribed "
                                "temperature leaves nothing for the film or radiation to change",
                                later.where, body.name, other));
      if (first.where == later.where &&
          ((first.temperature && later.heat_flux) || (first.heat_flux && later.temperature)))
        issues_.add(line, detail::join(here, later.temperature ? "temperature" : "heat_flux"),
                    fmt::format("found a heat flux and a prescribed temperature on \"{}\" of "
                                "body \"{}\" (with {}); expected one of them: a prescribed "
                                "temperature leaves nothing for the heat flux to change",
                                later.where, body.name, other));
      if (first.where == later.where && any_of(first.displacement) && any_of(later.displacement))
        issues_.add(line, detail::join(here, "displacement"),
                    fmt::format("found displacements on \"{}\" of body \"{}\", which {} "
                                "prescribes too; expected one [[boundary]] with displacements "
                                "per face (merge them: their reaction columns share a name)",
                                later.where, body.name, other));
      for (int k = 0; k < dim_; ++k)
        if (first.where == later.where && ((first.displacement[k] && later.traction[k]) ||
                                           (first.traction[k] && later.displacement[k])))
          issues_.add(line, detail::join(here, later.traction[k] ? "traction" : "displacement"),
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
      for (int k = 0; k < dim_; ++k)
        if (first.displacement[k] && later.displacement[k] &&
            !same_table(*first.displacement[k], *later.displacement[k]))
          issues_.add(line, detail::at(detail::join(here, "displacement"), k),
                      fmt::format("found another value for component {} of the displacement of "
                                  "{} node(s) that {} prescribes too ({}); expected the same value "
                                  "from both",
                                  axes[k], shared.size(), other, where));
      if (first.temperature && later.temperature &&
          !same_table(*first.temperature, *later.temperature))
        issues_.add(line, detail::join(here, "temperature"),
                    fmt::format("found another temperature for {} node(s) that {} prescribes "
                                "too ({}); expected the same value from both",
                                shared.size(), other, where));
    }
}

/// Faces under load control (force): their nodes carry one displacement per loaded component,
/// so no node of one may be prescribed, loaded by another face in that component, or touched by
/// a contact row; the body must be solved directly (not FETI), start at rest, and the contact
/// bodies may have one loaded component in all (a scalar root per QP: rigid_coupling.hpp).
void CaseReader::check_load_control() {
  const auto* node = root_.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  const auto& bcs = p_.boundaries;
  const char* axes = "xyz";
  int in_contact = 0;
  for (size_t j = 0; j < bcs.size(); ++j) {
    const auto& bc = bcs[j];
    if (!any_of(bc.force)) continue;
    const int line = detail::line_of(*a->get(j));
    const auto key = detail::join(detail::at("boundary", j), "force");
    const auto& body = p_.bodies[static_cast<size_t>(bc.body)];
    if (body.subdomains > 1)
      issues_.add(line, key,
                  fmt::format("found a force on body \"{}\", which is cut into {} subdomains; "
                              "expected subdomains = 1 (load control is not implemented with "
                              "FETI bodies)",
                              body.name, body.subdomains));
    if (body.start_in_equilibrium && p_.time.scheme == physics::Scheme::dynamic)
      issues_.add(line, key,
                  fmt::format("found a force on body \"{}\" with initial_state = "
                              "\"equilibrium\"; expected initial_state = \"rest\" (the static "
                              "start does not solve for a loaded face)",
                              body.name));
    const auto nodes = body.mesh.boundary_nodes(bc.where);
    for (const auto& c : p_.contacts)
      for (const auto& [b, where] :
           {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
        if (b != bc.body) continue;
        ++in_contact;
        const auto surface = body.mesh.boundary_nodes(*where);
        std::vector<int> shared;
        std::set_intersection(nodes.begin(), nodes.end(), surface.begin(), surface.end(),
                              std::back_inserter(shared));
        if (!shared.empty())
          issues_.add(line, key,
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
      for (int k = 0; k < dim_; ++k)
        if (bc.force[k] && (other.displacement[k] || (other.force[k] && i < j)))
          issues_.add(line, detail::at(key, k),
                      fmt::format("found {} node(s) of \"{}\" whose component {} boundary[{}] "
                                  "(line {}) {} too; expected the nodes of a loaded face free "
                                  "of other displacements and forces in that component",
                                  shared.size(), bc.where, axes[k], i, detail::line_of(*a->get(i)),
                                  other.displacement[k] ? "prescribes" : "loads"));
    }
  }
  if (in_contact > 0) {
    int loaded = 0;
    for (const auto& bc : bcs) {
      bool contact_body = false;
      for (const auto& c : p_.contacts)
        contact_body = contact_body || c.slave_body == bc.body || c.master_body == bc.body;
      if (contact_body)
        for (int k = 0; k < dim_; ++k) loaded += bc.force[k] ? 1 : 0;
    }
    if (loaded > 1)
      issues_.add(detail::line_of(*a->get(0)), "boundary",
                  fmt::format("found {} loaded force components on the bodies in contact; "
                              "expected at most one (load control in contact solves for one "
                              "face displacement)",
                              loaded));
  }
}

void CaseReader::check_reaction_columns() {
  const auto* node = root_.get("boundary");
  const auto* a = node ? node->as_array() : nullptr;
  if (!a) return;
  std::map<std::string, size_t> owner;  // reaction_<body>_<where> → its [[boundary]]
  const auto& bcs = p_.boundaries;
  for (size_t j = 0; j < bcs.size(); ++j) {
    if (!any_of(bcs[j].displacement)) continue;
    const auto& body = p_.bodies[static_cast<size_t>(bcs[j].body)];
    const auto label = fmt::format("reaction_{}_{}", body.name, bcs[j].where);
    const auto [it, fresh] = owner.emplace(label, j);
    // The same face of the same body in two tables is one support (BodySystem::add_boundary).
    if (fresh || (bcs[it->second].body == bcs[j].body && bcs[it->second].where == bcs[j].where))
      continue;
    const auto& first = bcs[it->second];
    issues_.add(detail::line_of(*a->get(j)), detail::join(detail::at("boundary", j), "where"),
                fmt::format("found \"{}\" of body \"{}\", whose history.csv columns {}_x|y|z "
                            "are also those of boundary[{}] (line {}: \"{}\" of body \"{}\"); "
                            "expected body and boundary names whose reaction columns differ",
                            bcs[j].where, body.name, label, it->second,
                            detail::line_of(*a->get(it->second)), first.where,
                            p_.bodies[static_cast<size_t>(first.body)].name));
  }
}

void CaseReader::check_massless_cells() {
  if (p_.time.scheme != physics::Scheme::dynamic ||
      p_.time.contact_scheme != physics::ContactScheme::modified_mass)
    return;
  // The scheme's nodes: every contact surface of the body, of any pair (BodySystem). A cell
  // with all of them has no massive node to carry its mass (fem::singular_mass_u): the run
  // stopped with exit 1 where this is an input to change (issue 42 D9).
  const auto& bodies = *root_.get("bodies")->as_array();
  for (size_t b = 0; b < p_.bodies.size(); ++b) {
    std::vector<char> massless;
    std::vector<std::string> surfaces;
    for (const auto& c : p_.contacts)
      for (const auto& [body, where] :
           {std::pair{c.slave_body, &c.slave_where}, {c.master_body, &c.master_where}}) {
        if (body != static_cast<int>(b)) continue;
        const auto& m = p_.bodies[b].mesh;
        massless.resize(static_cast<size_t>(m.n_nodes()), 0);
        for (const int n : m.boundary_nodes(*where)) massless[static_cast<size_t>(n)] = 1;
        surfaces.push_back("\"" + *where + "\"");
      }
    if (massless.empty()) continue;
    const auto& m = p_.bodies[b].mesh;
    for (int c = 0; c < m.n_cells(); ++c) {
      const auto nodes = m.cell(c);
      if (!std::all_of(nodes.begin(), nodes.end(),
                       [&](int n) { return massless[static_cast<size_t>(n)] != 0; }))
        continue;
      issues_.add(detail::line_of(*bodies.get(b)), detail::at("bodies", b),
                  fmt::format("found body \"{}\" with cell {} (0-based) that has every node on "
                              "its contact surface(s) {}: the modified mass scheme "
                              "(contact_scheme = \"modified_mass\") takes the mass off those "
                              "nodes and leaves that cell none; expected at least two cells "
                              "through the body's thickness under a contact surface (refine the "
                              "mesh across it), or contact_scheme = \"stabilised\"",
                              p_.bodies[b].name, c, fmt::join(surfaces, ", ")));
      break;
    }
  }
}

/// A quasistatic body, and one that starts in static equilibrium, must be held against every
/// rigid motion: K_u is singular otherwise.
void CaseReader::check_quasistatic_bodies_held() {
  const bool quasistatic = p_.time.scheme == physics::Scheme::quasistatic;
  const auto& bodies = *root_.get("bodies")->as_array();
  for (size_t b = 0; b < p_.bodies.size(); ++b) {
    if (!quasistatic && !p_.bodies[b].start_in_equilibrium) continue;
    if (const int n = physics::free_rigid_modes(p_, static_cast<int>(b)); n > 0)
      issues_.add(detail::line_of(*bodies.get(b)), detail::at("bodies", b),
                  quasistatic
                      ? fmt::format("found body \"{}\" with {} rigid-body motion(s) left free by "
                                    "its displacement boundaries, expected a quasistatic body "
                                    "held by [[boundary]] displacements (or scheme = \"dynamic\")",
                                    p_.bodies[b].name, n)
                      : fmt::format("found body \"{}\" with initial_state = \"equilibrium\" and "
                                    "{} rigid-body motion(s) left free by its displacement "
                                    "boundaries, expected a body held by [[boundary]] "
                                    "displacements (or initial_state = \"rest\")",
                                    p_.bodies[b].name, n));
  }
}

}  // namespace

std::optional<std::pair<int, std::string>> stray_non_ascii(std::string_view text) {
  // TOML allows non-ASCII only inside strings and comments. toml++ 3.3.0 reaches an
  // unreachable branch (undefined behaviour) on U+00A1–U+0499 and U+2FDE–U+33D7 outside them
  // (is_non_ascii_horizontal_whitespace; found by tests/fuzz/fuzz_case_reader), so such text
  // is refused here, before toml++ sees it.
  int line = 1;
  size_t i = 0;
  const size_t n = text.size();
  auto skip_to = [&](std::string_view close, bool escapes, bool single_line) {
    while (i < n) {
      if (escapes && text[i] == '\\' && i + 1 < n) {
        if (text[i + 1] == '\n') ++line;
        i += 2;
        continue;
      }
      if (text.compare(i, close.size(), close) == 0) {
        i += close.size();
        return;
      }
      if (text[i] == '\n') {
        if (single_line) return;  // an unterminated string: toml++ reports it
        ++line;
      }
      ++i;
    }
  };
  while (i < n) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '#') {
      while (i < n && text[i] != '\n') ++i;
    } else if (text.compare(i, 3, "\"\"\"") == 0) {
      i += 3;
      skip_to("\"\"\"", true, false);
    } else if (text.compare(i, 3, "\'\'\'") == 0) {
      i += 3;
      skip_to("\'\'\'", false, false);
    } else if (c == '"') {
      ++i;
      skip_to("\"", true, true);
    } else if (c == '\'') {
      ++i;
      skip_to("\'", false, true);
    } else if (static_cast<unsigned char>(c) >= 0x80) {
      std::string bytes;  // the UTF-8 sequence as written
      for (size_t k = i; k < n && k < i + 4 && static_cast<unsigned char>(text[k]) >= 0x80; ++k)
        bytes += fmt::format("\\x{:02X}", static_cast<unsigned char>(text[k]));
      return std::pair{line, bytes};
    } else {
      ++i;
    }
  }
  return std::nullopt;
}

physics::Problem read_case(const std::filesystem::path& file,
                           std::span<const std::string> overrides) {
  if (const auto why = not_a_file(file); !why.empty())
    throw InputError({{file.string(), 1, "(file)", "cannot read the case file: it " + why}});
  std::string text;
  {
    std::ifstream in(file, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    text = s.str();
  }
  if (const auto stray = stray_non_ascii(text))
    throw InputError({{file.string(), stray->first, "(syntax)",
                       fmt::format("found the non-ASCII bytes {} outside a string or comment, "
                                   "expected ASCII keys, values and punctuation (other "
                                   "characters belong in \"strings\" or # comments)",
                                   stray->second)}});
  toml::table root;
  try {
    root = toml::parse(text, file.string());
  } catch (const toml::parse_error& e) {
    throw InputError({{file.string(), static_cast<int>(e.source().begin.line), "(syntax)",
                       fmt::format("not valid TOML: {}", e.description())}});
  }
  const auto applied = detail::apply_overrides(root, overrides);
  try {
    auto problem = CaseReader(file, root).read();
    problem.overrides.assign(overrides.begin(), overrides.end());
    problem.content = detail::case_content(root, applied);
    // A warning about an overridden value names its --set, not a line of the file.
    const auto prefix = file.string() + ":";
    for (auto& w : problem.warnings) {
      if (w.rfind(prefix, 0) != 0) continue;
      const auto key_at = w.find(": ", prefix.size());
      const auto key_end = w.find(": ", key_at + 2);
      if (key_at == std::string::npos || key_end == std::string::npos) continue;
      std::vector<InputIssue> one{{"", 0, w.substr(key_at + 2, key_end - key_at - 2), ""}};
      detail::attribute_issues(one, applied);
      if (one[0].line < 0) w = one[0].file + w.substr(key_at);
    }
    return problem;
  } catch (const InputError& e) {
    if (applied.empty()) throw;
    auto issues = e.issues();
    detail::attribute_issues(issues, applied);
    throw InputError(std::move(issues));
  }
}

}  // namespace tc::io
