#pragma once
// Private to the io layer: the pieces read_case validates a TOML case file with.
// `Issues` collects every problem with its line (nothing is thrown until the whole file has
// been read); `TableReader` reads one TOML table at a dotted key path with typed getters that
// record what is wrong ("found X, expected Y") and reports the keys it does not know, with the
// closest known key as a suggestion. The node-level readers serve array entries and values
// (time tables, vectors) that are not a table member of their own.
#include <toml++/toml.h>

#include <array>
#include <functional>
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/table.hpp"
#include "tc/io/schema/case_schema.hpp"

namespace tc::io::detail {

/// Levenshtein distance (insertions, deletions, substitutions).
[[nodiscard]] int edit_distance(std::string_view a, std::string_view b);
/// Line of a node in its file (0 when unknown).
[[nodiscard]] int line_of(const toml::node& n);
/// What a node is, for "found ...": `"fast"`, `0.5`, `2.0`, `true`, `an array of 3 entries`.
[[nodiscard]] std::string describe(const toml::node& n);
/// "" when n is an integer from `min` to 10⁹, otherwise the issue: "found X, expected an
/// integer ≥ min", or "found X, which is too large; expected an integer from min to 10⁹".
[[nodiscard]] std::string integer_issue(const toml::node& n, int min);

/// The problems of one case file, thrown together as one InputError.
class Issues {
 public:
  explicit Issues(std::string file) : file_(std::move(file)) {}
  /// A line < 1 (unknown) is reported as line 1 so every issue points into the file.
  void add(int line, std::string key, std::string message);
  [[nodiscard]] bool empty() const { return issues_.empty(); }
  [[nodiscard]] size_t size() const { return issues_.size(); }
  /// Throws InputError with the issues in file order (stable by line).
  [[noreturn]] void raise();

 private:
  std::string file_;
  std::vector<InputIssue> issues_;
};

/// A constraint on a number: the predicate and the words that say what is expected.
struct Range {
  std::function<bool(double)> ok;  // empty = any finite number
  std::string expected = "a number";
};
/// A temperature: "a temperature > 0 K".
[[nodiscard]] const Range& temperature();
/// A key's range as the readers check it (no words: any finite number).
[[nodiscard]] Range range_of(const schema::Key& key);
/// What a missing key is expected to be: "a time step > 0", "an integer ≥ 1", "a table".
[[nodiscard]] std::string expected_of(const schema::Key& key);

enum class Need { optional, required };

/// Joins a dotted key path: join("", "a") = "a", join("a", "b") = "a.b".
[[nodiscard]] std::string join(const std::string& path, std::string_view key);
/// Indexed key: at("bodies", 1) = "bodies[1]".
[[nodiscard]] std::string at(const std::string& path, size_t index);

/// One TOML table at a dotted key path with its schema (the keys it may hold). Constructing it
/// reports every other key as unknown. Holds references: the table and Issues must outlive it.
/// A table of the case file reads its section of case_schema.cpp: the getters without a
/// need or a range take them from there. The value tables (`{ t, value }`) name their keys.
class TableReader {
 public:
  TableReader(const toml::table& t, std::string path, Issues& issues,
              const schema::Section& section);
  TableReader(const toml::table& t, std::string path, Issues& issues,
              std::initializer_list<std::string_view> keys);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] std::string key(std::string_view k) const { return join(path_, k); }
  [[nodiscard]] int line() const { return line_of(*t_); }
  [[nodiscard]] const toml::table& table() const { return *t_; }
  [[nodiscard]] Issues& issues() const { return *issues_; }
  [[nodiscard]] bool has(std::string_view k) const { return t_->contains(k); }
  /// Line of member k, or of the table when k is absent.
  [[nodiscard]] int line(std::string_view k) const;
  /// Records an issue about member k (at its line, or the table's when absent).
  void issue(std::string_view k, std::string message) const;

  /// Member k; when absent and required, an issue "missing; expected <expected>".
  const toml::node* get(std::string_view k, Need need, std::string_view expected) const;
  std::optional<double> number(std::string_view k, Need need, const Range& range = {}) const;
  std::optional<int> integer(std::string_view k, Need need, int min) const;
  std::optional<std::string> string(std::string_view k, Need need) const;
  std::optional<bool> boolean(std::string_view k) const;
  /// A string that must be one of `choices`.
  std::optional<std::string> choice(std::string_view k, Need need,
                                    std::span<const std::string_view> choices) const;

