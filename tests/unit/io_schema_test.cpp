// The case schema (src/tc/io/schema/case_schema.cpp) against what depends on it:
// docs/case-format.md's key table lists every key of the schema with its type, default, unit and
// doc, and nothing else; every key of the documented examples is in the schema; and each default of
// the schema is what the reader gives Problem when the key is absent (an absent key and the key set
// to its default read to the same Problem).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <toml++/toml.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>

#include "support/case_text.hpp"
#include "tc/dual/dual_contact.hpp"
#include "tc/io/case/case_reader.hpp"
#include "tc/io/schema/case_schema.hpp"

namespace {

namespace fs = std::filesystem;
namespace schema = tc::io::schema;
using tc::physics::Problem;

std::string read_file(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string case_format() {
  return read_file(fs::path(TC_SOURCE_DIR) / "docs/case-format.md");
}

/// The row of a key in the reference table, as the schema says it.
std::string row(const schema::Section& s, const schema::Key& k) {
  const auto d = k.default_value;
  const auto dflt = d == "required" || d == "none" ? std::string(d) : fmt::format("`{}`", d);
  return fmt::format("| `{}` | {} | {} | {} | {} |", schema::full_name(s, k), schema::type_words(k),
                     dflt, k.unit.empty() ? "–" : k.unit, k.doc);
}

/// The table rows (`| \`key\` | …`) of the section of case-format.md under `heading`.
std::map<std::string, std::string> documented_rows(const std::string& doc,
                                                   const std::string& heading) {
  std::map<std::string, std::string> rows;
  const auto begin = doc.find("\n" + heading + "\n");
  if (begin == std::string::npos) return rows;
  const auto end = doc.find("\n## ", begin + 1);
  std::istringstream in(doc.substr(begin, end - begin));
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const auto close = line.find('`', 3);
    rows[line.substr(3, close - 3)] = line;
  }
  return rows;
}

constexpr const char* kHeading = "## Keys, defaults and units";

TEST(CaseSchema, KeyTableOfCaseFormatIsTheSchema) {
  const auto rows = documented_rows(case_format(), kHeading);
  std::string expected;  // the whole table, to paste when a key was added to the schema
  size_t keys = 0;
  for (const auto& s : schema::sections())
    for (const auto& k : s.keys) {
      ++keys;
      expected += row(s, k) + "\n";
      const auto name = schema::full_name(s, k);
      const auto it = rows.find(name);
      if (it == rows.end())
        ADD_FAILURE() << name << " is in the schema but not in case-format.md's key table";
      else
        EXPECT_EQ(it->second, row(s, k)) << "the row of " << name;
    }
  for (const auto& [name, line] : rows) {
    bool known = false;
    for (const auto& s : schema::sections())
      for (const auto& k : s.keys) known = known || schema::full_name(s, k) == name;
    EXPECT_TRUE(known) << name << " is documented in the key table but not in the schema";
  }
  EXPECT_EQ(rows.size(), keys) << "the table as the schema has it:\n" << expected;
}

/// Every key of `t` (at schema section `path`) is a key of the schema; tables are followed.
void expect_in_schema(const toml::table& t, const std::string& path, const std::string& where,
                      int& checked) {
  const schema::Section* section = nullptr;
  for (const auto& s : schema::sections())
    if (s.path == path) section = &s;
  ASSERT_NE(section, nullptr) << where << ": no schema section " << path;
  for (const auto& [name, value] : t) {
    const std::string k(name.str());
    const schema::Key* key = nullptr;
    for (const auto& c : section->keys)
      if (c.name == k) key = &c;
    ++checked;
    if (!key) {
      ADD_FAILURE() << where << ": the documented key " << (path.empty() ? k : path + "." + k)
                    << " is not in the schema";
      continue;
    }
    const auto sub = path.empty() ? k : path + "." + k;
    using T = schema::Type;
    if (key->type == T::table && value.is_table())
      expect_in_schema(*value.as_table(), sub, where, checked);
    if ((key->type == T::tables || key->type == T::contact_tables) && value.is_array())
      for (const auto& e : *value.as_array())
        if (e.is_table()) expect_in_schema(*e.as_table(), sub, where, checked);
    if (key->type == T::contact_tables && value.is_table())
      expect_in_schema(*value.as_table(), sub, where, checked);
    if (key->type == T::named_tables && value.is_table())
      for (const auto& [n, m] : *value.as_table())
        if (m.is_table()) expect_in_schema(*m.as_table(), sub + ".*", where, checked);
  }
}

TEST(CaseSchema, DocumentedExampleKeysAreInTheSchema) {
  const auto doc = case_format();
  int blocks = 0, checked = 0;
  for (size_t at = doc.find("```toml\n"); at != std::string::npos;
       at = doc.find("```toml\n", at + 1)) {
    const auto begin = at + 8, end = doc.find("```", begin);
    const auto line = 1 + std::count(doc.begin(), doc.begin() + static_cast<long>(at), '\n');
    toml::table t;
    try {
      t = toml::parse(doc.substr(begin, end - begin));
    } catch (const toml::parse_error& e) {
      ADD_FAILURE() << "case-format.md:" << line << ": the example is not TOML: " << e.what();
      continue;
    }
    ++blocks;
    expect_in_schema(t, "", fmt::format("case-format.md:{}", line), checked);
  }
  EXPECT_GE(blocks, 2);     // the annotated case and the [[contact]] pairs at least
  EXPECT_GE(checked, 100);  // the annotated case alone names more keys than that
}

// ---------------------------------------------------------------------------------------
// Defaults

/// A two-body contact case that sets no optional key.
constexpr const char* kMinimalCase = R"(dimension = 3
[time]
step = 0.1
end = 0.2
[materials.steel]
density = 7850.0
young_modulus = 2.1e11
poisson_ratio = 0.3
thermal_expansion = 1.2e-5
specific_heat = 450.0
thermal_conductivity = 50.0
[[bodies]]
name = "a"
material = "steel"
mesh = { box = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0], cells = [2, 2, 2] } }
[[bodies]]
name = "b"
material = "steel"
mesh = { box = { min = [0.0, 0.0, 1.0], max = [1.0, 1.0, 2.0], cells = [2, 2, 2] } }
[[boundary]]
body = "a"
where = "zmin"
displacement = [0.0, 0.0, 0.0]
[[boundary]]
body = "b"
where = "zmax"
displacement = [0.0, 0.0, 0.0]
[contact]
slave = { body = "b", where = "zmin" }
master = { body = "a", where = "zmax" }
conductance = { slave = 1e-3, master = 1e-3 }
)";

