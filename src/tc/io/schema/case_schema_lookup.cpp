// Look-ups in the case schema (case_schema.hpp): a section by its path, a key by its name, and
// the dotted name the messages and docs/case-format.md print; the data is in case_schema.cpp.
#include <fmt/format.h>

#include <stdexcept>
#include <string>

#include "tc/io/schema/case_schema.hpp"

namespace tc::io::schema {

const Section& section(std::string_view path) {
  for (const auto& s : sections())
    if (s.path == path) return s;
  throw std::logic_error(fmt::format("case schema: no section \"{}\"", path));
}

const Key& key(const Section& s, std::string_view name) {
  for (const auto& k : s.keys)
    if (k.name == name) return k;
  throw std::logic_error(fmt::format("case schema: no key \"{}\" in \"{}\"", name, s.path));
}

std::string full_name(const Section& s, const Key& k) {
  return s.path.empty() ? std::string(k.name) : fmt::format("{}.{}", s.path, k.name);
}

}  // namespace tc::io::schema
