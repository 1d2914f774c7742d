#pragma once
// The one way a value is written into a generated shell script (Slurm job arrays, GNU
// parallel command lines): as one single-quoted word, so that no byte of it (quotes, `$`,
// backquotes, newlines, spaces) can end the word, expand or run anything.
#include <string>
#include <string_view>

namespace texsim {

// `s` as one word for POSIX sh and bash: 'text', each ' in it written as '\'' ; the empty
// string is ''. Every byte but NUL is kept as it is; a shell word cannot hold NUL, so a NUL
// throws InputError naming `what` (the value's role, e.g. "--out").
std::string shell_quote(std::string_view s, std::string_view what = "shell argument");

}  // namespace texsim
