#include "tc/core/stop.hpp"

namespace tc::core {

std::atomic<int> stop_signal{0};

}  // namespace tc::core
