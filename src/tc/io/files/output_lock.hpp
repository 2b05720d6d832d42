#pragma once
// The lock of an output directory (issue 20, docs/robustness.md). Two runs writing into one
// directory interleave their history.csv rows and race on checkpoint.bin.tmp: one of them
// died on the rename, the other reported success over a mixed history. A run therefore holds
// an exclusive flock() on the directory itself (issue 42: one on the file DIR/.lock was
// defeated by deleting the file), from before it writes anything until it exits; DIR/.lock
// holds its pid for the message of a run refused. The kernel drops the lock when the process
// dies, however it dies, so nothing a killed run leaves behind blocks the next run.
#include <filesystem>

#include "tc/core/error.hpp"

namespace tc::io {

/// The output directory cannot be used by this run (locked by another run, holding an earlier
/// run's output, a system directory): invalid input, exit code 2.
class OutputInUse : public Error {
 public:
  using Error::Error;
};

/// What a run does with the output of an earlier run found in its directory (history.csv,
/// summary.json, checkpoint.bin, result.pvd, the .vtu/.pvtu pieces): a --restart continues it;
/// a new run refuses it (OutputInUse: its history and checkpoint would be overwritten and its
/// stale pieces left lying beside the new ones) unless told to replace it (--force), which
/// removes those files first.
enum class EarlierRun { keep, refuse, replace };

/// Holds the lock of an output directory for its lifetime. Only MPI rank 0 locks (the
/// directory may be shared by ranks on several hosts); every rank learns the outcome.
class OutputLock {
 public:
  /// Locks `directory`, creating it if `create` (a new run's --output); a directory that does
  /// not exist and is not to be created (a --restart's, refused later for its missing
  /// checkpoint) is left alone and nothing is locked. Collective on PETSC_COMM_WORLD: every
  /// rank throws OutputInUse ("output directory D is in use by pid N") when another process
  /// holds the lock, or Error when the directory or the lock file cannot be created.
  OutputLock(const std::filesystem::path& directory, bool create,
             EarlierRun earlier = EarlierRun::keep);
  ~OutputLock();
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  /// The lock file of an output directory.
  [[nodiscard]] static std::filesystem::path file(const std::filesystem::path& directory);

 private:
  int fd_ = -1;            // DIR/.lock
  int directory_fd_ = -1;  // DIR, locked
};

}  // namespace tc::io
