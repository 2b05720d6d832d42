#pragma once
// The keys of a case file, declared once as data (case-format.md is their contract): per
// table of the file its keys in the order the messages list them, each with its type, the
// values it takes (a range in the words of the messages, or choices), its default, its unit
// and one line of doc. The reader validates from it (TableReader), docs/case-format.md's key
// tables are tested against it (tests/unit/io_schema_test.cpp), and so are Problem's
// defaults (docs/choices.md, "One schema for the case keys").
#include <limits>
#include <span>
#include <string>
#include <string_view>

namespace tc::io::schema {

enum class Type {
  number,             // a finite number within `range`
  integer,            // an integer from `min` to `max` (10⁹ when max is 0)
  boolean,            // true or false
  string,             // any string
  name,               // a string that names something (a body, a boundary, a material)
  choice,             // one of `choices`
  time_table,         // a number or { t = [...], value = [...] } within `range`
  temperature_table,  // a number or { temperature = [...], value = [...] } within `range`
  gap_table,          // a number or { gap = [...], value = [...] } within `range`
  vector,             // `dimension` numbers
  numbers,            // a non-empty array of numbers, each within `range`
  counts,             // `dimension` integers ≥ 1
  components,         // `dimension` entries, each a number, a time table or "free"
  subdomains,         // an integer ≥ 1 or "auto"
  dimension,          // 2 or 3
  table,              // a table whose keys are the section `<path>.<key>`
  tables,             // an array of tables, each of the section `<key>`
  named_tables,       // tables NAME = { ... }, each of the section `<key>.*`
  contact_tables,     // one table or an array of tables, each of the section `<key>`
};

/// An interval of numbers with its words ("a time step > 0"); no words: any finite number.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_closed = false, hi_closed = false;
  std::string_view words;
  [[nodiscard]] bool contains(double x) const {
    return (x > lo || (lo_closed && x == lo)) && (x < hi || (hi_closed && x == hi));
  }
};

struct Key {
  std::string_view name;
  Type type;
  Range range{};  // number, time_table, temperature_table
  int min = 1;    // integer
  int max = 0;    // integer: 0 = up to 10⁹
  std::span<const std::string_view> choices{};
  /// The value an absent key stands for, as TOML (`1e-6`, `"nested"`, `true`), or `required`,
  /// `none` (nothing is prescribed), or the key whose value it takes
  /// (`physics.reference_temperature`).
  std::string_view default_value = "none";
  std::string_view unit = "";
  std::string_view doc = "";
  /// What a missing key or a wrong value is expected to be, where its type alone does not say.
  std::string_view expected = "";
  [[nodiscard]] bool required() const { return default_value == "required"; }
};

struct Section {
  /// The table's path as the key reference writes it: "" (the root), "time", "materials.*"
  /// (each named material), "bodies" (each [[bodies]] entry), "bodies.mesh.box".
  std::string_view path;
  std::span<const Key> keys;
};

/// Every section of the case file, the root first.
[[nodiscard]] std::span<const Section> sections();
/// The section at `path`; throws std::logic_error when there is none (a reader bug).
[[nodiscard]] const Section& section(std::string_view path);
/// The key `name` of `s`; throws std::logic_error when it has none (a reader bug).
[[nodiscard]] const Key& key(const Section& s, std::string_view name);
/// The key's full path in the reference: "solver.qp_tolerance", "bodies.mesh.box.min".
[[nodiscard]] std::string full_name(const Section& s, const Key& k);
/// The key's type in words for the reference: "number > 0", "\"plain\" | \"stabilised\"".
[[nodiscard]] std::string type_words(const Key& k);

}  // namespace tc::io::schema
