#include "tc/core/timer.hpp"

#include <sys/resource.h>

namespace tc::core {

double peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;   // never fails for RUSAGE_SELF
  return 1024.0 * static_cast<double>(usage.ru_maxrss);  // Linux reports kibibytes
}

}  // namespace tc::core
