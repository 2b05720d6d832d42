#pragma once
// Writing the files of a run so that a failed write (a full disk, a file-size limit, an I/O
// error) is an OutputError naming the file and the system's reason, never an exception out
// of a destructor (fmt::ostream flushed in its destructor and aborted the run: issue 20, #2),
// and leaves no partial file behind: whatever was listed or renamed before stays whole.
#include <fmt/format.h>

#include <filesystem>
#include <initializer_list>
#include <iterator>
#include <string>
#include <string_view>
#include <utility>

namespace tc::io {

/// The text of a file, formatted in memory and then written whole by write_file or
/// replace_file.
class TextBuffer {
 public:
  template <class... T>
  void print(fmt::format_string<T...> format, T&&... args) {
    fmt::format_to(std::back_inserter(buffer_), format, std::forward<T>(args)...);
  }
  [[nodiscard]] std::string_view view() const { return {buffer_.data(), buffer_.size()}; }

 private:
  fmt::memory_buffer buffer_;
};

/// A new file written while it is formatted, a chunk at a time: the ASCII frame of a 10⁶-dof
/// body is half a GiB of text, and formatting it whole put that on the run's memory peak
/// (bench/RESULTS.md, "Issue 39's 10⁶-dof case"). The rules of write_file hold: created with
/// O_EXCL | O_NOFOLLOW, a failed write removes the file and throws OutputError, and a file not
/// finished (an exception while formatting) is removed by the destructor.
class StreamedFile {
 public:
  explicit StreamedFile(const std::filesystem::path& file);
  ~StreamedFile();
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;

  template <class... T>
  void print(fmt::format_string<T...> format, T&&... args) {
    fmt::format_to(std::back_inserter(buffer_), format, std::forward<T>(args)...);
    if (buffer_.size() >= kChunk) flush();
  }
  /// Writes what is left and closes the file; throws OutputError (and removes it) on failure.
  void finish();

 private:
  static constexpr size_t kChunk = size_t{1} << 20;  // few system calls, a negligible buffer
  void flush();
  void remove();
  std::filesystem::path file_;
  int fd_;
  fmt::memory_buffer buffer_;
};

/// While it lives, every file written by the functions below into `directory` is created,
/// renamed and removed relative to a descriptor of the directory opened here (openat,
/// renameat): should the path come to name another directory (`rm -rf DIR` and a new run
/// into DIR, a link put in the place of DIR), the writes still go to this one, or fail if it
/// was deleted, and never into the other (issue 42, D2). Throws OutputError if it cannot be
/// opened.
class PinnedDirectory {
 public:
  explicit PinnedDirectory(const std::filesystem::path& directory);
  ~PinnedDirectory();
  PinnedDirectory(const PinnedDirectory&) = delete;
  PinnedDirectory& operator=(const PinnedDirectory&) = delete;
  [[nodiscard]] int fd() const { return fd_; }

 private:
  std::string key_;
  int fd_ = -1;
};

/// Writes `bytes` to `file`, a new file, and closes it; on failure removes it and throws
/// OutputError. Whatever had the name before (a stale file, a symbolic or hard link planted
/// there) is unlinked first and the file is created with O_EXCL | O_NOFOLLOW: nothing is ever
/// written through a link to a file outside the output directory (issue 42, D1).
void write_file(const std::filesystem::path& file, std::string_view bytes);
/// The same with the bytes given in parts, written one after the other.
void write_file(const std::filesystem::path& file, std::initializer_list<std::string_view> parts);

/// write_file to `file`.tmp, then renames it over `file`: a reader sees the old file or the
/// new one, whole. The rename replaces a link named `file` itself, never its target.
void replace_file(const std::filesystem::path& file, std::string_view bytes);

/// replace_file that keeps the new file open for appending: the descriptor (the caller closes
/// it) refers to the file written, not to whatever the name may later point to.
[[nodiscard]] int replace_file_for_append(const std::filesystem::path& file,
                                          std::string_view bytes);

/// For files that a library writes by their path (HDF5 through MPI-IO): removes `file`
/// (through its pinned directory, as write_file does, and whatever it is: a stale file, a
/// link), ignoring its absence or a failure, which the library's exclusive creation reports.
void remove_file(const std::filesystem::path& file);
/// Renames `from` over `to` (the rename replaces a link named `to` itself, never its target);
/// on failure removes `from` and throws OutputError.
void rename_file(const std::filesystem::path& from, const std::filesystem::path& to);

/// `s` with control bytes (and DEL) as \xNN, for paths and names printed on a terminal: an
/// output name with a newline or escape codes was echoed raw (issue 42).
[[nodiscard]] std::string printable(std::string_view s);
[[nodiscard]] inline std::string printable(const std::string& s) {
  return printable(std::string_view(s));
}
[[nodiscard]] inline std::string printable(const char* s) {
  return printable(std::string_view(s));
}
[[nodiscard]] inline std::string printable(const std::filesystem::path& p) {
  return printable(std::string_view(p.native()));
}

/// What keeps `path` from being read as a file ("does not exist", "is a directory", ...), or ""
/// when it is a regular file (after symbolic links). "does not exist" was said of all of them.
[[nodiscard]] std::string not_a_file(const std::filesystem::path& path);

/// Appends one record to the O_APPEND descriptor `fd` of `file`; on failure cuts the file
/// back to its size before, so no partial record stays, and throws OutputError.
void append_record(int fd, const std::filesystem::path& file, std::string_view bytes);

}  // namespace tc::io
