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

namespace {
/// How a NumericalError names its step: "step ?" when the thrower could not know it.
std::string step_text(int step) {
  if (step < 0) return "step ?";
  if (step == 0) return "set-up before step 1";
  return fmt::format("step {}", step);
}
}  // namespace

NumericalError::NumericalError(const std::string& what, int step, int iteration, double residual)
    : Error(fmt::format("{} ({}, iteration {}, residual {:.3e})", what, step_text(step), iteration,
                        residual)),
      step_(step),
      iteration_(iteration),
      residual_(residual) {}

NumericalError NumericalError::preformatted(const std::string& what, int step, int iteration,
                                            double residual) {
  return {Preformatted{}, what, step, iteration, residual};
}

NumericalError NumericalError::at_step(int step) const {
  if (step_ >= 0 || step < 0) return *this;
  // The text was formatted by the constructor above, here or on the rank that threw it
  // (collective.cpp sends what() as it is): its last "(step ?, " is the unknown step.
  std::string text = what();
  const auto unknown = fmt::format("({}, ", step_text(-1));
  if (const auto at = text.rfind(unknown); at != std::string::npos)
    text = fmt::format("{}({}, {}", text.substr(0, at), step_text(step),
                       text.substr(at + unknown.size()));
  return preformatted(text, step, iteration_, residual_);
}

void rethrow_at_step(const NumericalError& e, int step) {
  if (dynamic_cast<const Collective*>(&e) != nullptr)
    throw CollectiveError<NumericalError>(e.at_step(step));
  throw e.at_step(step);
}

bool reported_here(const std::exception& e, int rank) {
  return rank == 0 || dynamic_cast<const Collective*>(&e) == nullptr;
}

}  // namespace tc
