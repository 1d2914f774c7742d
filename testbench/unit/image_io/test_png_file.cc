// PNG files through libpng (pipeline/image_io/png_file.h): the writer's images read back bit for
// bit, by texsim's reader and by OpenImageIO; the reader gives OpenImageIO's pixels for every
// kind of PNG it takes and leaves the others (alpha, transparency, grey, 16-bit) to it; damaged
// files and failed writes are errors naming the file, and a failed write leaves nothing behind.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <png.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/png_file.h"
#include "pipeline/render/frame_compare.h"
#include "pipeline/report/image_metrics.h"
#include "testbench/lib/temp_dir.h"

namespace {

using namespace texsim;  // NOLINT(google-build-using-namespace)

std::vector<uint8_t> noise(size_t n, uint32_t seed) {
  std::vector<uint8_t> v(n);
  for (uint8_t& b : v) {
    seed = seed * 1664525u + 1013904223u;
    b = static_cast<uint8_t>(seed >> 24);
  }
  return v;
}

std::vector<uint8_t> file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// OpenImageIO's 8-bit RGB of a file, as texsim read every image before libpng.
Rgb8Image oiio_rgb8(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  Rgb8Image img;
  if (!in) return img;
  img.width = in->spec().width;
  img.height = in->spec().height;
  img.rgb.resize(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, img.rgb.data()));
  return img;
}

// A PNG of any kind, written with libpng directly: `samples` holds one byte (or two, 16-bit)
// per sample, palette indices one per byte.
struct PngKind {
  int colour = PNG_COLOR_TYPE_RGB, depth = 8;
  bool interlaced = false, gamma = false, srgb = false, trns = false;
};

void write_kind(const std::string& path, int w, int h, const PngKind& k) {
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), k.depth,
               k.colour, k.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  int channels = 3;
  std::vector<png_color> palette;
  std::vector<png_byte> alphas;
  if (k.colour == PNG_COLOR_TYPE_PALETTE) {
    channels = 1;
    const std::vector<uint8_t> c = noise(size_t{3} * 256, 7);
    for (size_t i = 0; i < (size_t{1} << k.depth); ++i)
      palette.push_back({c[3 * i], c[3 * i + 1], c[3 * i + 2]});
    png_set_PLTE(png, info, palette.data(), static_cast<int>(palette.size()));
    if (k.trns) {
      alphas.assign(palette.size(), 128);
      png_set_tRNS(png, info, alphas.data(), static_cast<int>(alphas.size()), nullptr);
    }
  } else if (k.colour == PNG_COLOR_TYPE_GRAY) {
    channels = 1;
  } else if (k.colour == PNG_COLOR_TYPE_RGB_ALPHA) {
    channels = 4;
  } else if (k.trns) {
    png_color_16 key{};  // the colour of the first pixel: transparent in OpenImageIO's reading
    const std::vector<uint8_t> first = noise(3, 3);
    key.red = first[0];
    key.green = first[1];
    key.blue = first[2];
    png_set_tRNS(png, info, nullptr, 0, &key);
  }
  if (k.gamma) png_set_gAMA(png, info, 1 / 2.2);
  if (k.srgb) png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
  png_write_info(png, info);
  if (k.depth < 8) png_set_packing(png);
  const size_t row =
      static_cast<size_t>(w) * static_cast<size_t>(channels) * (k.depth == 16 ? 2 : 1);
  std::vector<uint8_t> px = noise(row * static_cast<size_t>(h), 3);
  if (k.colour == PNG_COLOR_TYPE_PALETTE) {
    for (uint8_t& b : px) b = static_cast<uint8_t>(b % (1 << k.depth));
  }
  std::vector<png_bytep> rows;
  rows.reserve(static_cast<size_t>(h));
  for (int y = 0; y < h; ++y) rows.push_back(px.data() + static_cast<size_t>(y) * row);
  png_write_image(png, rows.data());
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

