#pragma once
// Test-only: writes a fuzzer's bytes to a per-process temporary file (the readers under test
// take paths), and runs a parser so that only InputError may leave it: any other exception
// is a defect and aborts, so libFuzzer reports it.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "blocks/base/input_error.h"

namespace texsim::fuzz {

inline std::string write_input(const uint8_t* data, size_t size, const char* ext) {
  std::string path = "/tmp/texsim-fuzz-" + std::to_string(static_cast<long>(::getpid())) + ext;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

template <class F>
void expect_clean(F&& f) {
  try {
    f();
  } catch (const InputError&) {
    // Bad input must end here: a clear error naming where and what.
  } catch (const std::exception& e) {
    std::fprintf(stderr, "non-InputError exception: %s\n", e.what());
    std::abort();
  }
}

}  // namespace texsim::fuzz
