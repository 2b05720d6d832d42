#pragma once
// Writing the files of a run so that a failed write (a full disk, a file-size limit, an I/O
// error) is an OutputError naming the file and the system's reason, never an exception out
// of a destructor (fmt::ostream flushed in its destructor and aborted the run: issue 20, #2),
// and leaves no partial file behind: whatever was listed or renamed before stays whole.
#include <fmt/format.h>

#include <filesystem>
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

/// Writes `bytes` to `file` (created or truncated) and closes it; on failure removes it and
/// throws OutputError.
void write_file(const std::filesystem::path& file, std::string_view bytes);

/// write_file to `file`.tmp, then renames it over `file`: a reader sees the old file or the
/// new one, whole.
void replace_file(const std::filesystem::path& file, std::string_view bytes);

/// What keeps `path` from being read as a file ("does not exist", "is a directory", ...), or ""
/// when it is a regular file (after symbolic links). "does not exist" was said of all of them.
[[nodiscard]] std::string not_a_file(const std::filesystem::path& path);

/// Appends one record to the O_APPEND descriptor `fd` of `file`; on failure cuts the file
/// back to its size before, so no partial record stays, and throws OutputError.
void append_record(int fd, const std::filesystem::path& file, std::string_view bytes);

}  // namespace tc::io
