#include "tc/core/table.hpp"

#include <algorithm>

#include "tc/core/verify.hpp"

namespace tc::core {

double piecewise_linear(const std::vector<double>& x, const std::vector<double>& v, double at) {
  if (x.empty()) return v.front();
  if (at <= x.front()) return v.front();
  if (at >= x.back()) return v.back();
  const auto hi = std::upper_bound(x.begin(), x.end(), at) - x.begin();
  const auto lo = hi - 1;
  const double s = (at - x[lo]) / (x[hi] - x[lo]);
  return (1.0 - s) * v[lo] + s * v[hi];
}

TimeTable::TimeTable(std::vector<double> t, std::vector<double> v)
    : t_(std::move(t)), v_(std::move(v)) {
  TC_VERIFY(!v_.empty() && t_.size() == v_.size(), "a time table pairs each time with a value");
  TC_VERIFY(std::is_sorted(t_.begin(), t_.end()), "the reader sorts a time table's times");
  if (t_.size() == 1) t_.clear();
}

TemperatureTable::TemperatureTable(std::vector<double> theta, std::vector<double> v)
    : theta_(std::move(theta)), v_(std::move(v)) {
  TC_VERIFY(!v_.empty() && theta_.size() == v_.size(),
            "a temperature table pairs each temperature with a value");
  TC_VERIFY(std::is_sorted(theta_.begin(), theta_.end()),
            "the reader sorts a temperature table's temperatures");
  // Flat: the constant itself, bit for bit (interpolating between equal values need not give
  // that value back in floating point).
  if (std::all_of(v_.begin(), v_.end(), [&](double x) { return x == v_.front(); })) {
    theta_.clear();
    v_.resize(1);
  }
}

double TemperatureTable::max_value() const {
  return *std::max_element(v_.begin(), v_.end());
}

double TemperatureTable::min_value() const {
  return *std::min_element(v_.begin(), v_.end());
}

double TemperatureTable::slope(double theta) const {
  if (theta_.empty() || theta < theta_.front() || theta >= theta_.back()) return 0.0;
  const auto hi = std::upper_bound(theta_.begin(), theta_.end(), theta) - theta_.begin();
  const auto lo = hi - 1;
  return (v_[hi] - v_[lo]) / (theta_[hi] - theta_[lo]);
}

double TemperatureTable::integral(double from, double to) const {
  if (from > to) return -integral(to, from);
  if (theta_.empty()) return v_.front() * (to - from);
  // Over [from, to] the law is linear between the breakpoints inside it and at its ends: the
  // trapezoid of each piece is exact.
  double sum = 0, x = from, fx = (*this)(from);
  for (size_t i = 0; i < theta_.size(); ++i) {
    if (theta_[i] <= from) continue;
    if (theta_[i] >= to) break;
    sum += 0.5 * (fx + v_[i]) * (theta_[i] - x);
    x = theta_[i];
    fx = v_[i];
  }
  return sum + 0.5 * (fx + (*this)(to)) * (to - x);
}

}  // namespace tc::core
