#pragma once
// The one exception type for bad input (files, records, config keys). Its message always
// names where (file, line:column or record) and what is wrong; the CLI prints it and exits 2.
#include <stdexcept>
#include <string>

namespace texsim {

class InputError : public std::runtime_error {
 public:
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where + ": " + what) {}
};

}  // namespace texsim
