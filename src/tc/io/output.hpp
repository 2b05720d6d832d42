#pragma once
// What a run leaves in its output directory (case-format.md): result.pvd with one .vtu per
// body and written step, history.csv (one row per step), summary.json (rewritten at start,
// "running", and at the end, "completed" or "stopped"). Only MPI rank 0 writes.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <vector>

#include "tc/io/vtu.hpp"
#include "tc/physics/simulation.hpp"

namespace tc::io {

class OutputWriter : public physics::Observer {
 public:
  explicit OutputWriter(std::filesystem::path directory, int every = 1);
  ~OutputWriter() override;
  void start(const physics::Simulation& sim) override;
  void step(const physics::Simulation& sim) override;
  void finish(const physics::Simulation& sim, const physics::RunStatus& status) override;

 private:
  void write_fields(const physics::Simulation& sim);
  void write_summary(const physics::Simulation& sim, const std::string& status,
                     const std::string& message) const;

  std::filesystem::path dir_;
  int every_;
  bool root_;
  std::unique_ptr<PvdCollection> pvd_;
  std::FILE* history_ = nullptr;
  double output_seconds_ = 0;
};

/// The fields of one body written to its .vtu (exposed for tests).
void body_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data,
                 std::vector<Field>& cell_data);

/// The contact fields of the slave body (contact_pressure, tangential_traction, slip_velocity),
/// appended to its point data; nothing for other bodies or without a mortar pair.
void contact_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data);

/// A progress line: rewritten in place on a terminal, plain lines (about 20 per run) otherwise.
class ProgressLine : public physics::Observer {
 public:
  explicit ProgressLine(bool terminal);
  void step(const physics::Simulation& sim) override;
  void finish(const physics::Simulation& sim, const physics::RunStatus& status) override;

 private:
  bool terminal_;
  bool root_;
  double start_ = 0;
};

/// Forwards every event to each observer in order.
class Observers : public physics::Observer {
 public:
  explicit Observers(std::vector<physics::Observer*> list) : list_(std::move(list)) {}
  void start(const physics::Simulation& s) override {
    for (auto* o : list_) o->start(s);
  }
  void step(const physics::Simulation& s) override {
    for (auto* o : list_) o->step(s);
  }
  void finish(const physics::Simulation& s, const physics::RunStatus& r) override {
    for (auto* o : list_) o->finish(s, r);
  }

 private:
  std::vector<physics::Observer*> list_;
};

/// A JSON string literal with the escapes JSON requires.
[[nodiscard]] std::string json_string(const std::string& s);

}  // namespace tc::io
