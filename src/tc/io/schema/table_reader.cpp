#include "tc/io/schema/table_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace tc::io::detail {

int edit_distance(std::string_view a, std::string_view b) {
  std::vector<int> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j)
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] != b[j - 1])});
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

int line_of(const toml::node& n) {
  return static_cast<int>(n.source().begin.line);
}

namespace {

std::string describe_float(double v) {
  auto s = fmt::format("{}", v);
  // Say 2.0, not 2, so "expected an integer" reads right.
  if (std::isfinite(v) && s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

/// The largest integer any count or iteration limit of a case may have (an int holds it).
constexpr std::int64_t kMaxInteger = 1'000'000'000;

}  // namespace

std::string integer_issue(const toml::node& n, int min) {
  if (const auto* i = n.as_integer(); i && i->get() >= min && i->get() <= kMaxInteger) return "";
  // Beyond the limit "expected an integer ≥ 1" read as if 4294967297 were not an integer.
  if (n.is_number() && *n.value<double>() > static_cast<double>(kMaxInteger))
    return fmt::format("found {}, which is too large; expected an integer from {} to {}",
                       describe(n), min, kMaxInteger);
  return fmt::format("found {}, expected an integer ≥ {}", describe(n), min);
}

std::string describe(const toml::node& n) {
  if (const auto* s = n.as_string()) return fmt::format("\"{}\"", s->get());
  if (const auto* i = n.as_integer()) return fmt::format("{}", i->get());
  if (const auto* f = n.as_floating_point()) return describe_float(f->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = n.as_array())
    return a->size() == 1 ? "an array of 1 entry"
                          : fmt::format("an array of {} entries", a->size());
  if (n.is_table()) return "a table";
  return "a date or time";
}

void Issues::add(int line, std::string key, std::string message) {
  issues_.push_back({file_, std::max(line, 1), std::move(key), std::move(message)});
}

void Issues::raise() {
  std::stable_sort(issues_.begin(), issues_.end(),
                   [](const InputIssue& a, const InputIssue& b) { return a.line < b.line; });
  throw InputError(std::move(issues_));
}

const Range& temperature() {
  static const Range kelvin{[](double x) { return x > 0; }, "a temperature > 0 K"};
  return kelvin;
}

Range range_of(const schema::Key& key) {
  if (key.range.words.empty()) return {};
  return {[r = key.range](double x) { return r.contains(x); }, std::string(key.range.words)};
}

std::string expected_of(const schema::Key& key) {
  using T = schema::Type;
  switch (key.type) {
    case T::number:
      return range_of(key).expected;
    case T::integer:
      return fmt::format("an integer ≥ {}", key.min);
    case T::string:
    case T::name:
      return "a string";
    case T::boolean:
      return "true or false";
    case T::choice: {
      std::vector<std::string> quoted;
      for (const auto c : key.choices) quoted.push_back(fmt::format("\"{}\"", c));
      return fmt::format("one of {}", fmt::join(quoted, ", "));
    }
    case T::time_table:
      return range_of(key).expected + " (a number or a time table)";
    case T::temperature_table:
      return range_of(key).expected + " (a number or a table in θ)";
    case T::gap_table:
      return range_of(key).expected + " (a number or a table in the gap)";
    case T::table:
      return "a table";
    case T::tables:
    case T::contact_tables:
      return fmt::format("one or more [[{}]] tables", key.name);
    default:
      return std::string(key.expected);
  }
}

std::string join(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : fmt::format("{}.{}", path, key);
}

std::string at(const std::string& path, size_t index) {
  return fmt::format("{}[{}]", path, index);
}

// ---------------------------------------------------------------------------------------
// TableReader

TableReader::TableReader(const toml::table& t, std::string path, Issues& issues,
                         const schema::Section& section)
    : t_(&t), path_(std::move(path)), issues_(&issues), section_(&section) {
  std::vector<std::string_view> keys;
  for (const auto& k : section.keys) keys.push_back(k.name);
  report_unknown(keys);
}

TableReader::TableReader(const toml::table& t, std::string path, Issues& issues,
                         std::initializer_list<std::string_view> keys)
    : t_(&t), path_(std::move(path)), issues_(&issues) {
  report_unknown({keys.begin(), keys.size()});
}

void TableReader::report_unknown(std::span<const std::string_view> keys) {
  for (const auto& [k, v] : *t_) {
    const std::string_view name = k.str();
    if (std::find(keys.begin(), keys.end(), name) != keys.end()) continue;
    std::string_view best;
    int best_distance = 3;  // suggest only within edit distance 2
    for (const auto known : keys)
      if (const int d = edit_distance(name, known); d < best_distance) {
        best_distance = d;
        best = known;
      }
    const auto hint = best.empty() ? std::string() : fmt::format(" (did you mean '{}'?)", best);
    issues_->add(
        line_of(v), join(path_, name),
        fmt::format("found an unknown key{}, expected one of: {}", hint, fmt::join(keys, ", ")));
  }
}

int TableReader::line(std::string_view k) const {
  const auto* n = t_->get(k);
  return n ? line_of(*n) : line();
}

void TableReader::issue(std::string_view k, std::string message) const {
  issues_->add(line(k), key(k), std::move(message));
}

const toml::node* TableReader::get(std::string_view k, Need need, std::string_view expected) const {
  const auto* n = t_->get(k);
  if (!n && need == Need::required) issue(k, fmt::format("missing; expected {}", expected));
  return n;
}

std::optional<double> TableReader::number(std::string_view k, Need need, const Range& range) const {
  const auto* n = get(k, need, range.expected);
  return n ? read_number(*n, key(k), *issues_, range) : std::nullopt;
}

std::optional<int> TableReader::integer(std::string_view k, Need need, int min) const {
  const auto expected = fmt::format("an integer ≥ {}", min);
  const auto* n = get(k, need, expected);
  if (!n) return std::nullopt;
  if (auto problem = integer_issue(*n, min); !problem.empty()) {
    issue(k, std::move(problem));
    return std::nullopt;
  }
  return static_cast<int>(n->as_integer()->get());
}

std::optional<std::string> TableReader::string(std::string_view k, Need need) const {
  const auto* n = get(k, need, "a string");
  if (!n) return std::nullopt;
  if (const auto* s = n->as_string()) return s->get();
  issue(k, fmt::format("found {}, expected a string", describe(*n)));
  return std::nullopt;
}

std::optional<bool> TableReader::boolean(std::string_view k) const {
  const auto* n = get(k, Need::optional, "true or false");
  if (!n) return std::nullopt;
  if (const auto* b = n->as_boolean()) return b->get();
  issue(k, fmt::format("found {}, expected true or false", describe(*n)));
  return std::nullopt;
}

std::optional<std::string> TableReader::choice(std::string_view k, Need need,
                                               std::span<const std::string_view> choices) const {
  std::vector<std::string> quoted;
  for (const auto c : choices) quoted.push_back(fmt::format("\"{}\"", c));
  const auto expected = fmt::format("one of {}", fmt::join(quoted, ", "));
  const auto* n = get(k, need, expected);
  if (!n) return std::nullopt;
  const auto* s = n->as_string();
  if (s && std::find(choices.begin(), choices.end(), s->get()) != choices.end()) return s->get();
  issue(k, fmt::format("found {}, expected {}", describe(*n), expected));
  return std::nullopt;
}

const schema::Key& TableReader::spec(std::string_view k) const {
  if (!section_) throw std::logic_error(fmt::format("{}: a value table has no schema", path_));
  return schema::key(*section_, k);
}

const toml::node* TableReader::get(std::string_view k) const {
  const auto& s = spec(k);
  return get(k, s.required() ? Need::required : Need::optional, expected_of(s));
}

std::optional<double> TableReader::number(std::string_view k) const {
  const auto& s = spec(k);
  return number(k, s.required() ? Need::required : Need::optional, range_of(s));
}

std::optional<int> TableReader::integer(std::string_view k) const {
  const auto& s = spec(k);
  return integer(k, s.required() ? Need::required : Need::optional, s.min);
}

std::optional<std::string> TableReader::string(std::string_view k) const {
  return string(k, spec(k).required() ? Need::required : Need::optional);
}

std::optional<std::string> TableReader::choice(std::string_view k) const {
  const auto& s = spec(k);
  return choice(k, s.required() ? Need::required : Need::optional, s.choices);
}

std::optional<TableReader> TableReader::sub_table(std::string_view k) const {
  const auto& s = spec(k);
  const auto* n = get(k, s.required() ? Need::required : Need::optional, "a table");
  if (!n) return std::nullopt;
  const auto& sub = schema::section(join(std::string(section_->path), k));
  if (const auto* t = n->as_table()) return TableReader(*t, key(k), *issues_, sub);
  issue(k, fmt::format("found {}, expected a table", describe(*n)));
  return std::nullopt;
}

// ---------------------------------------------------------------------------------------
// Values

std::optional<double> read_number(const toml::node& n, const std::string& key, Issues& issues,
                                  const Range& range) {
  if (!n.is_number()) {
    const auto expected = range.ok ? fmt::format("a number ({})", range.expected) : range.expected;
    issues.add(line_of(n), key, fmt::format("found {}, expected {}", describe(n), expected));
    return std::nullopt;
  }
  const double v = *n.value<double>();
  if (!std::isfinite(v) || (range.ok && !range.ok(v))) {
    issues.add(line_of(n), key, fmt::format("found {}, expected {}", describe(n), range.expected));
    return std::nullopt;
  }
  return v;
}

namespace {

/// The non-empty array of numbers at member k of a time table.
std::optional<std::vector<double>> read_list(const TableReader& t, std::string_view k,
                                             const Range& range) {
  const auto* n = t.get(k, Need::required, "a non-empty array of numbers");
  if (!n) return std::nullopt;
  const auto* a = n->as_array();
  if (!a || a->empty()) {
    t.issue(k, fmt::format("found {}, expected a non-empty array of numbers", describe(*n)));
    return std::nullopt;
  }
  std::vector<double> out;
  bool good = true;
  for (size_t i = 0; i < a->size(); ++i) {
    const auto v = read_number(*a->get(i), at(t.key(k), i), t.issues(), range);
    good = good && v.has_value();
    out.push_back(v.value_or(0.0));
  }
  return good ? std::optional(std::move(out)) : std::nullopt;
}

/// The abscissa of a table: its key and the word for its entries in the messages.
struct Abscissa {
  std::string_view key, plural;
};
constexpr Abscissa kTime{"t", "times"};
constexpr Abscissa kInterfaceTemperature{"temperature", "temperatures"};
constexpr Abscissa kGap{"gap", "gaps"};

bool strictly_increasing(const TableReader& t, const std::vector<double>& x, Abscissa a) {
  for (size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1])) {
      t.issue(a.key, fmt::format("found {}[{}] = {} after {}[{}] = {}, expected strictly "
                                 "increasing {}",
                                 a.key, i, x[i], a.key, i - 1, x[i - 1], a.plural));
      return false;
    }
  return true;
}

/// The points and values of a table { <a.key> = [...], value = [...] }: the points strictly
/// increasing and within `x_range`, as many values as points (≥ 1), each within `range`.
std::optional<std::pair<std::vector<double>, std::vector<double>>> read_points(const TableReader& t,
                                                                               Abscissa a,
                                                                               const Range& x_range,
                                                                               const Range& range) {
  const auto x = read_list(t, a.key, x_range);
  const auto values = read_list(t, "value", range);
  if (!x || !values) return std::nullopt;
  bool good = strictly_increasing(t, *x, a);
  if (x->size() != values->size()) {
    t.issue("value", fmt::format("found {} values for {} {}, expected as many values as {}",
                                 values->size(), x->size(), a.plural, a.plural));
    good = false;
  }
  if (!good) return std::nullopt;
  return std::pair{*x, *values};
}

/// The array at n with `size` entries (0: 2 or 3, the dimension being unknown), or an issue
/// "expected an array of <size> <what> (dimension = <size>)<detail>".
const toml::array* sized_array(const toml::node& n, const std::string& key, Issues& issues,
                               int size, std::string_view what, std::string_view detail = "") {
  const auto* a = n.as_array();
  const int count = a ? static_cast<int>(a->size()) : -1;
  if (a && (size == 0 ? (count == 2 || count == 3) : count == size)) return a;
  const auto expected = size == 0 ? fmt::format("2 or 3 {}", what)
                                  : fmt::format("{} {} (dimension = {})", size, what, size);
  issues.add(line_of(n), key,
             fmt::format("found {}, expected an array of {}{}", describe(n), expected, detail));
  return nullptr;
}

}  // namespace

