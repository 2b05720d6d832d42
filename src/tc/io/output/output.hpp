#pragma once
// What a run leaves in its output directory (case-format.md): result.pvd with one .vtu per
// body and written step, history.csv (one row per step), summary.json (rewritten at start,
// "running", and at the end, "completed" or "stopped"). Only MPI rank 0 writes, except the
// fields on more than one rank: each rank writes the cells of its own subdomains as a piece
// (<body>_<step>_<rank>.vtu) and rank 0 the .pvtu that lists them, which result.pvd names;
// or, with format = "vtkhdf", every rank writes its piece into one <body>_<step>.vtkhdf.
// Every writing phase is collective (core::collective_check): a failure on one rank stops all.
// Every file is whole whenever the run stops, even by SIGKILL: history.csv gets one write()
// per row (a row is there or not, never half), result.pvd and summary.json are replaced by
// a rename, and a .vtu is listed in result.pvd only once it is written.
#include <atomic>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tc/io/files/files.hpp"
#include "tc/io/output/probes.hpp"
#include "tc/io/vtk/vtkhdf.hpp"
#include "tc/io/vtk/vtu.hpp"
#include "tc/run/simulation.hpp"

namespace tc::io {

class OutputWriter : public physics::Observer {
 public:
  explicit OutputWriter(std::filesystem::path directory, int every = 1,
                        VtuEncoding encoding = VtuEncoding::ascii,
                        FieldFiles files = FieldFiles::vtu);
  /// The encoding `[output]` format and compression name.
  [[nodiscard]] static VtuEncoding encoding_of(const physics::OutputSettings& output);
  /// Continue the output of a run restarted from a checkpoint (io/restart/checkpoint.hpp) instead
  /// of starting afresh: at start(), history.csv keeps its rows before the restored step and
  /// result.pvd its data sets up to it; the restored step's row is written again (the same
  /// values) and its fields, written by the first run, are kept.
  void resume() { resume_ = true; }
  /// The stop flag of the signal handlers: once it is set, summary.stopped.json is renamed
  /// over summary.json after every row, so that a kill before finish() (mpirun's SIGKILL a
  /// second after its SIGTERM) leaves a summary.json that says "stopped" after the last row.
  void watch_stop(const std::atomic<int>* stop) { stop_ = stop; }
  ~OutputWriter() override;
  void start(const physics::Simulation& sim) override;
  void step(const physics::Simulation& sim) override;
  void finish(const physics::Simulation& sim, const physics::RunStatus& status) override;
  /// The last step whose history row is written (rank 0): summary.json's steps_done. One less
  /// than the simulation's step when that step's row could not be written.
  [[nodiscard]] int steps_written() const { return steps_written_; }
  /// summary.json as it must read should the process end before finish() writes the real one
  /// (a second stop signal; a kill after a first one, as mpirun does; a summary.json that
  /// cannot be written): status "stopped" and the steps whose output is whole. Rewritten in
  /// place after every history row (no rename: write_stopped_summary), removed by finish(); a
  /// signal handler renames it over summary.json (rename is async-signal-safe; formatting JSON
  /// there is not).
  [[nodiscard]] static std::filesystem::path stopped_summary(const std::filesystem::path& dir) {
    return dir / "summary.stopped.json";  // the name is spelled out where the file is renamed
  }
  /// The run's phases outside the simulation, in summary.json's wall_seconds with the
  /// simulation's: "history" and "output" (the fields) timed here; "startup", "reading",
  /// "checkpoint" and "progress" by the caller (TimedObserver).
  [[nodiscard]] core::PhaseTimers& phases() { return phases_; }

 private:
  void write_fields(const physics::Simulation& sim);
  /// Body b's <stem>.vtkhdf, every rank's piece written collectively (all ranks call it).
  void write_vtkhdf_fields(const physics::Simulation& sim, int b, const std::string& stem);
  /// result.pvd of a restart: its data sets up to the restored step, or, when it is missing or
  /// not whole, a list rebuilt from the whole .vtu/.pvtu files of those steps found in dir_.
  void resume_collection(const physics::Simulation& sim);
  /// Throws OutputError when dir_ or its history.csv is no longer the one this run opened at
  /// start (deleted, `rm -rf` and made again, replaced by another run's): the rows written
  /// would be in no file of dir_, and a run that said `done` would have lost them (issue 42,
  /// D2). Rank 0; a stat() of each, cheap beside a step.
  void require_in_place();
  /// summary.json "stopped" when it cannot be written in full at the end (a full disk):
  /// summary.stopped.json, already on disk, renamed over it (issue 42, D12).
  void fall_back_to_stopped_summary(const physics::Simulation& sim,
                                    const std::string& message) const;
  [[nodiscard]] std::string summary_text(const physics::Simulation& sim, const std::string& status,
                                         const std::string& message) const;
  void write_summary(const physics::Simulation& sim, const std::string& status,
                     const std::string& message,
                     const std::string& file_name = "summary.json") const;
  /// summary.stopped.json rewritten in place (created once, O_EXCL | O_NOFOLLOW through pin_).
  void write_stopped_summary(const physics::Simulation& sim, const std::string& message);

