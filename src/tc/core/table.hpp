#pragma once
// A scalar given as a constant or as a piecewise-linear table of time, constant beyond
// its ends (case-format.md: Dirichlet and Neumann data, sources).
#include <vector>

namespace tc::core {

class TimeTable {
 public:
  TimeTable() = default;
  /*implicit*/ TimeTable(double constant) : v_{constant} {}
  /// Requires t strictly increasing and t.size() == v.size() >= 1 (checked by the caller).
  TimeTable(std::vector<double> t, std::vector<double> v);

  [[nodiscard]] double operator()(double time) const;
  [[nodiscard]] bool is_constant() const { return t_.empty(); }
  [[nodiscard]] const std::vector<double>& times() const { return t_; }
  [[nodiscard]] const std::vector<double>& values() const { return v_; }

 private:
  std::vector<double> t_;       // empty for a constant
  std::vector<double> v_{0.0};  // one value for a constant
};

}  // namespace tc::core
