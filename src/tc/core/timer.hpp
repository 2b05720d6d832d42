#pragma once
// Wall-clock time per named phase (summary.json: assembly, mortar, factorization, ...), and
// how much the process's peak resident memory rose while in each phase (summary.json's
// peak_memory_gib): where a run's memory goes, without an external profiler.
#include <chrono>
#include <map>
#include <string>

namespace tc::core {

/// The peak resident set size of this process so far (getrusage's ru_maxrss), in bytes.
[[nodiscard]] double peak_resident_bytes();

/// Wall seconds since this process started (its start time in /proc/self/stat against the
/// boot clock, to the kernel's tick: the loader's and the libraries' start-up included); since
/// the first call where /proc is not there.
[[nodiscard]] double seconds_since_process_start();

/// The phases' times are exclusive: a scope opened inside another pauses it, so the time of
/// nested phases is counted once, in the innermost, and the phases add up to the time spent
/// in any of them (summary.json's phases add up to the run's wall time).
class PhaseTimers {
 public:
  /// Adds the time from construction to destruction, less that of the scopes opened inside
  /// it, to phase `name`, and the rise of the peak resident memory in the whole time (a phase
  /// that allocates what an earlier one freed adds nothing: it is the high-water mark that is
  /// attributed).
  class Scope {
   public:
    Scope(PhaseTimers& t, std::string name)
        : timers_(t),
          name_(std::move(name)),
          start_(std::chrono::steady_clock::now()),
          peak_(peak_resident_bytes()),
          outer_(t.open_) {
      if (outer_) outer_->pause(start_);
      t.open_ = this;
    }
    ~Scope() {
      const auto now = std::chrono::steady_clock::now();
      pause(now);
      timers_.peak_growth_[name_] += peak_resident_bytes() - peak_;
      timers_.open_ = outer_;
      if (outer_) outer_->start_ = now;
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    void pause(std::chrono::steady_clock::time_point now) {
      timers_.add(name_, std::chrono::duration<double>(now - start_).count());
      start_ = now;
    }
    PhaseTimers& timers_;
    std::string name_;
    std::chrono::steady_clock::time_point start_;
    double peak_;
    Scope* outer_;
  };

  [[nodiscard]] Scope scope(std::string name) { return Scope(*this, std::move(name)); }
  void add(const std::string& name, double seconds) { seconds_[name] += seconds; }
  [[nodiscard]] double operator[](const std::string& name) const {
    const auto it = seconds_.find(name);
    return it == seconds_.end() ? 0.0 : it->second;
  }
  [[nodiscard]] const std::map<std::string, double>& all() const { return seconds_; }
  /// Bytes by which the peak resident memory rose inside phase `name`.
  [[nodiscard]] double peak_growth(const std::string& name) const {
    const auto it = peak_growth_.find(name);
    return it == peak_growth_.end() ? 0.0 : it->second;
  }

 private:
  std::map<std::string, double> seconds_;
  std::map<std::string, double> peak_growth_;
  Scope* open_ = nullptr;  // the innermost open scope
};

}  // namespace tc::core
