#pragma once
// Private to the io layer: `--set KEY=VALUE` on the parsed case (case-format.md, "Overrides"),
// and the case's content as a restart compares it (its identity: every key and value, without
// comments, layout or the keys a restart may change).
#include <toml++/toml.h>

#include <set>
#include <span>
#include <string>
#include <vector>

#include "tc/core/error.hpp"

namespace tc::io::detail {

/// One `--set KEY=VALUE`: the key in the notation of the reader's messages
/// (`bodies[0].material`; `bodies.0.material` is read as that), the value as given.
struct Override {
  std::string spec;  // as given on the command line
  std::string key;   // normalised: `a.b[0].c`
};

/// Puts every override into `root` (VALUE parsed as a TOML value; a bare word that is not one,
/// e.g. `steel`, is the string), creating the tables on its path that are missing. Returns the
/// overrides with their normalised keys; throws InputError naming `--set KEY=VALUE` when a key
/// cannot be set (empty, an index out of range, a path through a value that is not a table).
std::vector<Override> apply_overrides(toml::table& root, std::span<const std::string> specs);

/// `issue` (of the validation of the overridden table) reattributed to the override it comes
/// from, when its key is the override's or below it (file = "--set KEY=VALUE", no line).
void attribute_issues(std::vector<InputIssue>& issues, std::span<const Override> overrides);

/// The keys a restart may change (case-format.md, "Restart"): they do not enter the identity.
[[nodiscard]] bool restart_may_change(const std::string& key);

/// The case's content, one `key = value` line per leaf value in key order (numbers to 17
/// digits, integers as reals: `end = 1` and `end = 1.0` are one value), overridden keys marked
/// ` (--set)`, without the keys a restart may change. Comments, layout, table style and the
/// order in the file do not enter it.
[[nodiscard]] std::string case_content(const toml::table& root,
                                       std::span<const Override> overrides);

/// The first difference between two case_content texts: "KEY: VALUE in the checkpoint's run,
/// VALUE now" (a key absent on one side is said so); "" when they are equal.
[[nodiscard]] std::string content_difference(const std::string& was, const std::string& now);

}  // namespace tc::io::detail