std::optional<core::TimeTable> read_time_table(const toml::node& n, const std::string& key,
                                               Issues& issues, const Range& range) {
  if (n.is_number()) {
    const auto v = read_number(n, key, issues, range);
    return v ? std::optional<core::TimeTable>(*v) : std::nullopt;
  }
  const auto* table = n.as_table();
  if (!table) {
    issues.add(line_of(n), key,
               fmt::format("found {}, expected {} or a table {{ t = [...], value = [...] }}",
                           describe(n), range.expected));
    return std::nullopt;
  }
  const TableReader t(*table, key, issues, {"t", "value"});
  const auto points = read_points(t, kTime, {}, range);
  if (!points) return std::nullopt;
  return core::TimeTable(points->first, points->second);
}

std::optional<core::TimeTable> read_gap_table(const toml::node& n, const std::string& key,
                                              Issues& issues, const Range& range) {
  if (n.is_number()) {
    const auto v = read_number(n, key, issues, range);
    return v ? std::optional<core::TimeTable>(*v) : std::nullopt;
  }
  const auto* table = n.as_table();
  if (!table) {
    issues.add(line_of(n), key,
               fmt::format("found {}, expected {} or a table in the gap {{ gap = [...] (m), "
                           "value = [...] }}",
                           describe(n), range.expected));
    return std::nullopt;
  }
  const TableReader t(*table, key, issues, {"gap", "value"});
  const Range gaps{[](double g) { return g >= 0; }, "a gap ≥ 0 m"};
  const auto points = read_points(t, kGap, gaps, range);
  if (!points) return std::nullopt;
  return core::TimeTable(points->first, points->second);
}

