#pragma once
// A scalar given as a constant or as a piecewise-linear table, constant beyond its ends: of
// time (case-format.md: Dirichlet and Neumann data, sources) or of the temperature (the
// interface laws 𝔉(θ), γ_C(θ) of 2.13). Two types, so that neither is evaluated at the other's
// argument.
#include <vector>

namespace tc::core {

/// v(x) of the table (x_i, v_i), x strictly increasing: linear between the x_i, v_0 before
/// x_0 and v_n after x_n; v_0 alone when x is empty (a constant).
[[nodiscard]] double piecewise_linear(const std::vector<double>& x, const std::vector<double>& v,
                                      double at);

class TimeTable {
 public:
  TimeTable() = default;
  /*implicit*/ TimeTable(double constant) : v_{constant} {}
  /// Requires t strictly increasing and t.size() == v.size() >= 1 (checked by the caller).
  TimeTable(std::vector<double> t, std::vector<double> v);

  [[nodiscard]] double operator()(double time) const { return piecewise_linear(t_, v_, time); }
  [[nodiscard]] bool is_constant() const { return t_.empty(); }
  [[nodiscard]] const std::vector<double>& times() const { return t_; }
  [[nodiscard]] const std::vector<double>& values() const { return v_; }

 private:
  std::vector<double> t_;       // empty for a constant
  std::vector<double> v_{0.0};  // one value for a constant
};

/// A material law of the temperature θ [K]: a constant, or piecewise linear in θ and
/// constant beyond the table's ends. A table whose values are all equal is that constant, so
/// a law written as a one-point or a flat table runs exactly as the number would.
class TemperatureTable {
 public:
  TemperatureTable() = default;
  /*implicit*/ TemperatureTable(double constant) : v_{constant} {}
  /// Requires theta strictly increasing and theta.size() == v.size() >= 1 (checked by the
  /// caller).
  TemperatureTable(std::vector<double> theta, std::vector<double> v);

  [[nodiscard]] double operator()(double theta) const {
    return piecewise_linear(theta_, v_, theta);
  }
  [[nodiscard]] bool is_constant() const { return theta_.empty(); }
  [[nodiscard]] const std::vector<double>& temperatures() const { return theta_; }
  [[nodiscard]] const std::vector<double>& values() const { return v_; }
  /// The largest and the smallest value the law takes (at a table point: it is linear between).
  [[nodiscard]] double max_value() const;
  [[nodiscard]] double min_value() const;
  /// dv/dθ: the slope of the segment holding θ (the upper one at a table point), 0 beyond the
  /// ends and for a constant.
  [[nodiscard]] double slope(double theta) const;
  /// ∫_from^to v(θ) dθ, exact for the piecewise-linear law (trapezoids on whole segments).
  [[nodiscard]] double integral(double from, double to) const;

 private:
  std::vector<double> theta_;   // empty for a constant
  std::vector<double> v_{0.0};  // one value for a constant
};

}  // namespace tc::core
