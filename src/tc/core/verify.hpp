#pragma once
// Always-on checks of internal invariants (TC_VERIFY), apart from the Release-only asserts of
// hot inner loops. A broken invariant is a defect of thermocontact, not of the user's input or
// of the numerics, so it has its own type, outside tc::Error's user-facing family: the
// handlers that map errors to exit codes 1 and 2 do not take it for a bad case or a failed
// solve, and the message names the source line to report.
#include <stdexcept>
#include <string>
#include <string_view>

namespace tc {

/// An internal invariant that does not hold, at `file`:`line` (relative to the project).
class InternalError : public std::logic_error {
 public:
  InternalError(std::string file, int line, const std::string& what);
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] int line() const { return line_; }

 private:
  std::string file_;
  int line_;
};

/// Throws the InternalError of a failed TC_VERIFY (out of line: the check's cost at the call
/// is one predictable branch).
[[noreturn]] void verify_failed(const char* condition, const char* file, int line,
                                std::string_view message);

}  // namespace tc

/// Checks `cond` in every build type; if it is false, throws tc::InternalError naming the file,
/// the line, the condition and `msg` (a string: why the invariant matters to the caller).
#define TC_VERIFY(cond, msg)                                 \
  do {                                                       \
    if (!(cond)) [[unlikely]]                                \
      ::tc::verify_failed(#cond, __FILE__, __LINE__, (msg)); \
  } while (false)
