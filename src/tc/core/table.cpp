#include "tc/core/table.hpp"

#include <algorithm>
#include <cassert>

namespace tc::core {

TimeTable::TimeTable(std::vector<double> t, std::vector<double> v)
    : t_(std::move(t)), v_(std::move(v)) {
  assert(!v_.empty() && t_.size() == v_.size());
  assert(std::is_sorted(t_.begin(), t_.end()));
  if (t_.size() == 1) t_.clear();
}

double TimeTable::operator()(double time) const {
  if (t_.empty()) return v_.front();
  if (time <= t_.front()) return v_.front();
  if (time >= t_.back()) return v_.back();
  const auto hi = std::upper_bound(t_.begin(), t_.end(), time) - t_.begin();
  const auto lo = hi - 1;
  const double s = (time - t_[lo]) / (t_[hi] - t_[lo]);
  return (1.0 - s) * v_[lo] + s * v_[hi];
}

}  // namespace tc::core
