// libFuzzer harness: bytes through the strict DDS reader (parse_dds). A file is either refused
// with an InputError or read into an image whose levels hold exactly their blocks' bytes, and
// that image written with the legacy header and with the DX10 header reads back identical.
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "pipeline/image_io/dds_file.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

bool same(const CompressedImage& a, const CompressedImage& b) {
  if (a.format != b.format || a.width != b.width || a.height != b.height ||
      a.block_bytes != b.block_bytes || a.levels.size() != b.levels.size())
    return false;
  for (size_t i = 0; i < a.levels.size(); ++i) {
    if (a.levels[i].width != b.levels[i].width || a.levels[i].height != b.levels[i].height ||
        a.levels[i].bytes != b.levels[i].bytes)
      return false;
  }
  return true;
}

void round_trip(const CompressedImage& img, bool dx10) {
  const std::string s = dds_bytes(img, dx10, "fuzz");  // throws (aborts) if img is inconsistent
  const CompressedImage back =
      parse_dds({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, "fuzz round trip");
  if (!same(img, back)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  CompressedImage img;
  bool read = false;
  fuzz::expect_clean([&] {
    img = parse_dds(std::span<const uint8_t>(data, size), "fuzz input");
    read = true;
  });
  if (!read) return 0;
  check_compressed_image(img, "fuzz");  // the reader's result is always writable
  round_trip(img, false);
  round_trip(img, true);
  return 0;
}
