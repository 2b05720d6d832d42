#pragma once
// history.csv and result.pvd as the restart and kill tests read them.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace tc::test {

struct History {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  bool whole = true;  // every row has one value per column and ends with '\n'
};

inline std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream s(line);
  std::string cell;
  while (std::getline(s, cell, ',')) out.push_back(cell);
  return out;
}

inline History read_history(const std::filesystem::path& file) {
  History h;
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  if (!text.empty() && text.back() != '\n') h.whole = false;
  std::istringstream lines(text);
  std::string line;
  if (!std::getline(lines, line)) return h;
  h.columns = split_csv(line);
  while (std::getline(lines, line)) {
    const auto cells = split_csv(line);
    if (cells.size() != h.columns.size()) h.whole = false;
    std::vector<double> row;
    for (const auto& c : cells) {
      char* end = nullptr;
      row.push_back(std::strtod(c.c_str(), &end));
      if (end == c.c_str() || *end != '\0') h.whole = false;
    }
    h.rows.push_back(std::move(row));
  }
  return h;
}

/// The largest relative difference |a − b| / max(|a|, |b|) over all cells of the rows both
/// have, except the columns named in `skip` (0 when equal, also for a = b = 0).
inline double max_relative_difference(const History& a, const History& b,
                                      const std::vector<std::string>& skip) {
  double worst = 0;
  for (size_t r = 0; r < std::min(a.rows.size(), b.rows.size()); ++r)
    for (size_t c = 0; c < a.columns.size(); ++c) {
      if (std::find(skip.begin(), skip.end(), a.columns[c]) != skip.end()) continue;
      const double x = a.rows[r][c], y = b.rows[r][c];
      const double scale = std::max(std::abs(x), std::abs(y));
      if (x != y) worst = std::max(worst, scale > 0 ? std::abs(x - y) / scale : INFINITY);
    }
  return worst;
}

/// One column over all rows (empty when the history has no such column).
inline std::vector<double> column(const History& h, const std::string& name) {
  std::vector<double> out;
  const auto it = std::find(h.columns.begin(), h.columns.end(), name);
  if (it == h.columns.end()) return out;
  const auto c = static_cast<size_t>(it - h.columns.begin());
  for (const auto& r : h.rows) out.push_back(r[c]);
  return out;
}

/// Counters and wall times: not physical columns, left out of the comparisons below.
inline bool is_counter(const std::string& name) {
  static const std::vector<std::string> counters{"step",
                                                 "time",
                                                 "coupling_iterations",
                                                 "qp_iterations",
                                                 "operator_applications",
                                                 "wall_seconds",
                                                 "friction_iterations"};
  return std::find(counters.begin(), counters.end(), name) != counters.end();
}

/// max over rows of |a − b| in one column (infinite when the runs have different lengths).
inline double max_abs_difference(const History& a, const History& b, const std::string& name) {
  const auto va = column(a, name), vb = column(b, name);
  double d = vb.size() == va.size() ? 0.0 : INFINITY;
  for (size_t i = 0; i < va.size() && i < vb.size(); ++i) d = std::max(d, std::abs(va[i] - vb[i]));
  return d;
}

/// max over rows of |a − b| / scale per physical column of two runs of one case: the scale is
/// the column's largest magnitude in a, or for the components of one support's reaction the
/// largest of the three (a tangential reaction that is round-off next to the normal one is
/// judged against that).
inline std::map<std::string, double> column_differences(const History& a, const History& b) {
  auto peak = [&](const std::string& name) {
    double m = 0;
    for (const double v : column(a, name)) m = std::max(m, std::abs(v));
    return m;
  };
  std::map<std::string, double> out;
  for (const auto& name : a.columns) {
    if (is_counter(name)) continue;
    double scale = peak(name);
    if (name.rfind("reaction_", 0) == 0) {
      const auto group = name.substr(0, name.size() - 1);  // reaction_<body>_<where>_
      for (const char* k : {"x", "y", "z"}) scale = std::max(scale, peak(group + k));
    }
    // contact_force_<axis>[_<pair>]: against the resultant's largest component (a component
    // of a symmetric case is round-off, ~1e-4 N against 1e6 N on tests/cases/feti/quasistatic)
    const std::string force = "contact_force_";
    if (name.rfind(force, 0) == 0 && name.size() > force.size()) {
      const auto pair = name.substr(force.size() + 1);  // "" or "_<pair>"
      for (const char* k : {"x", "y", "z"}) scale = std::max(scale, peak(force + k + pair));
    }
    const double d = max_abs_difference(a, b, name);
    out[name] = scale > 0 ? d / scale : d;
  }
  return out;
}

/// The same over the peak of each column's unit: every energy and heat column (J) shares one
/// scale, every force and reaction (N) another, the rest their own peak. A quantity that is
/// round-off around zero while others of its unit are large (the frictional heat at impact,
/// 1e-11 J beside 1e4 J of kinetic energy; the thermoelastic net thermal energy, −4e-8 J) is
/// then judged at that unit's scale, not at its own noise.
inline std::map<std::string, double> differences_by_unit(const History& a, const History& b) {
  auto unit = [](const std::string& n) -> std::string {
    for (const char* e : {"energy", "heat", "dissipation", "work"})
      if (n.find(e) != std::string::npos) return "J";
    for (const char* f : {"force", "reaction"})
      if (n.find(f) != std::string::npos) return "N";
    return n;
  };
  std::map<std::string, double> peak, out;
  for (const auto& name : a.columns)
    if (!is_counter(name))
      for (const double v : column(a, name))
        peak[unit(name)] = std::max(peak[unit(name)], std::abs(v));
  for (const auto& name : a.columns) {
    if (is_counter(name)) continue;
    const double d = max_abs_difference(a, b, name), scale = peak[unit(name)];
    out[name] = scale > 0 ? d / scale : d;
  }
  return out;
}

/// The .vtu files a result.pvd lists, and whether it is a whole collection document.
struct Collection {
  bool whole = false;
  std::vector<std::string> files;
  std::vector<double> times;
};

inline Collection read_collection(const std::filesystem::path& file) {
  Collection c;
  std::ifstream in(file);
  std::stringstream ss;
  ss << in.rdbuf();
  const auto text = ss.str();
  c.whole = text.rfind("<?xml", 0) == 0 && text.find("<Collection>") != std::string::npos &&
            text.find("</Collection>\n</VTKFile>\n") != std::string::npos;
  const std::regex data_set(R"re(<DataSet timestep="([^"]*)" part="[0-9]+" file="([^"]*)"/>)re");
  for (std::sregex_iterator it(text.begin(), text.end(), data_set), end; it != end; ++it) {
    c.times.push_back(std::stod((*it)[1]));
    c.files.push_back((*it)[2]);
  }
  return c;
}

/// A .vtu that an XML reader would accept: it ends with the closing tag of the document,
/// after the grid (ASCII) or after the appended data (binary).
inline bool whole_vtu(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const auto text = ss.str();
  const auto ends_with = [&](const std::string& tail) {
    return text.size() > tail.size() &&
           text.compare(text.size() - tail.size(), tail.size(), tail) == 0;
  };
  return text.rfind("<?xml", 0) == 0 && (ends_with("</UnstructuredGrid>\n</VTKFile>\n") ||
                                         ends_with("</AppendedData>\n</VTKFile>\n"));
}

}  // namespace tc::test
