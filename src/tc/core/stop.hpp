#pragma once
// The process-wide stop request: the number of the stop signal (SIGINT, SIGTERM, …) that
// asked this process to stop, 0 while none did. apps/thermocontact's signal handler sets it;
// long waits below the app (the time loop, the Gmsh reader's child process) read it, so that a
// signal ends them promptly instead of being noticed only when they return.
#include <atomic>

namespace tc::core {

/// Lock-free, so that a signal handler may store into it.
extern std::atomic<int> stop_signal;
static_assert(std::atomic<int>::is_always_lock_free);

}  // namespace tc::core
