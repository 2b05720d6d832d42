#include "tc/physics/problem.hpp"

#include <cmath>

namespace tc::physics {

int TimeSettings::n_steps() const {
  return static_cast<int>(std::lround(end / step));
}

}  // namespace tc::physics
