#include "tc/io/files/files.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <vector>

#include "tc/core/error.hpp"
#include "tc/core/verify.hpp"

namespace tc::io {

namespace {

[[noreturn]] void fail(const char* what, const std::filesystem::path& file, int err) {
  throw OutputError(fmt::format("cannot {} {}: {}", what, printable(file), std::strerror(err)));
}

/// write() until all of `bytes` is out; the errno of the failure, or 0. A short write is
/// retried, so a full disk shows as ENOSPC (or EFBIG beyond a file-size limit).
int write_all(int fd, std::string_view bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const auto n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno;
    if (n == 0) return EIO;
    done += static_cast<size_t>(n);
  }
  return 0;
}

}  // namespace

namespace {

struct Pin {
  std::string key;  // the directory, as the parent_path() of the files written into it
  int fd;
};
std::vector<Pin>& pins() {
  static std::vector<Pin> list;
  return list;
}

std::string key_of(const std::filesystem::path& directory) {
  return (directory / "x").parent_path().lexically_normal().string();
}

/// Where `file` is: the descriptor of its pinned directory and its name there, or the
/// current directory's and the path itself.
struct Place {
  int dir;
  std::string name;
};
Place place(const std::filesystem::path& file) {
  const auto key = file.parent_path().lexically_normal().string();
  for (const auto& p : pins())
    if (p.key == key) return {p.fd, file.filename().string()};
  return {AT_FDCWD, file.string()};
}

/// A new file at `file`, open for writing: whatever had the name is unlinked first (a stale
/// temporary file of a killed run, a planted link), and O_EXCL | O_NOFOLLOW refuse whatever
/// appears there in between instead of following it.
int create_new(const std::filesystem::path& file, int flags) {
  // Its failure (nothing there, a directory, a read-only file system) shows in the open.
  const auto at = place(file);
  (void)::unlinkat(at.dir, at.name.c_str(), 0);
  const int fd = ::openat(at.dir, at.name.c_str(),
                          O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC | flags, 0644);
  if (fd < 0) fail("create", file, errno);
  return fd;
}

/// Writes `bytes` to the new file `fd` of `file`; on failure closes and removes it and throws.
void fill(int fd, const std::filesystem::path& file, std::string_view bytes, bool close) {
  int err = write_all(fd, bytes);
  // close() reports the errors of writes it completes (NFS, some quota systems).
  if (close && ::close(fd) != 0 && err == 0) err = errno;
  if (err == 0) return;
  if (!close) ::close(fd);
  const auto at = place(file);
  ::unlinkat(at.dir, at.name.c_str(), 0);  // a partial file must not be mistaken for a written one
  fail("write", file, err);
}

void rename_over(const std::filesystem::path& tmp, const std::filesystem::path& file) {
  const auto from = place(tmp), to = place(file);
  if (::renameat(from.dir, from.name.c_str(), to.dir, to.name.c_str()) == 0) return;
  const int err = errno;
  ::unlinkat(from.dir, from.name.c_str(), 0);
  fail("replace", file, err);
}

std::filesystem::path temporary(const std::filesystem::path& file) {
  return std::filesystem::path(file.string() + ".tmp");
}

}  // namespace

StreamedFile::StreamedFile(const std::filesystem::path& file)
    : file_(file), fd_(create_new(file, 0)) {}

StreamedFile::~StreamedFile() {
  if (fd_ >= 0) remove();
}

void StreamedFile::remove() {
  ::close(fd_);
  fd_ = -1;
  const auto at = place(file_);
  ::unlinkat(at.dir, at.name.c_str(), 0);  // a partial file must not be mistaken for a written one
}

void StreamedFile::flush() {
  TC_VERIFY(fd_ >= 0, "StreamedFile written after it was finished or failed");
  const int err = write_all(fd_, {buffer_.data(), buffer_.size()});
  buffer_.clear();
  if (err == 0) return;
  remove();
  fail("write", file_, err);
}

void StreamedFile::finish() {
  flush();
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) == 0) return;  // close() reports the errors of writes it completes
  const int err = errno;
  const auto at = place(file_);
  ::unlinkat(at.dir, at.name.c_str(), 0);
  fail("write", file_, err);
}

PinnedDirectory::PinnedDirectory(const std::filesystem::path& directory)
    : key_(key_of(directory)), fd_(::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {
  if (fd_ < 0) fail("open the directory", directory, errno);
  pins().push_back({key_, fd_});
}

PinnedDirectory::~PinnedDirectory() {
  auto& list = pins();
  for (auto it = list.begin(); it != list.end(); ++it)
    if (it->fd == fd_) {
      list.erase(it);
      break;
    }
  ::close(fd_);
}

void write_file(const std::filesystem::path& file, std::string_view bytes) {
  fill(create_new(file, 0), file, bytes, true);
}

void write_file(const std::filesystem::path& file, std::initializer_list<std::string_view> parts) {
  const int fd = create_new(file, 0);
  size_t left = parts.size();
  for (const auto part : parts) fill(fd, file, part, --left == 0);
  if (parts.size() == 0) fill(fd, file, {}, true);
}

void replace_file(const std::filesystem::path& file, std::string_view bytes) {
  const auto tmp = temporary(file);
  write_file(tmp, bytes);
  rename_over(tmp, file);
}

int replace_file_for_append(const std::filesystem::path& file, std::string_view bytes) {
  const auto tmp = temporary(file);
  const int fd = create_new(tmp, O_APPEND);
  fill(fd, tmp, bytes, false);
  try {
    rename_over(tmp, file);
  } catch (...) {
    ::close(fd);
    throw;
  }
  return fd;
}

void remove_file(const std::filesystem::path& file) {
  const auto at = place(file);
  (void)::unlinkat(at.dir, at.name.c_str(), 0);
}

void rename_file(const std::filesystem::path& from, const std::filesystem::path& to) {
  rename_over(from, to);
}

std::string printable(std::string_view s) {
  std::string out;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    out += u < 0x20 || u == 0x7F ? fmt::format("\\x{:02X}", u) : std::string(1, c);
  }
  return out;
}

void append_record(int fd, const std::filesystem::path& file, std::string_view bytes) {
  const off_t before = ::lseek(fd, 0, SEEK_END);
  const int err = write_all(fd, bytes);
  if (err == 0) return;
  // Part of the record may be on disk (a write cut short by the limit): cut it off.
  if (before >= 0 && ::ftruncate(fd, before) != 0) {
    // nothing more to do: the write error is what the user needs to hear of
  }
  fail("write", file, err);
}

std::string not_a_file(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  using std::filesystem::file_type;
  if (status.type() == file_type::regular) return "";
  if (status.type() == file_type::not_found) return "does not exist";
  if (status.type() == file_type::directory) return "is a directory";
  if (ec) return fmt::format("cannot be examined ({})", ec.message());
  return "is not a regular file (a device, pipe or socket)";
}

}  // namespace tc::io