std::string table_text(const tc::core::TemperatureTable& t) {
  return fmt::format("{}@{}", t.values(), t.temperatures());
}

/// Every setting of a Problem that a key with a default fills, as text.
std::string settings_text(const Problem& p) {
  std::string s =
      fmt::format("title {} | dimension {} | scheme {} {} | ", p.title, p.dimension,
                  static_cast<int>(p.time.scheme), static_cast<int>(p.time.contact_scheme));
  const auto& ph = p.physics;
  s += fmt::format("physics {} {} {} {} {} | ", ph.reference_temperature, ph.thermal_expansion,
                   ph.thermoelastic_heating, static_cast<int>(ph.thermoelastic_rate),
                   ph.lumped_heat_capacity);
  for (const auto& b : p.bodies) {
    s += fmt::format("body {} {} {} {} {} ", b.name, b.initial_temperature, b.initial_velocity,
                     b.start_in_equilibrium, b.subdomains);
    // A default TimeTable and TimeTable(0.0) are the same load: compare their values.
    for (const auto& f : b.body_force) s += fmt::format("{} {} ", f(0.0), f(1.0));
    s += fmt::format("{} {} | ", b.heat_source(0.0), b.heat_source(1.0));
  }
  for (const auto& c : p.contacts)
    s += fmt::format("contact {} {} {} {} {} {} | ", c.name, table_text(c.friction),
                     table_text(c.conductance_slave), table_text(c.conductance_master),
                     c.heat_conduction, c.frictional_heating);
  const auto& v = p.solver;
  s += fmt::format(
      "solver {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} | ",
      v.coupling_tolerance, v.max_coupling_iterations, static_cast<int>(v.friction_loop),
      static_cast<int>(v.coupling_order), v.friction.acceleration, v.friction.qp_forcing,
      v.friction.qp_forcing_cap, v.friction.loop_forcing, v.friction.max_updates,
      static_cast<int>(v.conductance_treatment), v.qp_tolerance, v.max_qp_iterations,
      static_cast<int>(v.contact_dual),
      // Unset: the dual solver's own limit, which the schema's default must be.
      v.explicit_dual_limit.value_or(tc::physics::DualContactSettings{}.explicit_limit),
      v.factorization, v.feti_tolerance, v.max_feti_iterations,
      static_cast<int>(v.feti_preconditioner), v.newton_tolerance, v.max_newton_iterations,
      v.max_cutbacks, v.modulus_tolerance);
  const auto& o = p.output;
  s += fmt::format("output {} {} {} {} {} {}", o.directory.string(), o.every, o.checkpoint_every,
                   o.checkpoint_seconds, static_cast<int>(o.encoding), o.contact_csv);
  return s;
}

