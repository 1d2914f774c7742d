// libFuzzer harness: bytes as a .npz archive (from a file, through the zip directory, the
// bounded inflate and the .npy header) and as one .npy array, through the DEM reader. Bad
// input must end in InputError; a field whose size disagrees with its shape, or a height
// outside [0, 1] (NaN included), is a finding like a crash.
#include <cmath>
#include <cstdlib>
#include <string>

#include "pipeline/scene/npz_height_field.h"
#include "pipeline/scene/scene_memory.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;

void check(const NpzHeightField& f) {
  if (f.h.size() != static_cast<size_t>(f.width) * static_cast<size_t>(f.height)) std::abort();
  for (const double h : f.h) {
    if (!(h >= 0 && h <= 1)) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  set_scene_memory_limit(uint64_t{512} << 20);  // under the harness's 2 GB RSS limit
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const std::string path = texsim::fuzz::write_input(data, size, ".npz");
  texsim::fuzz::expect_clean([&] { check(read_npz_height_field(path)); });
  texsim::fuzz::expect_clean([&] { check(parse_npy_height_field(bytes, "fuzz.npy")); });
  return 0;
}
