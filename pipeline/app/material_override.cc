#include "pipeline/app/material_override.h"

#include <cmath>
#include <cstdio>

namespace texsim {

namespace {

std::string quoted(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

std::string key_text(const std::string& k) {
  const bool bare = !k.empty() && k.find_first_not_of(
                                      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnop"
                                      "qrstuvwxyz0123456789_-") == std::string::npos;
  return bare ? k : quoted(k);
}

std::string float_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  std::string s = buf;
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::string inline_toml(const toml::node& n) {
  if (const auto* t = n.as_table()) {
    std::string s = "{ ";
    bool first = true;
    for (const auto& [k, v] : *t) {
      s += (first ? "" : ", ") + key_text(std::string(k.str())) + " = " + inline_toml(v);
      first = false;
    }
    return s + (first ? "}" : " }");
  }
  if (const auto* a = n.as_array()) {
    std::string s = "[";
    for (size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + inline_toml(*a->get(i));
    return s + "]";
  }
  if (const auto* v = n.as_string()) return quoted(v->get());
  if (const auto* v = n.as_integer()) return std::to_string(v->get());
  if (const auto* v = n.as_floating_point()) return float_text(v->get());
  if (const auto* v = n.as_boolean()) return v->get() ? "true" : "false";
  return "\"\"";  // dates and times: no material key takes them
}

std::string material_override(const std::string& name, const toml::table& effects) {
  return "materials." + key_text(name) + "=" + inline_toml(effects);
}

toml::table copy_table(const toml::table& t) {
  toml::table c;
  for (const auto& [k, v] : t) {
    if (const auto* sub = v.as_table()) {
      c.insert(k, copy_table(*sub));
    } else {
      c.insert(k, v);
    }
  }
  return c;
}

toml::table& sub_table(toml::table& t, const std::string& key) {
  if (auto* s = t.get_as<toml::table>(key)) return *s;
  t.insert_or_assign(key, toml::table{});
  return *t.get_as<toml::table>(key);
}

}  // namespace texsim
