#include "tc/io/output_lock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <regex>
#include <string>
#include <vector>

#include "tc/core/petsc.hpp"

namespace tc::io {

namespace {

enum Outcome : int { locked = 0, in_use = 1, failed = 2 };

/// The pid written in a lock file, or "" (its holder may not have written it yet).
std::string holder(int fd) {
  char buf[32] = {};
  const auto n = ::pread(fd, buf, sizeof buf - 1, 0);
  std::string pid(buf, n > 0 ? static_cast<size_t>(n) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid;
}

int flock_nonblocking(int fd) {
  int rc = 0;
  do rc = ::flock(fd, LOCK_EX | LOCK_NB);
  while (rc != 0 && errno == EINTR);
  return rc;
}

/// Rank 0's part: the descriptor that holds the lock (-1 when there is nothing to lock).
int take_lock(const std::filesystem::path& directory, bool create) {
  std::error_code ec;
  if (!create && !std::filesystem::is_directory(directory, ec)) return -1;
  std::filesystem::create_directories(directory, ec);
  if (ec)
    throw Error(
        fmt::format("cannot create output directory {}: {}", directory.string(), ec.message()));
  const auto path = OutputLock::file(directory);
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw Error(
        fmt::format("cannot create the lock file {}: {}", path.string(), std::strerror(errno)));
  if (flock_nonblocking(fd) != 0) {
    const int err = errno;
    const auto pid = err == EWOULDBLOCK ? holder(fd) : std::string();
    ::close(fd);
    if (err != EWOULDBLOCK)
      throw Error(fmt::format("cannot lock {}: {}", path.string(), std::strerror(err)));
    throw OutputInUse(fmt::format(
        "output directory {} is in use by {} (another run writes into it: wait for it to end "
        "or choose another --output)",
        directory.string(), pid.empty() ? std::string("another process") : "pid " + pid));
  }
  // The pid is for the message of a run refused above; the lock itself is the flock, so a
  // failure to write it (a full disk) does not matter here and shows in the run's output.
  const auto text = fmt::format("{}\n", ::getpid());
  if (::ftruncate(fd, 0) == 0) {
    [[maybe_unused]] const auto n = ::pwrite(fd, text.data(), text.size(), 0);
  }
  return fd;
}

/// The files of a run in an output directory: what OutputWriter and CheckpointWriter write
/// (the pieces are <body>_<step>.vtu, <body>_<step>.pvtu and <body>_<step>_<rank>.vtu).
std::vector<std::filesystem::path> run_files(const std::filesystem::path& directory) {
  static const std::regex piece(R"(.+_[0-9]{6}(_[0-9]+)?\.p?vtu)");
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(directory, ec)) {
    const auto name = e.path().filename().string();
    if (name == "history.csv" || name == "summary.json" || name == "summary.stopped.json" ||
        name == "result.pvd" || name == "checkpoint.bin" || name == "checkpoint.bin.tmp" ||
        std::regex_match(name, piece))
      out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// Applies `earlier` to the run found in a locked directory (rank 0).
void handle_earlier_run(const std::filesystem::path& directory, EarlierRun earlier) {
  if (earlier == EarlierRun::keep) return;
  const auto files = run_files(directory);
  if (files.empty()) return;
  if (earlier == EarlierRun::refuse)
    throw OutputInUse(fmt::format(
        "output directory {} holds the output of an earlier run ({} files, {} first), which "
        "this run would overwrite and leave mixed with its own; expected an empty directory: "
        "--restart {} continues that run, --force replaces it",
        directory.string(), files.size(), files.front().filename().string(), directory.string()));
  for (const auto& f : files) {
    std::error_code ec;
    std::filesystem::remove(f, ec);
    if (ec)
      throw Error(fmt::format("cannot remove {} of the earlier run: {}", f.string(), ec.message()));
  }
}

/// Rank 0's outcome and message to every rank.
void share(int& outcome, std::string& message) {
  int header[2] = {outcome, static_cast<int>(message.size())};
  MPI_Bcast(header, 2, MPI_INT, 0, PETSC_COMM_WORLD);
  std::vector<char> text(static_cast<size_t>(header[1]) + 1, '\0');
  std::memcpy(text.data(), message.data(), std::min(message.size(), text.size() - 1));
  MPI_Bcast(text.data(), header[1], MPI_CHAR, 0, PETSC_COMM_WORLD);
  outcome = header[0];
  message = text.data();
}

}  // namespace

std::filesystem::path OutputLock::file(const std::filesystem::path& directory) {
  return directory / ".lock";
}

OutputLock::OutputLock(const std::filesystem::path& directory, bool create, EarlierRun earlier) {
  int outcome = locked;
  std::string message;
  if (core::PetscSession::rank() == 0) {
    try {
      fd_ = take_lock(directory, create);
      if (fd_ >= 0) handle_earlier_run(directory, earlier);
    } catch (const OutputInUse& e) {
      outcome = in_use, message = e.what();
    } catch (const std::exception& e) {
      outcome = failed, message = e.what();
    }
  }
  if (outcome != locked && fd_ >= 0) {  // refused after locking: no destructor will run
    ::close(fd_);
    fd_ = -1;
  }
  if (core::PetscSession::size() > 1) share(outcome, message);
  // Every rank throws the same error, reported once (by rank 0: core/collective.hpp).
  if (outcome == in_use) throw CollectiveError<OutputInUse>(OutputInUse(message));
  if (outcome == failed) throw CollectiveError<Error>(Error(message));
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Emptied while still held, so that the file left behind names no one; closing releases it.
  [[maybe_unused]] const int rc = ::ftruncate(fd_, 0);
  ::close(fd_);
}

}  // namespace tc::io
