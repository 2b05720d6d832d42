#pragma once
// Private to the io layer: the reader of one case file, section by section (case_reader.cpp:
// the root, [time], [physics], [materials], [solver], [output]; case_bodies.cpp: [[bodies]]
// and their meshes; case_boundaries.cpp: [[boundary]] and [contact]). The keys of every table
// are declared in case_schema.cpp; the checks that span sections are in case_checks.cpp and
// the memory policy (subdomains = "auto", box sizes) in auto_subdomains.cpp.
#include <toml++/toml.h>

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "tc/io/schema/table_reader.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/model/problem.hpp"

namespace tc::io::detail {

/// Reads one case file section by section into a Problem, collecting every issue; throws them
/// all at the end. Meshes are built on the way so boundary names can be checked.
class CaseReader {
 public:
  CaseReader(std::filesystem::path file, const toml::table& root)
      : file_(std::move(file)), issues_(file_.string()), root_(root) {}

  physics::Problem read();
  /// The field files `[output] format` chose (after read()): not in physics::Problem, whose
  /// encoding is the .vtu's (docs/choices.md, "VTKHDF: …").
  [[nodiscard]] FieldFiles field_files() const { return field_files_; }

 private:
  void read_dimension(const TableReader& root);
  void read_time(const TableReader& root);
  void read_physics(const TableReader& root);
  void read_materials(const TableReader& root);
  // A material's κ, c_p, α, E or ν: a number or a table in θ; its ρ: a number (ρ₀).
  std::optional<core::TemperatureTable> material_law(const TableReader& m, std::string_view k);
  std::optional<double> reference_density(const TableReader& m, std::string_view k);
  void read_bodies(const TableReader& root);
  void read_body(const toml::table& t, size_t index);
  void read_body_loads(const TableReader& b, physics::Body& body);
  /// `subdomains = "auto"` (or absent) → 1, or FETI subdomains where the direct path would not
  /// fit or would be slower (choose_subdomains); read after the contact pairs, whose
  /// multipliers the estimate counts.
  void resolve_auto_subdomains(const TableReader& root);
  /// The ranks a direct body's factor is spread over (1: each rank factorises it).
  [[nodiscard]] int factor_ranks(const TableReader& root) const;
  void read_mesh(const TableReader& b, physics::Body& body);
  void read_box(const TableReader& box, physics::Body& body);
  void read_mesh_file(const TableReader& mesh, physics::Body& body);
  /// Issue when a box has more cells in all than kMaxBoxCells, or more than fit in memory.
  [[nodiscard]] bool box_size_ok(const TableReader& box, const std::array<int, 3>& cells) const;
  void read_boundaries(const TableReader& root);
  void read_boundary(const toml::table& t, size_t index);
  /// film = { coefficient, ambient } and radiation = { emissivity, ambient } of a [[boundary]].
  void read_boundary_heat(const TableReader& b, physics::BoundaryCondition& bc);
  /// `contact`: one [contact] table or an array of [[contact]] tables, one pair each.
  void read_contacts(const TableReader& root);
  /// One pair at `path` ("contact" or "contact[i]"), appended to p_.contacts.
  TableReader read_contact(const toml::table& t, std::string path);
  void read_conductance(const TableReader& contact, physics::ContactSettings& c);
  /// `gap_conductance = { table, gas_conductivity, gas_offset, emissivity_slave,
  /// emissivity_master }` of pair c.
  void read_gap_conductance(const TableReader& contact, physics::ContactSettings& c);
  /// `master = { rigid = "plane", point, normal, velocity | displacement, temperature }` of
  /// pair c (case_rigid_tool.cpp): c.rigid_master, or issues; false when it has issues.
  bool read_rigid_tool(const TableReader& master, physics::ContactSettings& c);
  /// Issues for the rigid tool's keys on a side that is a body's surface (`side`: "slave" or
  /// "master"): a slave is always a body's surface.
  void refuse_tool_keys(const TableReader& s, std::string_view side);
  /// The thermal side of an adiabatic tool (no temperature): no conductance to give.
  void check_adiabatic_tool(const TableReader& contact);
  void read_solver(const TableReader& root);
  void read_output(const TableReader& root);
  /// [stability] (case_stability.cpp), with what the analysis needs of the rest of the case.
  void read_stability(const TableReader& root);
  /// [[probe]] tables (after the bodies: a point is located in its body's mesh).
  void read_probes(const TableReader& root);
  /// Warnings for values that are valid but implausible in SI (unit habits: MPa, °C, g/cm³).
  void warn_unit_habits();
  /// A warning `FILE:LINE: KEY: message` (the line of `key`, a dotted path, if known).
  void warn(const std::string& key, const std::string& message);

  /// The array of tables at `key` ([[key]]), or an issue.
  const toml::array* tables(const TableReader& root, std::string_view key);
  [[nodiscard]] std::filesystem::path resolve(const std::string& path) const {
    const std::filesystem::path p(path);
    return p.is_absolute() ? p : file_.parent_path() / p;
  }

  std::filesystem::path file_;
  Issues issues_;
  const toml::table& root_;
  physics::Problem p_;
  FieldFiles field_files_ = FieldFiles::vtu;
  int dim_ = 0;  // 0 while unknown (missing or invalid): lengths are then checked loosely
  std::map<std::string, std::optional<fem::Material>> materials_;  // nullopt: bad constants
  std::vector<bool> mesh_built_;                                   // per body
};

}  // namespace tc::io::detail
