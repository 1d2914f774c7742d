#pragma once
// `--set KEY=VALUE`: changes one key of a scene before it is read, so every override is
// validated exactly as the same key in the file. KEY is a dotted path through tables, with
// array indices as numbers (`planes.0.material`); VALUE is TOML (`8`, `1.5`, `"ewa"`,
// `[1, 2, 3]`, `{ mode = "ewa" }`), and a bare word is taken as a string (`mode=ewa`).
// Errors about an overridden value name `--set KEY` and the column in VALUE.
#include <string>
#include <vector>

namespace toml {
inline namespace v3 {
class table;
}
}  // namespace toml

namespace texsim {

// Applies each "KEY=VALUE" in order; creates missing tables; throws InputError naming the
// override on a malformed one, a path through a value that is not a table or array, or an
// index outside the array.
void apply_overrides(toml::table& root, const std::vector<std::string>& sets);

}  // namespace texsim
