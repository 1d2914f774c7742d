#pragma once
// Text from input files (names, paths, keys) is echoed in messages and reports: control
// characters and bytes that are not UTF-8 are shown as \xNN so they cannot act on a terminal
// or break a JSON writer. Newlines and tabs are kept.
#include <string>
#include <string_view>

namespace texsim {

// Length of the valid UTF-8 sequence starting at s[i], or 0 if none starts there.
size_t utf8_sequence_length(std::string_view s, size_t i);

// `s` with every control character (but \n and \t) and every byte outside a valid UTF-8
// sequence replaced by \xNN.
std::string printable(std::string_view s);

// True when `s` is valid UTF-8 without control characters (what a name may hold).
bool is_printable_utf8(std::string_view s);

}  // namespace texsim