std::optional<core::TemperatureTable> read_temperature_table(const toml::node& n,
                                                             const std::string& key, Issues& issues,
                                                             const Range& range,
                                                             std::string_view argument) {
  if (n.is_number()) {
    const auto v = read_number(n, key, issues, range);
    return v ? std::optional<core::TemperatureTable>(*v) : std::nullopt;
  }
  const auto* table = n.as_table();
  if (!table) {
    issues.add(line_of(n), key,
               fmt::format("found {}, expected {} or a table in {} "
                           "{{ temperature = [...], value = [...] }}",
                           describe(n), range.expected, argument));
    return std::nullopt;
  }
  // `t` is accepted by the schema only to say what is wrong with it: a law of the interface
  // or of a material is a function of the temperature, never of time.
  const TableReader t(*table, key, issues, {"temperature", "value", "t"});
  if (t.has("t")) {
    t.issue("t", fmt::format("found a table in time, expected a table in {} "
                             "{{ temperature = [...] (K), value = [...] }}",
                             argument));
    return std::nullopt;
  }
  const auto points = read_points(t, kInterfaceTemperature, temperature(), range);
  if (!points) return std::nullopt;
  return core::TemperatureTable(points->first, points->second);
}

std::optional<std::array<double, 3>> read_vector(const toml::node& n, const std::string& key,
                                                 Issues& issues, int size) {
  const auto* a = sized_array(n, key, issues, size, "numbers");
  if (!a) return std::nullopt;
  std::array<double, 3> out{};
  bool good = true;
  for (size_t k = 0; k < a->size(); ++k) {
    const auto v = read_number(*a->get(k), at(key, k), issues);
    good = good && v.has_value();
    out[k] = v.value_or(0.0);
  }
  return good ? std::optional(out) : std::nullopt;
}

