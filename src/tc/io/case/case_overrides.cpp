#include "tc/io/case/case_overrides.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <sstream>
#include <variant>

namespace tc::io::detail {

namespace {

using Segment = std::variant<std::string, size_t>;  // a table key or an array index

/// The segments of a key such as `bodies[0].material` or `bodies.0.material`; empty when the
/// key is malformed (an empty name, an unclosed or non-numeric index).
std::vector<Segment> parse_key(const std::string& key) {
  std::vector<Segment> out;
  size_t i = 0;
  const auto number = [](const std::string& s) {
    return !s.empty() && s.size() < 10 &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  while (i <= key.size()) {
    const size_t dot = std::min(key.find('.', i), key.size());
    std::string part = key.substr(i, dot - i);
    const size_t bracket = part.find('[');
    std::string name = part.substr(0, bracket);
    if (name.empty() && bracket != 0) return {};
    if (!name.empty()) {
      if (number(name))
        out.emplace_back(static_cast<size_t>(std::stoul(name)));
      else
        out.emplace_back(name);
    }
    for (size_t b = bracket; b != std::string::npos && b < part.size();) {
      const size_t close = part.find(']', b);
      if (part[b] != '[' || close == std::string::npos) return {};
      const std::string index = part.substr(b + 1, close - b - 1);
      if (!number(index)) return {};
      out.emplace_back(static_cast<size_t>(std::stoul(index)));
      b = close + 1;
    }
    if (name.empty() && bracket == 0 && out.empty()) return {};
    i = dot + 1;
  }
  return out;
}

std::string normalised(const std::vector<Segment>& segments) {
  std::string out;
  for (const auto& s : segments) {
    if (const auto* name = std::get_if<std::string>(&s))
      out += (out.empty() ? "" : ".") + *name;
    else
      out += fmt::format("[{}]", std::get<size_t>(s));
  }
  return out;
}

/// The value of `--set KEY=VALUE` as the member `v` of a table: VALUE as TOML (`0.5`,
/// `"steel"`, `[1, 0, 0]`, `{ slave = 1e-3, master = 1e-3 }`, `true`), or the bare word as a
/// string.
toml::table parse_value(const std::string& value, const std::string& spec) {
  try {
    auto t = toml::parse("v = " + value, "--set " + spec);
    if (t.size() == 1 && t.contains("v")) return t;
  } catch (const toml::parse_error&) {
  }
  toml::table t;
  t.insert("v", value);
  return t;
}

[[noreturn]] void refuse(const std::string& spec, const std::string& key, const std::string& why) {
  throw InputError({{"--set " + spec, -1, key.empty() ? "(key)" : key, why}});
}

std::string describe_node(const toml::node& n) {
  if (n.is_table()) return "a table";
  if (n.is_array()) return fmt::format("an array of {} entries", n.as_array()->size());
  if (n.is_string()) return "a string";
  if (n.is_boolean()) return "a boolean";
  return "a number";
}

}  // namespace

std::vector<Override> apply_overrides(toml::table& root, std::span<const std::string> specs) {
  std::vector<Override> out;
  for (const auto& spec : specs) {
    const size_t eq = spec.find('=');
    if (eq == std::string::npos)
      refuse(spec, "", "found no '=', expected --set KEY=VALUE (e.g. --set contact.friction=0.5)");
    const std::string key = spec.substr(0, eq), value = spec.substr(eq + 1);
    const auto segments = parse_key(key);
    if (segments.empty() || !std::holds_alternative<std::string>(segments.front()))
      refuse(spec, key,
             "found a key that is not a dotted path of names and [indices], expected e.g. "
             "contact.friction, time.end or bodies[0].material");
    Override o{spec, normalised(segments)};
    toml::node* at = &root;
    std::string path;
    for (size_t k = 0; k < segments.size(); ++k) {
      const bool last = k + 1 == segments.size();
      const auto& s = segments[k];
      const std::string here =
          path.empty() ? normalised({s})
                       : path + (std::holds_alternative<size_t>(s) ? "" : ".") + normalised({s});
      if (const auto* name = std::get_if<std::string>(&s)) {
        auto* table = at->as_table();
        if (!table)
          refuse(spec, o.key,
                 fmt::format("{} is {}, not a table: it has no key '{}'", path, describe_node(*at),
                             *name));
        if (last) {
          table->insert_or_assign(*name, *parse_value(value, spec).get("v"));
          break;
        }
        if (!table->contains(*name)) table->insert(*name, toml::table{});
        at = table->get(*name);
      } else {
        const size_t index = std::get<size_t>(s);
        auto* array = at->as_array();
        if (!array)
          refuse(spec, o.key,
                 fmt::format("{} is {}, not an array: [{}] indexes nothing (indices count from 0 "
                             "in arrays such as bodies and boundary)",
                             path, describe_node(*at), index));
        if (index >= array->size())
          refuse(spec, o.key,
                 fmt::format("{} has {} entries, so no [{}] (indices count from 0; --set changes "
                             "entries, it does not add them)",
                             path, array->size(), index));
        if (last) {
          array->replace(array->cbegin() + static_cast<std::ptrdiff_t>(index),
                         *parse_value(value, spec).get("v"));
          break;
        }
        at = array->get(index);
      }
      path = here;
    }
    out.push_back(std::move(o));
  }
  return out;
}

void attribute_issues(std::vector<InputIssue>& issues, std::span<const Override> overrides) {
  for (auto& issue : issues)
    for (const auto& o : overrides) {
      const auto& k = issue.key;
      const bool below = k == o.key || k.rfind(o.key + ".", 0) == 0 || k.rfind(o.key + "[", 0) == 0;
      // a table the override made: an unknown key there is the override's
      const bool above = (o.key.rfind(k + ".", 0) == 0 || o.key.rfind(k + "[", 0) == 0) &&
                         issue.message.find("unknown") != std::string::npos;
      if (!below && !above) continue;
      issue.file = "--set " + o.spec;
      issue.line = -1;
      break;
    }
}

bool restart_may_change(const std::string& key) {
  // end: a restart may continue a run beyond its end (or stop it earlier, not before the
  // checkpoint); the output settings and the title change what is written, not the results.
  return key == "time.end" || key == "title" || key == "output" || key.rfind("output.", 0) == 0;
}

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\')
      out += std::string("\\") + c;
    else if (u < 0x20 || u == 0x7F)
      out += fmt::format("\\u{:04X}", u);
    else
      out += c;
  }
  return out + "\"";
}

