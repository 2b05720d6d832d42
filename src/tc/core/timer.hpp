#pragma once
// Wall-clock time per named phase (summary.json: assembly, mortar, factorization, ...).
#include <chrono>
#include <map>
#include <string>

namespace tc::core {

class PhaseTimers {
 public:
  /// Adds the time from construction to destruction to phase `name`.
  class Scope {
   public:
    Scope(PhaseTimers& t, std::string name)
        : timers_(t), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}
    ~Scope() {
      timers_.add(name_,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    PhaseTimers& timers_;
    std::string name_;
    std::chrono::steady_clock::time_point start_;
  };

  [[nodiscard]] Scope scope(std::string name) { return Scope(*this, std::move(name)); }
  void add(const std::string& name, double seconds) { seconds_[name] += seconds; }
  [[nodiscard]] double operator[](const std::string& name) const {
    const auto it = seconds_.find(name);
    return it == seconds_.end() ? 0.0 : it->second;
  }
  [[nodiscard]] const std::map<std::string, double>& all() const { return seconds_; }

 private:
  std::map<std::string, double> seconds_;
};

}  // namespace tc::core
