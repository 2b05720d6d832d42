#include "tc/core/timer.hpp"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

namespace tc::core {

double peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;   // never fails for RUSAGE_SELF
  return 1024.0 * static_cast<double>(usage.ru_maxrss);  // Linux reports kibibytes
}

double seconds_since_process_start() {
  static const double start = [] {
    // Field 22 of /proc/self/stat, after the command in parentheses (which may hold spaces).
    std::ifstream in("/proc/self/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto close = text.rfind(')');
    timespec boot{};
    if (close == std::string::npos || clock_gettime(CLOCK_BOOTTIME, &boot) != 0) return -1.0;
    std::istringstream fields(text.substr(close + 2));
    std::string field;
    for (int i = 3; i <= 22 && fields >> field; ++i) {
    }
    const double ticks = std::atof(field.c_str()), hz = static_cast<double>(sysconf(_SC_CLK_TCK));
    if (ticks <= 0 || hz <= 0) return -1.0;
    // The start on the steady clock: now, less the time since the start on the boot clock.
    const double since = boot.tv_sec + 1e-9 * boot.tv_nsec - ticks / hz;
    const double steady =
        std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    return steady - std::max(0.0, since);
  }();
  const double now =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  static const double first = now;
  return now - (start >= 0 ? start : first);
}

}  // namespace tc::core
