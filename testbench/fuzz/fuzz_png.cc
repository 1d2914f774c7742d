// libFuzzer harness: bytes through the libpng reader of reference frames (read_png_rgb8), at
// most 1024 pixels per side. A decoded image must hold exactly width x height RGB pixels and
// round-trip bit for bit through the libpng writer; a damaged file must come back Failed with a
// reason, never crash or leak.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pipeline/image_io/png_file.h"
#include "testbench/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace texsim;  // NOLINT(google-build-using-namespace)
  PngImage img;
  std::string error;
  const PngRead r = read_png_rgb8(data, size, 1024, &img, &error);
  if (r == PngRead::Failed && error.empty()) std::abort();
  if (r != PngRead::Ok) return 0;
  if (img.width <= 0 || img.height <= 0 || img.width > 1024 || img.height > 1024 ||
      img.rgb.size() != static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 3) {
    std::abort();
  }
  const std::string path = fuzz::write_input(nullptr, 0, ".png");
  if (!write_png_rgb8(path, img.width, img.height, img.rgb.data(), false).empty()) std::abort();
  const std::string bytes = [&] {
    std::string s;
    if (std::FILE* f = std::fopen(path.c_str(), "rb")) {
      char buf[65536];
      for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
      std::fclose(f);
    }
    return s;
  }();
  PngImage back;
  if (read_png_rgb8(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(), 1024, &back,
                    &error) != PngRead::Ok ||
      back.rgb != img.rgb) {
    std::abort();
  }
  return 0;
}
