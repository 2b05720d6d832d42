#include "tc/io/files/output_lock.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <regex>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "tc/core/numeric/petsc.hpp"
#include "tc/io/files/files.hpp"

namespace tc::io {

namespace {

enum Outcome : int { locked = 0, in_use = 1, failed = 2 };

/// The pid written in a lock file, or "" (its holder may not have written it yet, or the file
/// was deleted). Read without following a link: the file is ours, a link planted there is not.
std::string holder(const std::filesystem::path& directory) {
  const int fd =
      ::open(OutputLock::file(directory).c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return "";
  char buf[32] = {};
  const auto n = ::pread(fd, buf, sizeof buf - 1, 0);
  ::close(fd);
  std::string pid(buf, n > 0 ? static_cast<size_t>(n) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  if (pid.find_first_not_of("0123456789") != std::string::npos) return "";
  return pid;
}

int flock_nonblocking(int fd) {
  int rc = 0;
  do rc = ::flock(fd, LOCK_EX | LOCK_NB);
  while (rc != 0 && errno == EINTR);
  return rc;
}

/// Why `directory` may not hold a run's output, or "": the root directory and the system's
/// own directories. As root, `--output /` wrote .lock, history.csv and the fields into / (and
/// `--force` would remove files of those names there). Anything below them is the user's call
/// but for the kernel's pseudo file systems, where nothing a run writes belongs.
std::string system_directory(const std::filesystem::path& directory) {
  std::error_code ec;
  auto path = std::filesystem::weakly_canonical(std::filesystem::absolute(directory, ec), ec);
  if (ec) return "";  // examined again when it is created or opened
  if (!path.has_filename() && path != path.root_path()) path = path.parent_path();  // "/usr/"
  if (path == path.root_path()) return "the root directory";
  static const char* const whole[] = {"/bin",   "/boot", "/dev",  "/etc",  "/lib", "/lib32",
                                      "/lib64", "/proc", "/run",  "/sbin", "/sys", "/usr",
                                      "/var",   "/home", "/root", "/opt",  "/srv", "/tmp"};
  static const char* const trees[] = {"/dev", "/proc", "/sys"};
  for (const char* d : trees) {
    const auto rel = path.lexically_relative(d);
    if (!rel.empty() && *rel.begin() != "..") return fmt::format("a directory under {}", d);
  }
  for (const char* d : whole)
    if (path == std::filesystem::path(d)) return "a directory of the system";
  return "";
}

/// The lock of a directory. Taken on the directory itself, not on a file in it: a file can be
/// deleted (`rm DIR/.lock`) and a second run then locked a new one and was admitted (issue 42,
/// D2). Returns the directory's descriptor that holds it, or -1 where the file system does
/// not lock directories (flock on NFS is emulated by byte-range locks, which need a descriptor
/// open for writing): there the lock falls back to DIR/.lock alone.
int lock_directory(const std::filesystem::path& directory) {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0)
    throw Error(fmt::format("cannot open output directory {}: {}", printable(directory),
                            std::strerror(errno)));
  if (flock_nonblocking(fd) == 0) return fd;
  const int err = errno;
  ::close(fd);
  if (err == EWOULDBLOCK) {
    const auto pid = holder(directory);
    throw OutputInUse(fmt::format(
        "output directory {} is in use by {} (another run writes into it: wait for it to end "
        "or choose another --output)",
        printable(directory), pid.empty() ? std::string("another process") : "pid " + pid));
  }
  return -1;
}

/// Rank 0's part: the descriptors of the locked directory and of its .lock file, which holds
/// this process's pid for the message of a run refused (both -1 when there is nothing to lock).
std::pair<int, int> take_lock(const std::filesystem::path& directory, bool create) {
  std::error_code ec;
  if (!create && !std::filesystem::is_directory(directory, ec)) return {-1, -1};
  if (const auto why = system_directory(directory); !why.empty())
    throw OutputInUse(fmt::format(
        "output directory {}: found {}, expected a directory of the run's own (a run writes "
        "its history, fields and a lock file there)",
        printable(directory), why));
  std::filesystem::create_directories(directory, ec);
  if (ec)
    throw Error(
        fmt::format("cannot create output directory {}: {}", printable(directory), ec.message()));
  const int dir_fd = lock_directory(directory);
  const auto path = OutputLock::file(directory);
  // Never opened through a link: `ln -s victim DIR/.lock` truncated the victim (issue 42, D1).
  // Where the directory is locked, .lock is only the pid's record: made anew. Where it is not
  // (the fall-back), the flock on .lock is the lock, and deleting the file of a running run
  // is the limit that remains.
  const int at = dir_fd >= 0 ? dir_fd : AT_FDCWD;
  const auto name = dir_fd >= 0 ? path.filename().string() : path.string();
  if (dir_fd >= 0) (void)::unlinkat(at, name.c_str(), 0);
  const int fd = ::openat(at, name.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) {
    const int err = errno;
    if (dir_fd >= 0) ::close(dir_fd);
    throw Error(
        fmt::format("cannot create the lock file {}: {}", printable(path), std::strerror(err)));
  }
  if (dir_fd < 0 && flock_nonblocking(fd) != 0) {
    const int err = errno;
    ::close(fd);
    if (err != EWOULDBLOCK)
      throw Error(fmt::format("cannot lock {}: {}", printable(path), std::strerror(err)));
    const auto pid = holder(directory);
    throw OutputInUse(fmt::format(
        "output directory {} is in use by {} (another run writes into it: wait for it to end "
        "or choose another --output)",
        printable(directory), pid.empty() ? std::string("another process") : "pid " + pid));
  }
  // The pid is for the message of a run refused above; the lock itself is the flock, so a
  // failure to write it (a full disk) does not matter here and shows in the run's output.
  const auto text = fmt::format("{}\n", ::getpid());
  if (::ftruncate(fd, 0) == 0) {
    [[maybe_unused]] const auto n = ::pwrite(fd, text.data(), text.size(), 0);
  }
  return {dir_fd, fd};
}

/// The files of a run in an output directory: what OutputWriter and CheckpointWriter write
/// (the pieces are <body>_<step>.vtu, <body>_<step>.pvtu and <body>_<step>_<rank>.vtu; the
/// contact nodes' contact_<step>.csv).
std::vector<std::filesystem::path> run_files(const std::filesystem::path& directory) {
  static const std::regex piece(R"((.+_[0-9]{6}(_[0-9]+)?\.p?vtu)|(contact_[0-9]{6}\.csv))");
  std::vector<std::filesystem::path> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(directory, ec)) {
    const auto name = e.path().filename().string();
    if (name == "history.csv" || name == "probes.csv" || name == "summary.json" ||
        name == "summary.stopped.json" || name == "result.pvd" || name == "checkpoint.bin" ||
        name == "checkpoint.bin.tmp" || std::regex_match(name, piece))
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
        printable(directory), files.size(), printable(files.front().filename()),
        printable(directory)));
  for (const auto& f : files) {
    std::error_code ec;
    std::filesystem::remove(f, ec);
    if (ec)
      throw Error(
          fmt::format("cannot remove {} of the earlier run: {}", printable(f), ec.message()));
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
      std::tie(directory_fd_, fd_) = take_lock(directory, create);
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
  if (outcome != locked && directory_fd_ >= 0) {
    ::close(directory_fd_);
    directory_fd_ = -1;
  }
  if (core::PetscSession::size() > 1) share(outcome, message);
  // Every rank throws the same error, reported once (by rank 0: core/numeric/collective.hpp).
  if (outcome == in_use) throw CollectiveError<OutputInUse>(OutputInUse(message));
  if (outcome == failed) throw CollectiveError<Error>(Error(message));
}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  // Emptied while still held, so that the file left behind names no one; closing releases it.
  [[maybe_unused]] const int rc = ::ftruncate(fd_, 0);
  ::close(fd_);
  if (directory_fd_ >= 0) ::close(directory_fd_);
}

}  // namespace tc::io
