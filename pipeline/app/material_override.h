#pragma once
// A material's whole table as one `--set` override, so the error ledger and the tuner can
// change, add or drop any effect of a material (e.g. drop its coordinate unit) through the
// same override path as `texsim run --set` and sweeps.
#include <toml++/toml.h>

#include <string>

namespace texsim {

// The node as an inline TOML value (tables as `{ k = v, ... }`), deterministic: keys in the
// table's order, floats with 17 significant digits.
std::string inline_toml(const toml::node& n);

// "materials.<name>=<the table inline>".
std::string material_override(const std::string& name, const toml::table& effects);

// A copy of `t` with every table and array made a plain (non-inline) value, so it can be
// edited and written back; toml++ keeps sub-tables shared otherwise.
toml::table copy_table(const toml::table& t);

// The table at `key` of `t`, created (empty) when missing.
toml::table& sub_table(toml::table& t, const std::string& key);

}  // namespace texsim
