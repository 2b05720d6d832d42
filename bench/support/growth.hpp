#pragma once
// The growth exponent of a cost against a size: the least-squares slope of log(cost) against
// log(size), which the benchmarks report for time and memory.
#include <cmath>
#include <vector>

namespace tc::bench {

/// Slope of log y against log x over the pairs (x_i, y_i); x, y > 0, at least two sizes.
inline double growth_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace tc::bench
