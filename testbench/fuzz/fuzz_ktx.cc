// libFuzzer harness: bytes through the strict KTX 1.1 reader (parse_ktx). A file is either
// refused with an InputError or read into an image whose levels hold exactly their blocks'
// bytes, and that image written back (without the key/value data) reads back identical.
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "pipeline/image_io/ktx_file.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

bool same(const CompressedImage& a, const CompressedImage& b) {
  if (a.format != b.format || a.width != b.width || a.height != b.height ||
      a.block_w != b.block_w || a.block_h != b.block_h || a.block_bytes != b.block_bytes ||
      a.levels.size() != b.levels.size())
    return false;
  for (size_t i = 0; i < a.levels.size(); ++i) {
    if (a.levels[i].width != b.levels[i].width || a.levels[i].height != b.levels[i].height ||
        a.levels[i].bytes != b.levels[i].bytes)
      return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  CompressedImage img;
  bool read = false;
  fuzz::expect_clean([&] {
    img = parse_ktx(std::span<const uint8_t>(data, size), "fuzz input");
    read = true;
  });
  if (!read) return 0;
  check_compressed_image(img, "fuzz");           // the reader's result is always writable
  const std::string s = ktx_bytes(img, "fuzz");  // throws (aborts) if img is inconsistent
  const CompressedImage back =
      parse_ktx({reinterpret_cast<const uint8_t*>(s.data()), s.size()}, "fuzz round trip");
  if (!same(img, back)) std::abort();
  return 0;
}
