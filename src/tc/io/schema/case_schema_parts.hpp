#pragma once
// What the parts of the schema (case_schema.cpp, case_schema_output.cpp) share: the ranges with
// the words of their messages, and the sections the other file declares.
#include <limits>
#include <span>
#include <string_view>

#include "tc/io/schema/case_schema.hpp"

namespace tc::io::schema {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Ranges, with the words of the messages ("found 0.0, expected a time step > 0").
constexpr Range above_zero(std::string_view words) {
  return {0, kInf, false, false, words};
}
constexpr Range from_zero(std::string_view words) {
  return {0, kInf, true, false, words};
}

/// The keys of [output] and of each [[probe]] (case_schema_output.cpp).
[[nodiscard]] std::span<const Key> output_keys();
[[nodiscard]] std::span<const Key> probe_keys();
/// The keys of [stability] (case_schema_output.cpp).
[[nodiscard]] std::span<const Key> stability_keys();

}  // namespace tc::io::schema