/// The `--set` key of a schema key in kMinimalCase, or "" when its default cannot be set
/// there (required keys, keys with no default, tables).
std::string override_key(const schema::Section& s, const schema::Key& k) {
  const auto d = k.default_value;
  if (d == "required" || d == "none" || d == "physics.reference_temperature") return "";
  const std::map<std::string_view, std::string> prefix{{"", ""},
                                                       {"time", "time."},
                                                       {"physics", "physics."},
                                                       {"bodies", "bodies[0]."},
                                                       {"contact", "contact."},
                                                       {"solver", "solver."},
                                                       {"output", "output."}};
  const auto it = prefix.find(s.path);
  return it == prefix.end() ? "" : it->second + std::string(k.name);
}

TEST(CaseSchema, DefaultsAreWhatTheReaderGivesAnAbsentKey) {
  const auto dir = fs::temp_directory_path() / fmt::format("tc_schema_{}", getpid());
  fs::create_directories(dir);
  const auto file = dir / "case.toml";
  std::ofstream(file) << kMinimalCase;
  const auto without = settings_text(tc::io::read_case(file));
  int compared = 0;
  for (const auto& s : schema::sections())
    for (const auto& k : s.keys) {
      const auto key = override_key(s, k);
      if (key.empty()) continue;
      const std::string set = fmt::format("{}={}", key, k.default_value);
      const std::vector<std::string> overrides{set};
      EXPECT_EQ(settings_text(tc::io::read_case(file, overrides)), without) << "--set " << set;
      ++compared;
    }
  // Every optional key with a value of its own: 1 root, 2 time, 5 physics, 5 bodies,
  // 4 contact, 22 solver, 7 output.
  EXPECT_EQ(compared, 46);
  fs::remove_all(dir);
}

/// A key whose default differs from Problem's would be caught above only if settings_text
/// showed it: each key set to another valid value must change the text.
TEST(CaseSchema, SettingsTextSeesEveryDefaultedKey) {
  const auto dir = fs::temp_directory_path() / fmt::format("tc_schema_other_{}", getpid());
  fs::create_directories(dir);
  const auto file = dir / "case.toml";
  std::ofstream(file) << kMinimalCase;
  const auto without = settings_text(tc::io::read_case(file));
  const std::map<std::string, std::string> other{{"title", "\"x\""},
                                                 {"time.scheme", "\"quasistatic\""},
                                                 {"time.contact_scheme", "\"plain\""},
                                                 {"physics.reference_temperature", "300.0"},
                                                 {"physics.thermal_expansion", "false"},
                                                 {"physics.thermoelastic_heating", "false"},
                                                 {"physics.thermoelastic_rate", "\"newmark\""},
                                                 {"physics.heat_capacity", "\"lumped\""},
                                                 {"bodies[0].initial_velocity", "[1.0, 0.0, 0.0]"},
                                                 {"bodies[0].initial_state", "\"equilibrium\""},
                                                 {"bodies[0].body_force", "[1.0, 0.0, 0.0]"},
                                                 {"bodies[0].heat_source", "1.0"},
                                                 {"bodies[0].subdomains", "2"},
                                                 {"contact.name", "\"pair\""},
                                                 {"contact.friction", "0.5"},
                                                 {"contact.heat_conduction", "false"},
                                                 {"contact.frictional_heating", "false"},
                                                 {"solver.coupling_tolerance", "1e-5"},
                                                 {"solver.max_coupling_iterations", "21"},
                                                 {"solver.coupling_order", "\"heat_first\""},
                                                 {"solver.friction_loop", "\"staggered\""},
                                                 {"solver.qp_tolerance", "1e-9"},
                                                 {"solver.max_qp_iterations", "2001"},
                                                 {"solver.factorization", "\"petsc\""},
                                                 {"solver.feti_tolerance", "1e-9"},
                                                 {"solver.max_feti_iterations", "1001"},
                                                 {"solver.feti_preconditioner", "\"lumped\""},
                                                 {"solver.contact_dual", "\"auto\""},
                                                 {"solver.newton_tolerance", "1e-9"},
                                                 {"solver.max_newton_iterations", "51"},
                                                 {"solver.modulus_tolerance", "1e-2"},
                                                 {"solver.coupling_acceleration", "false"},
                                                 {"solver.conductance_treatment", "\"lagged\""},
                                                 {"solver.qp_forcing", "2e-2"},
                                                 {"solver.qp_forcing_cap", "2e-3"},
                                                 {"solver.loop_forcing", "2e-2"},
                                                 {"solver.max_friction_updates", "101"},
                                                 {"solver.explicit_dual_limit", "1501"},
                                                 {"solver.max_cutbacks", "5"},
                                                 {"output.directory", "\"elsewhere\""},
                                                 {"output.every", "2"},
                                                 {"output.format", "\"binary\""},
                                                 {"output.compression", "\"zlib\""},
                                                 {"output.contact_csv", "true"},
                                                 {"output.checkpoint_every", "1"},
                                                 {"output.checkpoint_seconds", "11.0"}};
  int changed = 0;
  for (const auto& s : schema::sections())
    for (const auto& k : s.keys) {
      const auto key = override_key(s, k);
      if (key.empty()) continue;
      const auto it = other.find(key);
      if (it == other.end()) {
        ADD_FAILURE() << key << ": no other value to set in this test";
        continue;
      }
      const std::vector<std::string> overrides{key + "=" + it->second};
      EXPECT_NE(settings_text(tc::io::read_case(file, overrides)), without) << key;
      ++changed;
    }
  EXPECT_EQ(changed, 46);
  fs::remove_all(dir);
}