void flatten(const toml::node& n, const std::string& key, std::vector<std::string>& lines) {
  if (const auto* t = n.as_table()) {
    if (t->empty()) lines.push_back(key + " = {}");
    for (const auto& [k, v] : *t) {
      const std::string sub = key.empty() ? std::string(k.str()) : key + "." + std::string(k.str());
      if (!restart_may_change(sub)) flatten(v, sub, lines);
    }
  } else if (const auto* a = n.as_array()) {
    if (a->empty()) lines.push_back(key + " = []");
    for (size_t i = 0; i < a->size(); ++i)
      flatten(*a->get(i), fmt::format("{}[{}]", key, i), lines);
  } else if (const auto* s = n.as_string()) {
    lines.push_back(key + " = " + quoted(s->get()));
  } else if (const auto* i = n.as_integer()) {
    lines.push_back(fmt::format("{} = {:.17g}", key, static_cast<double>(i->get())));
  } else if (const auto* d = n.as_floating_point()) {
    lines.push_back(fmt::format("{} = {:.17g}", key, d->get()));
  } else if (const auto* b = n.as_boolean()) {
    lines.push_back(key + " = " + (b->get() ? "true" : "false"));
  } else {  // dates and times: as TOML writes them
    std::ostringstream s;
    n.visit([&](const auto& v) { s << v; });
    lines.push_back(key + " = " + s.str());
  }
}

std::map<std::string, std::string> by_key(const std::string& content) {
  std::map<std::string, std::string> out;
  std::istringstream in(content);
  for (std::string line; std::getline(in, line);) {
    const size_t eq = line.find(" = ");
    if (eq != std::string::npos) out[line.substr(0, eq)] = line.substr(eq + 3);
  }
  return out;
}

}  // namespace

std::string case_content(const toml::table& root, std::span<const Override> overrides) {
  std::vector<std::string> lines;
  flatten(root, "", lines);
  for (auto& line : lines) {
    const auto key = line.substr(0, line.find(" = "));
    for (const auto& o : overrides)
      if (key == o.key || key.rfind(o.key + ".", 0) == 0 || key.rfind(o.key + "[", 0) == 0) {
        line += " (--set)";
        break;
      }
  }
  std::sort(lines.begin(), lines.end());
  std::string out;
  for (const auto& line : lines) out += line + "\n";
  return out;
}

std::string content_difference(const std::string& was, const std::string& now) {
  const auto a = by_key(was), b = by_key(now);
  auto i = a.begin();
  auto j = b.begin();
  while (i != a.end() || j != b.end()) {
    if (j == b.end() || (i != a.end() && i->first < j->first))
      return fmt::format("{}: {} in the checkpoint's run, absent now", i->first, i->second);
    if (i == a.end() || j->first < i->first)
      return fmt::format("{}: absent in the checkpoint's run, {} now", j->first, j->second);
    if (i->second != j->second)
      return fmt::format("{}: {} in the checkpoint's run, {} now", i->first, i->second, j->second);
    ++i;
    ++j;
  }
  return "";
}

}  // namespace tc::io::detail
