// libFuzzer harness: bytes through the libpng reader of reference frames (read_png_rgb8), at
// most 1024 pixels per side, as given and again with every chunk's CRC recomputed (so that
// mutations reach the chunk and image parsers behind the checksums). A decoded image must hold
// exactly width x height RGB pixels and round-trip bit for bit through the libpng writer; a
// damaged file must come back Failed with a reason, never crash or leak.
#include <zlib.h>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pipeline/image_io/png_file.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

uint32_t be32(const std::vector<uint8_t>& b, size_t at) {
  return static_cast<uint32_t>(b[at]) << 24 | static_cast<uint32_t>(b[at + 1]) << 16 |
         static_cast<uint32_t>(b[at + 2]) << 8 | static_cast<uint32_t>(b[at + 3]);
}

// The bytes with each chunk's CRC (big-endian, over type and data) made right.
std::vector<uint8_t> with_crcs_fixed(const uint8_t* data, size_t size) {
  std::vector<uint8_t> b(data, data + size);
  for (size_t at = 8; at + 12 <= b.size();) {
    const uint32_t len = be32(b, at);
    if (len > b.size() - at - 12) break;
    const auto crc = static_cast<uint32_t>(crc32(0, b.data() + at + 4, len + 4));
    for (int i = 0; i < 4; ++i) b[at + 8 + len + i] = static_cast<uint8_t>(crc >> (24 - 8 * i));
    at += 12 + len;
  }
  return b;
}

std::string file_text(const std::string& path) {
  std::string s;
  if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
    char buf[65536];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
    std::fclose(f);
  }
  return s;
}

void check(const uint8_t* data, size_t size) {
  PngImage img;
  std::string error;
  const PngRead r = read_png_rgb8(data, size, 1024, &img, &error);
  if (r == PngRead::Failed && error.empty()) std::abort();
  if (r != PngRead::Ok) return;
  if (img.width <= 0 || img.height <= 0 || img.width > 1024 || img.height > 1024 ||
      img.rgb.size() != static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 3) {
    std::abort();
  }
  const std::string path = fuzz::write_input(nullptr, 0, ".png");
  if (!write_png_rgb8(path, img.width, img.height, img.rgb.data(), false).empty()) std::abort();
  const std::string bytes = file_text(path);
  PngImage back;
  if (read_png_rgb8(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), 1024, &back,
                    &error) != PngRead::Ok ||
      back.rgb != img.rgb) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  check(data, size);
  const std::vector<uint8_t> fixed = with_crcs_fixed(data, size);
  check(fixed.data(), fixed.size());
  return 0;
}
