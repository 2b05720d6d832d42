#pragma once
// Restart files (case-format.md, "Restart"): OUTDIR/checkpoint.bin holds the
// physics::Checkpoint of a completed step, rewritten by CheckpointPolicy (at the first step,
// every checkpoint_every steps or checkpoint_seconds, at a stop and at the end) through a
// temporary file and a rename, so that whenever the run stops the file is a whole checkpoint.
//
// Layout (native byte order, for a restart on the same kind of machine): the magic
// "TCCHKPT\0", format version (u32), FNV-1a hash of the case's content and its mesh files' bytes
// (u64), the content (Problem::content: u64 length, bytes; it names the key that changed), τ (f64),
// dimension and number of bodies (i32), n_u and n_θ of every body (i64), the step (i32);
// then the checkpoint's vectors (u64 length, values) and scalars; last an FNV-1a hash of all
// the bytes before it, so that a damaged file is refused instead of read.
#include <cstdint>
#include <filesystem>
#include <string>

#include "tc/core/error.hpp"
#include "tc/run/simulation.hpp"

namespace tc::io {

/// A checkpoint that cannot be used with this case: missing, damaged, or written for another
/// case. Invalid input: exit code 2.
class CheckpointError : public Error {
 public:
  using Error::Error;
};

// 2: + warm-start tangents, compliance records; 3: + the combined contact dual's warm start
// (gluing and Dirichlet λ, μ) and SMALBE's outer iterations; 4: + Σ_k w_k‖λ_τ,k‖ of the last step;
// 5: + the heat lost through film and radiation boundaries (heat_film, heat_radiation); 6: per
// contact pair its multipliers' nodes, tangents and ledger, compliance records per contact body;
// 7: + the interface heat solver's compliance record, the case's content after its hash;
// 8: + per contact pair the heat through its gap conductance
inline constexpr std::uint32_t checkpoint_version = 8;

/// The file name of the checkpoint in an output directory.
[[nodiscard]] std::filesystem::path checkpoint_file(const std::filesystem::path& directory);

/// FNV-1a (64 bit) of a file's bytes (0 when it cannot be read).
[[nodiscard]] std::uint64_t file_hash(const std::filesystem::path& file);
/// What a checkpoint belongs to: the case's content (Problem::content: its keys and values after
/// the --set overrides, without those a restart may change) and the bytes of every mesh file
/// it reads (a restart after a .msh file changed would continue on another mesh).
[[nodiscard]] std::uint64_t input_hash(const physics::Problem& problem);

/// The checkpoint of `sim`'s current step as bytes (header, data, checksum).
[[nodiscard]] std::string encode_checkpoint(const physics::Simulation& sim,
                                            std::uint64_t case_hash);
/// Reads bytes written by encode_checkpoint for the problem of `sim`; throws CheckpointError
/// naming `where` when they are damaged or were written for a different case.
[[nodiscard]] physics::Checkpoint decode_checkpoint(const std::string& bytes,
                                                    const physics::Simulation& sim,
                                                    std::uint64_t case_hash,
                                                    const std::string& where);

/// Writes `sim`'s checkpoint to `file` atomically (temporary file, then rename).
void write_checkpoint(const std::filesystem::path& file, const physics::Simulation& sim,
                      std::uint64_t case_hash);
/// Reads and checks a checkpoint file for `sim`'s problem (CheckpointError if unusable).
[[nodiscard]] physics::Checkpoint read_checkpoint(const std::filesystem::path& file,
                                                  const physics::Simulation& sim,
                                                  std::uint64_t case_hash);

/// Refuses (CheckpointError) a history.csv or result.pvd in a restart's directory that is not a
/// regular file: the restart reads them line by line.
void check_restart_outputs(const std::filesystem::path& directory);

/// Refuses (CheckpointError) a restart whose history.csv cannot be continued from `sim`'s
/// restored step k without a gap: missing, with another header, or without a row for each of
/// the steps 0 … k−1 in order (cut short, or a newer checkpoint copied in: the restart wrote
/// steps 0–9 then 40; issue 42, D3 and D11). Rows from step k on are written again.
void check_restart_history(const std::filesystem::path& directory, const physics::Simulation& sim);

/// When a checkpoint is written ([output] checkpoint_every, checkpoint_seconds;
/// docs/case-format.md): after a step once `every` steps (0: not by count) or `seconds` of
/// wall time (0: not by time) have passed since the last one, the time never less than
/// cost_factor times the last checkpoint's own cost (so that it stays within 1/cost_factor of
/// the run); and always at the first step, after a stop signal and at the end (CheckpointWriter).
struct CheckpointPolicy {
  int every = 0;
  double seconds = 10.0;
  static constexpr double cost_factor = 50.0;
  [[nodiscard]] static CheckpointPolicy of(const physics::OutputSettings& output);
  /// Whether a checkpoint is due `steps` steps and `seconds` after the last, which took `cost`.
  [[nodiscard]] bool due(int steps, double seconds, double cost) const;
};

/// Writes the checkpoint by its policy (MPI rank 0 only; every rank holds every body). Put it
/// after the OutputWriter: a checkpoint then never runs ahead of history.csv. A restart from a
/// checkpoint older than the last history row re-does the steps after it, and the OutputWriter
/// cuts history.csv back to the checkpoint's step (OutputWriter::resume): the rows come out
/// the same, bit for bit.
class CheckpointWriter : public physics::Observer {
 public:
  CheckpointWriter(std::filesystem::path directory, std::uint64_t case_hash,
                   CheckpointPolicy policy = {1, 0.0});
  void step(const physics::Simulation& sim) override;
  void finish(const physics::Simulation& sim, const physics::RunStatus& status) override;
  /// The step of the last checkpoint written (−1: none yet).
  [[nodiscard]] int written_step() const { return written_step_; }

 private:
  void write(const physics::Simulation& sim);
  std::filesystem::path file_;
  std::uint64_t case_hash_;
  CheckpointPolicy policy_;
  bool root_;
  int written_step_ = -1;
  int seen_step_ = -1;  // the last step whose output was whole (step() is called after it)
  double last_time_ = 0, last_cost_ = 0;
};

}  // namespace tc::io