  std::filesystem::path dir_;
  int every_;
  VtuEncoding encoding_;
  FieldFiles files_;
  bool root_;
  std::unique_ptr<PinnedDirectory> pin_;  // every write into dir_ goes through it
  std::unique_ptr<PvdCollection> pvd_;
  void open_history(const physics::Simulation& sim);
  /// `name` in dir_ with the header of `columns`, kept open for appending; on a resume its rows
  /// before the restored step stay (the header must match).
  [[nodiscard]] int open_csv(const std::string& name, const std::vector<std::string>& columns);
  void append_history(const std::string& line);

  int history_fd_ = -1;
  int probes_fd_ = -1;                  // probes.csv, with [[probe]] tables
  std::vector<ProbeStencil> stencils_;  // of the probes
  struct Identity {
    unsigned long long device = 0, inode = 0;
  };
  Identity directory_id_, history_id_;  // what start() opened (require_in_place)
  int stopped_fd_ = -1;                 // summary.stopped.json, rewritten in place
  size_t stopped_length_ = 0;           // its length so far (a shorter text is padded to it)
  int steps_written_ = 0;  // the last step whose history row is written (summary's steps_done)
  bool failed_ = false;    // a write failed or a row was not finite: the run is stopping
  bool resume_ = false;
  const std::atomic<int>* stop_ = nullptr;
  int resumed_step_ = -1;
  [[nodiscard]] std::string phases_json(const core::PhaseTimers& simulation) const;
  core::PhaseTimers phases_;
  std::string peak_memory_ = "null";  // summary.json's peak_memory_gib, gathered collectively
};

/// summary.json's peak_memory_gib: the peak resident memory of the largest and of the smallest
/// rank so far, and per phase the largest rise of a rank's peak inside it, in GiB. Collective
/// over PETSC_COMM_WORLD; the text is rank 0's.
[[nodiscard]] std::string peak_memory_json(const core::PhaseTimers& timers);

/// summary.json's blas_threads: the policy (core/numeric/threads.hpp), this rank's budget and what
/// its large kernels used so far.
[[nodiscard]] std::string blas_threads_json();

/// The fields of one body written to its .vtu (exposed for tests).
void body_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data,
                 std::vector<Field>& cell_data);

/// The contact fields (contact_pressure, tangential_traction, slip_velocity,
/// contact_heat_flux) of a body that is the slave or the master of a mortar pair, appended to
/// its point data: the slave's at its contact nodes, the master's carried through the mortar
/// (output_fields.cpp, MasterSide); nothing for other bodies.
void contact_fields(const physics::Simulation& sim, int body, std::vector<Field>& point_data);

/// The contact state of pair q per contact node k (its slave node nodes[k], weight ∫ψ_k):
/// pressure and conducted heat flux, tangential traction and slip velocity (3 per node).
/// nullopt without a mortar pair or multipliers for it.
struct PairNodeFields {
  std::vector<int> nodes;
  std::vector<double> weights, pressure, heat_flux, traction, slip_velocity;
};
[[nodiscard]] std::optional<PairNodeFields> pair_node_fields(const physics::Simulation& sim, int q);

/// contact_<step>.csv's text: one row per contact node of every pair (output.contact_csv).
[[nodiscard]] std::string contact_csv(const physics::Simulation& sim);
/// summary.json's "compliance": per contact body, how its compliances (A⁻¹)_TT were grown.
[[nodiscard]] std::string compliance_json(const physics::Simulation& sim);

/// A progress line: rewritten in place on a terminal, plain lines (about 20 per run) otherwise.
class ProgressLine : public physics::Observer {
 public:
  explicit ProgressLine(bool terminal);
  void step(const physics::Simulation& sim) override;
  void finish(const physics::Simulation& sim, const physics::RunStatus& status) override;
  /// "warning: …" on stderr (rank 0), on a line of its own.
  void warning(const physics::Simulation& sim, const std::string& message) override;

 private:
  bool terminal_;
  bool root_;
  double start_ = 0;
};

/// Forwards every event to `observer`, its time counted in phase `name` of `timers`.
class TimedObserver : public physics::Observer {
 public:
  TimedObserver(physics::Observer& observer, core::PhaseTimers& timers, std::string name)
      : observer_(observer), timers_(timers), name_(std::move(name)) {}
  void start(const physics::Simulation& s) override {
    auto t = timers_.scope(name_);
    observer_.start(s);
  }
  void step(const physics::Simulation& s) override {
    auto t = timers_.scope(name_);
    observer_.step(s);
  }
  void finish(const physics::Simulation& s, const physics::RunStatus& r) override {
    auto t = timers_.scope(name_);
    observer_.finish(s, r);
  }
  void warning(const physics::Simulation& s, const std::string& m) override {
    observer_.warning(s, m);  // the progress line prints the run's warnings
  }

 private:
  physics::Observer& observer_;
  core::PhaseTimers& timers_;
  std::string name_;
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
  void warning(const physics::Simulation& s, const std::string& m) override {
    for (auto* o : list_) o->warning(s, m);
  }

 private:
  std::vector<physics::Observer*> list_;
};

/// A JSON string literal with the escapes JSON requires.
[[nodiscard]] std::string json_string(const std::string& s);

}  // namespace tc::io
