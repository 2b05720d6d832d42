// The words for a key's type and range in docs/case-format.md's key table (and the messages),
// apart from the schema's data in case_schema.cpp.
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <string>
#include <vector>

#include "tc/io/schema/case_schema.hpp"

namespace tc::io::schema {

using T = Type;

std::string type_words(const Key& k) {
  const auto range = [&](std::string_view what) {
    return k.range.words.empty() ? std::string(what) : fmt::format("{}: {}", what, k.range.words);
  };
  switch (k.type) {
    case T::number:
      return range("number");
    case T::integer:
      return k.max > 0 ? fmt::format("integer {} to {}", k.min, k.max)
                       : fmt::format("integer ≥ {}", k.min);
    case T::boolean:
      return "true or false";
    case T::string:
      return "string";
    case T::name:
      return "name";
    case T::choice: {
      std::vector<std::string> quoted;
      for (const auto c : k.choices) quoted.push_back(fmt::format("\"{}\"", c));
      return fmt::format("{}", fmt::join(quoted, " or "));
    }
    case T::time_table:
      return range("number or time table");
    case T::temperature_table:
      return range("number or table in θ");
    case T::gap_table:
      return range("number or table in g");
    case T::vector:
      return "array of numbers";
    case T::numbers:
      return k.range.words.empty() ? std::string("array of numbers")
                                   : fmt::format("array of numbers, each {}", k.range.words);
    case T::counts:
      return "array of integers ≥ 1";
    case T::components:
      return "array of components";
    case T::subdomains:
      return "integer ≥ 1 or \"auto\"";
    case T::dimension:
      return "2 or 3";
    case T::table:
      return "table";
    case T::tables:
      return "array of tables";
    case T::named_tables:
      return "tables by name";
    case T::contact_tables:
      return "table or array of tables";
  }
  return "";
}

}  // namespace tc::io::schema
