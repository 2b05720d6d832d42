#include "tc/core/verify.hpp"

#include <fmt/format.h>

#include <cstring>
#include <utility>

namespace tc {

InternalError::InternalError(std::string file, int line, const std::string& what)
    : std::logic_error(what), file_(std::move(file)), line_(line) {}

void verify_failed(const char* condition, const char* file, int line, std::string_view message) {
  // The source file relative to the project (src/tc/…, tests/…): not the build machine's
  // directories, as check_petsc names it.
  const char* project = std::strstr(file, "src/tc/");
  if (!project) project = std::strstr(file, "tests/");
  const std::string where = project ? project : file;
  throw InternalError(where, line,
                      fmt::format("internal error at {}:{}: {} does not hold: {} (a defect of "
                                  "thermocontact, not of the case)",
                                  where, line, condition, message));
}

}  // namespace tc