TEST(PngFile, WriterRoundTripsBitExactly) {
  TempDir dir("texsim_png");
  for (const auto& [w, h] : {std::pair{1, 1}, {3, 5}, {257, 129}, {64, 1}}) {
    for (bool fast : {false, true}) {
      const std::vector<uint8_t> px = noise(static_cast<size_t>(w) * h * 3, w * 31 + h);
      const std::string path = dir.file("rt.png");
      ASSERT_EQ(write_png_rgb8(path, w, h, px.data(), fast), "");
      const std::vector<uint8_t> bytes = file_bytes(path);
      PngImage back;
      std::string error;
      ASSERT_EQ(read_png_rgb8(bytes.data(), bytes.size(), 16384, &back, &error), PngRead::Ok)
          << error;
      EXPECT_EQ(back.width, w);
      EXPECT_EQ(back.height, h);
      EXPECT_EQ(back.rgb, px) << w << "x" << h << (fast ? " fast" : "");
      EXPECT_EQ(oiio_rgb8(path).rgb, px) << "OpenImageIO reads other pixels";
    }
  }
}

TEST(PngFile, WriteImageGivesTheEightBitPixelsOnTheCanvas) {
  TempDir dir("texsim_png");
  ImageRgb img(2, 1, 3, 2, 6, 4, glm::dvec3(0.25, 0.5, 1.0));
  img.set(2, 1, glm::vec4(1.0f, 0.0f, 0.5f, 1.0f));
  img.set(4, 2, glm::vec4(0.2f, 2.0f, -1.0f, 1.0f));
  write_image(dir.file("img.png"), img);
  const Rgb8Image back = read_rgb8_image(dir.file("img.png"));
  ASSERT_EQ(back.width, 6);
  ASSERT_EQ(back.height, 4);
  const auto at = [&](int x, int y, int c) {
    return back.rgb[(static_cast<size_t>(y) * 6 + x) * 3 + c];
  };
  EXPECT_EQ(at(0, 0, 0), 64);  // background, round(0.25 * 255)
  EXPECT_EQ(at(0, 0, 1), 128);
  EXPECT_EQ(at(0, 0, 2), 255);
  EXPECT_EQ(at(2, 1, 0), 255);
  EXPECT_EQ(at(2, 1, 2), 128);
  EXPECT_EQ(at(4, 2, 0), 51);
  EXPECT_EQ(at(4, 2, 1), 255);  // clamped
  EXPECT_EQ(at(4, 2, 2), 0);
  EXPECT_EQ(back.rgb, oiio_rgb8(dir.file("img.png")).rgb);
  EXPECT_EQ(dir.entries(), 1u) << "a temporary file was left behind";
}

TEST(PngFile, ReaderGivesOpenImageIOsPixelsForEveryKind) {
  TempDir dir("texsim_png");
  struct Case {
    const char* name;
    PngKind kind;
    PngRead expected;
  };
  const Case cases[] = {
      {"rgb8", {}, PngRead::Ok},
      {"rgb8 interlaced", {PNG_COLOR_TYPE_RGB, 8, true}, PngRead::Ok},
      {"rgb8 gAMA", {PNG_COLOR_TYPE_RGB, 8, false, true}, PngRead::Ok},
      {"rgb8 sRGB", {PNG_COLOR_TYPE_RGB, 8, false, false, true}, PngRead::Ok},
      {"palette 8", {PNG_COLOR_TYPE_PALETTE, 8}, PngRead::Ok},
      {"palette 4", {PNG_COLOR_TYPE_PALETTE, 4}, PngRead::Ok},
      {"palette 1 interlaced", {PNG_COLOR_TYPE_PALETTE, 1, true}, PngRead::Ok},
      {"palette tRNS", {PNG_COLOR_TYPE_PALETTE, 8, false, false, false, true}, PngRead::NotHandled},
      {"rgb8 tRNS", {PNG_COLOR_TYPE_RGB, 8, false, false, false, true}, PngRead::NotHandled},
      {"rgba8", {PNG_COLOR_TYPE_RGB_ALPHA, 8}, PngRead::NotHandled},
      {"rgba8 gAMA", {PNG_COLOR_TYPE_RGB_ALPHA, 8, false, true}, PngRead::NotHandled},
      {"rgb16", {PNG_COLOR_TYPE_RGB, 16}, PngRead::NotHandled},
      {"grey8", {PNG_COLOR_TYPE_GRAY, 8}, PngRead::NotHandled},
  };
  for (const Case& c : cases) {
    const std::string path = dir.file("k.png");
    write_kind(path, 37, 23, c.kind);
    const std::vector<uint8_t> bytes = file_bytes(path);
    PngImage img;
    std::string error;
    EXPECT_EQ(read_png_rgb8(bytes.data(), bytes.size(), 16384, &img, &error), c.expected)
        << c.name << ": " << error;
    if (c.expected == PngRead::Ok) {
      EXPECT_EQ(img.rgb, oiio_rgb8(path).rgb) << c.name;
    }
    if (c.kind.colour == PNG_COLOR_TYPE_GRAY) {
      EXPECT_THROW(read_rgb8_image(path), InputError) << "grey is not RGB";
      continue;
    }
    // read_rgb8_image, whichever library decodes: OpenImageIO's pixels.
    EXPECT_EQ(read_rgb8_image(path).rgb, oiio_rgb8(path).rgb) << c.name;
  }
}

