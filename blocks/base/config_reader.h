#pragma once
// Typed reads of block Config fields from a TOML table, with errors that name the source
// file, line and column, the block and the key (DESIGN: "errors name the block and the key").
#include <toml++/toml.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace texsim {

// Parses TOML text; a syntax error is an InputError "source:line:column: what".
toml::table parse_toml(const std::string& text, const std::string& source_name);

class ConfigReader {
 public:
  // `block` names the owner in messages, e.g. "cache" or "material 'floor'".
  ConfigReader(const toml::table& table, std::string source, std::string block);

  double get_double(std::string_view key, double def) const;
  int64_t get_int(std::string_view key, int64_t def, int64_t lo, int64_t hi) const;
  bool get_bool(std::string_view key, bool def) const;
  std::string get_string(std::string_view key, const std::string& def) const;
  // A string that must be one of `choices`; returns its index.
  int get_choice(std::string_view key, int def, const std::vector<std::string_view>& choices) const;
  // Throws if the table holds a key not in `known` (catches typos in scenes).
  void reject_unknown(const std::vector<std::string_view>& known) const;
  const toml::table* subtable(std::string_view key) const;
  ConfigReader sub(std::string_view key) const;  // empty table if absent
  // The same table as a block inside a unit reads it: messages name `block`, and
  // reject_unknown also accepts `unit_keys` (the keys the unit itself reads).
  ConfigReader for_block(std::string block, std::vector<std::string_view> unit_keys) const;

  [[noreturn]] void fail(std::string_view key, const std::string& what) const;
  [[noreturn]] void fail_at(const toml::node& node, const std::string& what) const;
  std::string where(const toml::node* node) const;
  const toml::table& table() const { return *table_; }
  const std::string& source() const { return source_; }
  const std::string& block() const { return block_; }

 private:
  const toml::table* table_;
  std::string source_;
  std::string block_;
  std::vector<std::string_view> unit_keys_;
};

}  // namespace texsim
