#pragma once
// Test-only: the message of the InputError a call throws, "" if it throws none.
#include <string>

#include "blocks/base/input_error.h"

namespace texsim {

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace texsim