// [stability] needs a case it can analyse (quasistatic, a rigid tool that slides): its keys'
// defaults are checked on one, as the two tests above check the other sections'.
const std::string kStabilityCase = std::string(R"(dimension = 2
[time]
scheme = "quasistatic"
step = 0.1
end = 1.0
[physics]
thermoelastic_heating = false
)") + tc::test::kSteelToml + R"([[bodies]]
name = "block"
material = "steel"
mesh = { box = { min = [0.0, -0.5], max = [1.0, 0.0], cells = [2, 2] } }
[[boundary]]
body = "block"
where = "ymin"
displacement = [0.0, 0.0]
[contact]
slave = { body = "block", where = "ymax" }
master = { rigid = "plane", point = [0.0, 0.0], normal = [0.0, -1.0], velocity = [0.1, -1.0e-6] }
friction = 0.1
[stability]
speeds = [0.1]
)";

std::string stability_text(const Problem& p) {
  const auto& s = p.stability.value();
  return fmt::format("{} {} {} {} {} {} {} {}", s.speeds, s.eigenvalues, s.critical_speed, s.modes,
                     static_cast<int>(s.normal_control), s.friction_shear, s.target.value_or(-1.0),
                     s.state_step);
}

TEST(CaseSchema, StabilityDefaultsAreWhatTheReaderGivesAnAbsentKey) {
  const auto dir = fs::temp_directory_path() / fmt::format("tc_schema_stability_{}", getpid());
  fs::create_directories(dir);
  const auto file = dir / "case.toml";
  std::ofstream(file) << kStabilityCase;
  const auto without = stability_text(tc::io::read_case(file));
  const std::map<std::string, std::string> other{
      {"eigenvalues", "5"},        {"critical_speed", "false"},
      {"modes", "false"},          {"normal_control", "\"force\""},
      {"friction_shear", "false"}, {"state_step", "2"}};
  int compared = 0;
  for (const auto& k : schema::section("stability").keys) {
    if (k.default_value == "none") continue;
    const auto key = "stability." + std::string(k.name);
    const std::vector<std::string> same{fmt::format("{}={}", key, k.default_value)};
    EXPECT_EQ(stability_text(tc::io::read_case(file, same)), without) << key;
    const auto it = other.find(std::string(k.name));
    ASSERT_NE(it, other.end()) << key << ": no other value to set in this test";
    const std::vector<std::string> changed{key + "=" + it->second};
    EXPECT_NE(stability_text(tc::io::read_case(file, changed)), without) << key;
    ++compared;
  }
  EXPECT_EQ(compared, 6);
  fs::remove_all(dir);
}

}  // namespace