  // The same, member k as the section's schema declares it.
  [[nodiscard]] const schema::Key& spec(std::string_view k) const;
  const toml::node* get(std::string_view k) const;
  std::optional<double> number(std::string_view k) const;
  std::optional<int> integer(std::string_view k) const;
  std::optional<std::string> string(std::string_view k) const;
  std::optional<std::string> choice(std::string_view k) const;
  /// Member k as a table of the section `<this section>.<k>`.
  std::optional<TableReader> sub_table(std::string_view k) const;

 private:
  void report_unknown(std::span<const std::string_view> keys);

  const toml::table* t_;
  std::string path_;
  Issues* issues_;
  const schema::Section* section_ = nullptr;  // null: a value table
};

/// A finite number within `range`, or an issue at `key`.
std::optional<double> read_number(const toml::node& n, const std::string& key, Issues& issues,
                                  const Range& range = {});
/// A number or a table { t = [...], value = [...] }: t strictly increasing, as many values as
/// times (≥ 1), every value within `range`.
std::optional<core::TimeTable> read_time_table(const toml::node& n, const std::string& key,
                                               Issues& issues, const Range& range = {});
/// A number or a table in a temperature { temperature = [...], value = [...] }: temperatures
/// > 0 K and strictly increasing, as many values as temperatures (≥ 1), every value within
/// `range`; a table in time ({ t = ... }) is an issue of its own. `argument` names the
/// temperature in the messages (the interface's for the contact laws, the body's for a
/// material).
std::optional<core::TemperatureTable> read_temperature_table(
    const toml::node& n, const std::string& key, Issues& issues, const Range& range = {},
    std::string_view argument = "the interface temperature");
/// A number or a table in the gap { gap = [...], value = [...] }: gaps ≥ 0 and strictly
/// increasing, as many values as gaps (≥ 1), every value within `range`; piecewise linear,
/// constant beyond its ends (a TimeTable whose abscissa is the gap).
std::optional<core::TimeTable> read_gap_table(const toml::node& n, const std::string& key,
                                              Issues& issues, const Range& range = {});
/// An array of `n` finite numbers (n = 0: 2 or 3 entries, the dimension being unknown).
std::optional<std::array<double, 3>> read_vector(const toml::node& n, const std::string& key,
                                                 Issues& issues, int size);
/// An array of `n` integers ≥ 1 (n = 0: 2 or 3 entries); absent entries are 1.
std::optional<std::array<int, 3>> read_counts(const toml::node& n, const std::string& key,
                                              Issues& issues, int size);

/// Per component a number, a time table, or (when free_allowed) the string "free", which
/// leaves the component empty like an absent one.
using Components = std::array<std::optional<core::TimeTable>, 3>;
std::optional<Components> read_components(const toml::node& n, const std::string& key,
                                          Issues& issues, int size, bool free_allowed);

// ---------------------------------------------------------------------------------------
// Names

/// Longest body or boundary name that may reach a file name or a history.csv column.
inline constexpr size_t kMaxNameLength = 64;

/// `s` with control and non-ASCII bytes as \xNN, so that a reported value stays on its line.
[[nodiscard]] std::string printable(std::string_view s);
/// Why `name` cannot be used as a body or boundary name, or "" when it can.
[[nodiscard]] std::string unsafe_name(std::string_view name);
/// An issue at member k when its string value is not a safe name (see unsafe_name).
void check_name(const TableReader& t, std::string_view k, const std::string& name,
                std::string_view used_in);
/// An issue at a contact pair's `name` when it is not 1 to kMaxNameLength letters,
/// digits or '_': it becomes the suffix of history.csv columns (contact_normal_force_<name>).
void check_pair_name(const TableReader& t, const std::string& name);
/// `"a", "b"`, or "(none)".
[[nodiscard]] std::string quoted_list(const std::vector<std::string>& names);

}  // namespace tc::io::detail
