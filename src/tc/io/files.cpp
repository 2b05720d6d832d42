#include "tc/io/files.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "tc/core/error.hpp"

namespace tc::io {

namespace {

[[noreturn]] void fail(const char* what, const std::filesystem::path& file, int err) {
  throw OutputError(fmt::format("cannot {} {}: {}", what, file.string(), std::strerror(err)));
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

void write_file(const std::filesystem::path& file, std::string_view bytes) {
  const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("create", file, errno);
  int err = write_all(fd, bytes);
  // close() reports the errors of writes it completes (NFS, some quota systems).
  if (::close(fd) != 0 && err == 0) err = errno;
  if (err == 0) return;
  ::unlink(file.c_str());  // a partial file must not be mistaken for a written one
  fail("write", file, err);
}

void replace_file(const std::filesystem::path& file, std::string_view bytes) {
  const auto tmp = std::filesystem::path(file.string() + ".tmp");
  write_file(tmp, bytes);
  if (std::rename(tmp.c_str(), file.c_str()) != 0) {
    const int err = errno;
    ::unlink(tmp.c_str());
    fail("replace", file, err);
  }
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
