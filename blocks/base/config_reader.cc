#include "blocks/base/config_reader.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {
const toml::table& empty_table() {
  static const toml::table t;
  return t;
}
}  // namespace

toml::table parse_toml(const std::string& text, const std::string& source_name) {
  try {
    return toml::parse(text, source_name);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(source_name + ":" + std::to_string(b.line) + ":" + std::to_string(b.column),
                     std::string(e.description()));
  }
}

ConfigReader::ConfigReader(const toml::table& table, std::string source, std::string block)
    : table_(&table), source_(std::move(source)), block_(std::move(block)) {}

std::string ConfigReader::where(const toml::node* node) const {
  const toml::node* n = node ? node : table_;
  const auto& src = n->source();
  // A value from the command line (scene_overrides.h) is named by its option.
  if (src.path && src.path->rfind("--set ", 0) == 0) return *src.path;
  if (src.begin.line > 0) {
    return source_ + ":" + std::to_string(src.begin.line) + ":" + std::to_string(src.begin.column);
  }
  return source_;
}

void ConfigReader::fail(std::string_view key, const std::string& what) const {
  const toml::node* n = table_->get(key);
  throw InputError(where(n), block_ + "." + std::string(key) + ": " + what);
}

void ConfigReader::fail_at(const toml::node& node, const std::string& what) const {
  throw InputError(where(&node), block_ + ": " + what);
}

double ConfigReader::get_double(std::string_view key, double def) const {
  const toml::node* n = table_->get(key);
  if (!n) return def;
  double v = 0;
  if (auto f = n->value_exact<double>())
    v = *f;
  else if (auto i = n->value_exact<int64_t>())
    v = static_cast<double>(*i);
  else
    fail(key, "expected a number");
  if (!std::isfinite(v)) fail(key, "must be finite");
  return v;
}

int64_t ConfigReader::get_int(std::string_view key, int64_t def, int64_t lo, int64_t hi) const {
  const toml::node* n = table_->get(key);
  if (!n) return def;
  auto i = n->value_exact<int64_t>();
  if (!i) fail(key, "expected an integer");
  if (*i < lo || *i > hi) {
    fail(key, "value " + std::to_string(*i) + " out of range [" + std::to_string(lo) + ", " +
                  std::to_string(hi) + "]");
  }
  return *i;
}

bool ConfigReader::get_bool(std::string_view key, bool def) const {
  const toml::node* n = table_->get(key);
  if (!n) return def;
  auto b = n->value_exact<bool>();
  if (!b) fail(key, "expected true or false");
  return *b;
}

std::string ConfigReader::get_string(std::string_view key, const std::string& def) const {
  const toml::node* n = table_->get(key);
  if (!n) return def;
  auto s = n->value_exact<std::string>();
  if (!s) fail(key, "expected a string");
  return *s;
}

int ConfigReader::get_choice(std::string_view key, int def,
                             const std::vector<std::string_view>& choices) const {
  const toml::node* n = table_->get(key);
  if (!n) return def;
  auto s = n->value_exact<std::string>();
  std::string list;
  for (auto c : choices) list += (list.empty() ? "" : ", ") + std::string(c);
  if (!s) fail(key, "expected one of: " + list);
  auto it = std::find(choices.begin(), choices.end(), *s);
  if (it == choices.end()) fail(key, "unknown value '" + *s + "' (expected one of: " + list + ")");
  return static_cast<int>(it - choices.begin());
}

void ConfigReader::reject_unknown(const std::vector<std::string_view>& known) const {
  for (const auto& [k, v] : *table_) {
    const auto in = [&k = k](const std::vector<std::string_view>& keys) {
      return std::find(keys.begin(), keys.end(), k.str()) != keys.end();
    };
    if (!in(known) && !in(unit_keys_)) {
      std::string list;
      for (auto c : known) list += (list.empty() ? "" : ", ") + std::string(c);
      for (auto c : unit_keys_) list += ", " + std::string(c);
      throw InputError(
          where(&v), block_ + ": unknown key '" + std::string(k.str()) + "' (known: " + list + ")");
    }
  }
}

const toml::table* ConfigReader::subtable(std::string_view key) const {
  const toml::node* n = table_->get(key);
  if (!n) return nullptr;
  if (!n->is_table()) fail(key, "expected a table");
  return n->as_table();
}

ConfigReader ConfigReader::sub(std::string_view key) const {
  const toml::table* t = subtable(key);
  return ConfigReader(t ? *t : empty_table(), source_, block_ + "." + std::string(key));
}

ConfigReader ConfigReader::for_block(std::string block,
                                     std::vector<std::string_view> unit_keys) const {
  ConfigReader r(*table_, source_, std::move(block));
  r.unit_keys_ = std::move(unit_keys);
  return r;
}

}  // namespace texsim