std::optional<std::array<int, 3>> read_counts(const toml::node& n, const std::string& key,
                                              Issues& issues, int size) {
  const auto* a = sized_array(n, key, issues, size, "integers ≥ 1");
  if (!a) return std::nullopt;
  std::array<int, 3> out{1, 1, 1};
  bool good = true;
  for (size_t k = 0; k < a->size(); ++k) {
    const auto& e = *a->get(k);
    if (auto problem = integer_issue(e, 1); !problem.empty()) {
      issues.add(line_of(e), at(key, k), std::move(problem));
      good = false;
      continue;
    }
    out[k] = static_cast<int>(e.as_integer()->get());
  }
  return good ? std::optional(out) : std::nullopt;
}

std::optional<Components> read_components(const toml::node& n, const std::string& key,
                                          Issues& issues, int size, bool free_allowed) {
  const auto* a = sized_array(
      n, key, issues, size, "components",
      free_allowed ? ", each a number, a table or \"free\"" : ", each a number or a table");
  if (!a) return std::nullopt;
  Components out;
  for (size_t k = 0; k < a->size(); ++k) {
    const auto& e = *a->get(k);
    const auto ek = at(key, k);
    if (const auto* s = e.as_string()) {
      if (!free_allowed || s->get() != "free")
        issues.add(line_of(e), ek,
                   fmt::format("found {}, expected a number or a table{}", describe(e),
                               free_allowed ? " or \"free\"" : ""));
      continue;
    }
    out[k] = read_time_table(e, ek, issues);
  }
  // Bad entries are reported and left empty: the caller still checks the others.
  return out;
}

// ---------------------------------------------------------------------------------------
// Names

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

std::string quoted_list(const std::vector<std::string>& names) {
  if (names.empty()) return "(none)";
  std::string out;
  for (const auto& n : names) out += fmt::format("{}\"{}\"", out.empty() ? "" : ", ", n);
  return out;
}

}  // namespace tc::io::detail