TEST(PngFile, ShippedReferenceFramesReadAsOpenImageIOReadThem) {
  const std::string dir = std::string(TEXSIM_SOURCE_DIR) + "/traces/samples/openarena-aggressor/";
  for (const char* name : {"frame_0110.png", "frame_0111.png", "frame_0112.png"}) {
    const std::vector<uint8_t> bytes = file_bytes(dir + name);
    PngImage img;
    std::string error;
    ASSERT_EQ(read_png_rgb8(bytes.data(), bytes.size(), 16384, &img, &error), PngRead::Ok)
        << name << ": libpng should read it (8-bit RGB) " << error;
    EXPECT_EQ(img.rgb, oiio_rgb8(dir + name).rgb) << name;
  }
}

TEST(PngFile, DamagedFilesAreErrorsNamingTheFile) {
  TempDir dir("texsim_png");
  const std::vector<uint8_t> px = noise(size_t{40} * 30 * 3, 5);
  ASSERT_EQ(write_png_rgb8(dir.file("good.png"), 40, 30, px.data(), false), "");
  std::vector<uint8_t> bytes = file_bytes(dir.file("good.png"));
  PngImage img;
  std::string error;
  for (size_t keep : {bytes.size() / 2, size_t{40}, size_t{9}}) {
    error.clear();
    EXPECT_EQ(read_png_rgb8(bytes.data(), keep, 16384, &img, &error), PngRead::Failed) << keep;
    EXPECT_FALSE(error.empty());
  }
  EXPECT_EQ(read_png_rgb8(bytes.data(), bytes.size(), 39, &img, &error), PngRead::Failed);
  EXPECT_NE(error.find("more than 39 per side"), std::string::npos) << error;
  bytes[bytes.size() / 2] ^= 0x55;  // a flipped byte in the image data: its CRC fails
  EXPECT_EQ(read_png_rgb8(bytes.data(), bytes.size(), 16384, &img, &error), PngRead::Failed);
  std::ofstream(dir.file("bad.png"), std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size() / 2));
  try {
    read_rgb8_image(dir.file("bad.png"));
    ADD_FAILURE() << "a truncated PNG was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.file("bad.png")), std::string::npos) << e.what();
  }
}

TEST(PngFile, FailedWritesNameTheFileAndLeaveNothing) {
  TempDir dir("texsim_png");
  ImageRgb img(4, 4, glm::dvec3(0.5));
  std::ofstream(dir.file("plain")) << "a file, not a directory";
  const std::string under_file = dir.file("plain") + "/x.png";
  try {
    write_image(under_file, img);
    ADD_FAILURE() << "wrote under a file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(under_file), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Not a directory"), std::string::npos) << e.what();
  }
  // A full disk: the write fails in libpng or at close, and says why.
  std::filesystem::create_symlink("/dev/full", dir.file("full.png"));
  try {
    write_image(dir.file("full.png"), img);
    ADD_FAILURE() << "wrote to /dev/full";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.entries(), 2u) << "a temporary file was left behind";
}

}  // namespace
