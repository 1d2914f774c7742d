// libFuzzer harness: bytes through the strict .astc reader (parse_astc). A file is either
// refused with an InputError or read into a one-level 2-D ASTC image whose blocks fill the
// file exactly, and that image written back is the same bytes.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <span>
#include <string>

#include "pipeline/image_io/astc_file.h"
#include "testbench/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace texsim;  // NOLINT(google-build-using-namespace)
  CompressedImage img;
  bool read = false;
  fuzz::expect_clean([&] {
    img = parse_astc(std::span<const uint8_t>(data, size), "fuzz input");
    read = true;
  });
  if (!read) return 0;
  if (img.levels.size() != 1 || !is_astc_2d_footprint(img.block_w, img.block_h)) std::abort();
  const std::string s = astc_bytes(img, "fuzz");
  // The header of a file that reads is canonical (z sizes other than 1 are refused).
  if (s.size() != size || std::memcmp(s.data(), data, size) != 0) std::abort();
  return 0;
}
