#include "pipeline/scene/scene_overrides.h"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cstdio>

#include "blocks/base/input_error.h"
#include "blocks/base/printable.h"

namespace texsim {

namespace {

std::vector<std::string> split_path(const std::string& key, const std::string& where) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = key.find('.', start);
    parts.push_back(key.substr(start, dot - start));
    if (parts.back().empty()) throw InputError(where, "empty key in '" + key + "'");
    if (dot == std::string::npos) return parts;
    start = dot + 1;
  }
}

bool bare_word(const std::string& v) {
  if (v.empty()) return false;
  for (char c : v) {
    if (!std::isalnum(static_cast<unsigned char>(c)) &&
        std::string("_-:?&=/.+%").find(c) == std::string::npos)
      return false;
  }
  return true;
}

// VALUE as a TOML node whose source is `where` (so messages about it name the override).
toml::node_view<toml::node> parse_value(toml::table& holder, const std::string& value,
                                        const std::string& where) {
  try {
    holder = toml::parse("value = " + value, where);
  } catch (const toml::parse_error& e) {
    if (!bare_word(value)) {
      throw InputError(
          where, "'" + value + "' is not a TOML value (" + std::string(e.description()) + ")");
    }
    holder = toml::parse("value = \"" + value + "\"", where);
  }
  return holder["value"];
}

// A --set is one line of TOML: a newline, CR or other control character (tab aside, which TOML
// takes as a space) would let a value carry further keys or lines into the scene.
void check_one_line(const std::string& set) {
  for (size_t i = 0; i < set.size(); ++i) {
    const auto c = static_cast<unsigned char>(set[i]);
    if ((c < 0x20 && c != '\t') || c == 0x7f) {
      const size_t eq = set.find('=');
      char code[8];
      std::snprintf(code, sizeof code, "\\x%02x", c);
      throw InputError("--set " + printable(set.substr(0, std::min(eq, i))),
                       std::string("control character ") + code + " at byte " +
                           std::to_string(i + 1) +
                           ": a --set KEY=VALUE is one line without control characters");
    }
  }
}

}  // namespace

void apply_overrides(toml::table& root, const std::vector<std::string>& sets) {
  for (const std::string& set : sets) {
    check_one_line(set);
    const size_t eq = set.find('=');
    if (eq == std::string::npos) throw InputError("--set " + set, "expected KEY=VALUE");
    const std::string key = set.substr(0, eq), where = "--set " + key;
    const std::vector<std::string> path = split_path(key, where);
    toml::table holder;
    toml::node* value = parse_value(holder, set.substr(eq + 1), where).node();
    toml::node* at = &root;
    std::string walked;
    for (size_t i = 0; i < path.size(); ++i) {
      const std::string& part = path[i];
      const bool last = i + 1 == path.size();
      walked += (walked.empty() ? "" : ".") + part;
      if (toml::table* t = at->as_table()) {
        if (last) {
          t->insert_or_assign(part, std::move(*value));
          break;
        }
        if (!t->contains(part)) t->insert(part, toml::table{});
        at = t->get(part);
      } else if (toml::array* a = at->as_array()) {
        const bool digits = part.find_first_not_of("0123456789") == std::string::npos;
        const size_t idx = digits && part.size() < 9 ? std::stoul(part) : a->size();
        if (idx >= a->size()) {
          throw InputError(where, "'" + walked + "': the array has " + std::to_string(a->size()) +
                                      " elements (indices from 0)");
        }
        if (last) {
          a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(idx), std::move(*value));
          break;
        }
        at = a->get(idx);
      } else {
        throw InputError(where, "'" + walked.substr(0, walked.rfind('.')) +
                                    "' is a value, not a table or array");
      }
    }
  }
}

}  // namespace texsim
