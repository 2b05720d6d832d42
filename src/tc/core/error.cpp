#include "tc/core/error.hpp"

#include <fmt/format.h>

namespace tc {

std::string InputIssue::str() const {
  // line < 0: not from a file (a --set KEY=VALUE of the command line)
  if (line < 0) return fmt::format("{}: {}: {}", file, key, message);
  return fmt::format("{}:{}: {}: {}", file, line, key, message);
}

namespace {
std::string join_issues(const std::vector<InputIssue>& issues) {
  std::string out;
  for (const auto& i : issues) {
    if (!out.empty()) out += '\n';
    out += i.str();
  }
  return out;
}
}  // namespace

InputError::InputError(std::vector<InputIssue> issues)
    : Error(join_issues(issues)), issues_(std::move(issues)) {}

NumericalError::NumericalError(const std::string& what, int step, int iteration, double residual)
    : Error(fmt::format("{} (step {}, iteration {}, residual {:.3e})", what, step, iteration,
                        residual)),
      step_(step),
      iteration_(iteration),
      residual_(residual) {}

NumericalError NumericalError::preformatted(const std::string& what, int step, int iteration,
                                            double residual) {
  return {Preformatted{}, what, step, iteration, residual};
}

bool reported_here(const std::exception& e, int rank) {
  return rank == 0 || dynamic_cast<const Collective*>(&e) == nullptr;
}

}  // namespace tc
