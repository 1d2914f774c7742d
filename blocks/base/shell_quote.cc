#include "blocks/base/shell_quote.h"

#include "blocks/base/input_error.h"

namespace texsim {

std::string shell_quote(std::string_view s, std::string_view what) {
  if (s.find('\0') != std::string_view::npos)
    throw InputError(std::string(what), "contains a NUL byte, which no shell word can hold");
  std::string q = "'";
  q.reserve(s.size() + 2);
  for (const char c : s) {
    if (c == '\'') {
      q += "'\\''";  // close the quote, an escaped quote, reopen
    } else {
      q += c;
    }
  }
  return q + "'";
}

}  // namespace texsim
