// Texture loading through OpenImageIO (PNG, JPEG, EXR, TIFF, mip-mapped .tx from maketx),
// pyramid construction, procedural textures and their error messages, which name the scene
// file and the line:column of the texture's source when the texture comes from a scene.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <zlib.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "blocks/base/input_error.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"

namespace fs = std::filesystem;

namespace texsim {
namespace {

class Loader : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("texsim_loader_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A 64x32 gradient with 3 channels: r = x/63, g = y/31, b = 0.25.
  std::string write(const std::string& name, const OIIO::TypeDesc& type) {
    std::string p = (dir_ / name).string();
    std::vector<float> px(size_t{64} * 32 * 3);
    for (int y = 0; y < 32; ++y)
      for (int x = 0; x < 64; ++x) {
        float* q = &px[static_cast<size_t>(y * 64 + x) * 3];
        q[0] = static_cast<float>(x) / 63.0f;
        q[1] = static_cast<float>(y) / 31.0f;
        q[2] = 0.25f;
      }
    auto out = OIIO::ImageOutput::create(p);
    EXPECT_TRUE(out) << p;
    OIIO::ImageSpec spec(64, 32, 3, type);
    EXPECT_TRUE(out->open(p, spec));
    EXPECT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    out->close();
    return p;
  }
  fs::path dir_;
};

void expect_gradient(const Texture& t, double tol) {
  ASSERT_EQ(t.width(0), 64);
  ASSERT_EQ(t.height(0), 32);
  EXPECT_EQ(t.levels(), 7);  // 64x32 → ... → 1x1
  EXPECT_EQ(t.width(6), 1);
  EXPECT_EQ(t.height(6), 1);
  for (int y = 0; y < 32; y += 5)
    for (int x = 0; x < 64; x += 7) {
      const Rgba c = t.texel(0, x, y);
      EXPECT_NEAR(c.r, x / 63.0, tol);
      EXPECT_NEAR(c.g, y / 31.0, tol);
      EXPECT_NEAR(c.b, 0.25, tol);
      EXPECT_FLOAT_EQ(c.a, 1.0f);  // no alpha in the file: opaque
    }
  // Level 1 is the 2x2 box average of level 0.
  const Rgba l1 = t.texel(1, 3, 2);
  double avg = 0;
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) avg += t.texel(0, 6 + dx, 4 + dy).r / 4.0;
  EXPECT_NEAR(l1.r, avg, 1.0 / 255 + tol);
}

TEST_F(Loader, Png8Bit) {
  const Texture t = load_texture(write("g.png", OIIO::TypeDesc::UINT8), "");
  EXPECT_EQ(t.format(), TexelFormat::Rgba8);
  expect_gradient(t, 0.5 / 255 + 1e-6);
}

TEST_F(Loader, JpegWithinCompressionError) {
  const Texture t = load_texture(write("g.jpg", OIIO::TypeDesc::UINT8), "");
  expect_gradient(t, 0.04);
}

TEST_F(Loader, ExrIsFloat) {
  const Texture t = load_texture(write("g.exr", OIIO::TypeDesc::HALF), "");
  EXPECT_EQ(t.format(), TexelFormat::Rgba32f);
  expect_gradient(t, 1e-3);
}

TEST_F(Loader, Tiff16Bit) {
  const Texture t = load_texture(write("g.tif", OIIO::TypeDesc::UINT16), "");
  EXPECT_EQ(t.format(), TexelFormat::Rgba32f);
  expect_gradient(t, 1e-4);
}

TEST_F(Loader, MaketxMipChainIsReadNotRebuilt) {
  const std::string src = write("g.tif", OIIO::TypeDesc::UINT8);
  const std::string tx = (dir_ / "g.tx").string();
  const std::string cmd = "maketx --filter box " + src + " -o " + tx + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << "maketx (openimageio-tools) must be installed";
  const Texture t = load_texture(tx, "");
  expect_gradient(t, 0.5 / 255 + 1e-6);
  EXPECT_EQ(t.level(3).width, 8);
}

TEST_F(Loader, RelativePathsResolveAgainstBaseDir) {
  write("g.png", OIIO::TypeDesc::UINT8);
  EXPECT_EQ(load_texture("g.png", dir_.string()).width(0), 64);
}

TEST_F(Loader, ErrorsNameTheFile) {
  try {
    load_texture("missing.png", dir_.string());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png: cannot open texture file: no such file"),
              std::string::npos)
        << e.what();
  }
}

// Devices, FIFOs and directories are refused before anything reads them (a texture naming
// /dev/zero used to hang the run), and a file declaring more texels than a texture may have is
// refused from its header, before any pixel buffer is allocated.
TEST_F(Loader, SpecialFilesAndHugeDeclaredSizesAreRefused) {
  auto expect_error = [](const std::string& source, const std::string& dir, const char* what) {
    try {
      load_texture(source, dir);
      ADD_FAILURE() << source << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expect_error("/dev/zero", "", "/dev/zero: cannot read texture file: is a device");
  expect_error(dir_.string(), "", "cannot read texture file: is a directory");
  const std::string fifo = (dir_ / "pipe.png").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  expect_error(fifo, "", "pipe.png: cannot read texture file: is a FIFO");
  // A PNG whose header declares 20000 x 20000 RGB pixels (no pixel data follows).
  auto be32 = [](std::string& s, uint32_t v) {
    for (int k = 3; k >= 0; --k) s += static_cast<char>((v >> (8 * k)) & 0xFF);
  };
  auto chunk = [&](std::string& png, const std::string& type, const std::string& data) {
    be32(png, static_cast<uint32_t>(data.size()));
    const std::string body = type + data;
    png += body;
    be32(png, static_cast<uint32_t>(crc32(0, reinterpret_cast<const Bytef*>(body.data()),
                                          static_cast<uInt>(body.size()))));
  };
  std::string ihdr;
  be32(ihdr, 20000);
  be32(ihdr, 20000);
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8-bit RGB, no interlace
  std::string png("\x89PNG\r\n\x1a\n", 8);
  chunk(png, "IHDR", ihdr);
  chunk(png, "IDAT", std::string("\x78\x9c", 2));  // the start of a zlib stream, no pixels
  chunk(png, "IEND", "");
  const std::string huge = (dir_ / "huge.png").string();
  std::ofstream(huge, std::ios::binary) << png;
  expect_error(huge, "", "20000x20000 has more than the 8192x8192 texels");
}

TEST(Procedural, CheckerNoiseGridAndErrors) {
  const Texture c = make_procedural_texture("procedural:checker?size=64&cells=4", "x");
  EXPECT_EQ(c.width(0), 64);
  EXPECT_EQ(c.levels(), 7);
  EXPECT_NE(c.texel(0, 0, 0).r, c.texel(0, 16, 0).r);  // neighbouring cells differ
  EXPECT_EQ(c.texel(0, 0, 0).r, c.texel(0, 16, 16).r);
  EXPECT_NEAR(c.texel(6, 0, 0).r, (0.95 + 0.08) / 2, 0.01);  // 1x1 level: the mean
  const Texture n = make_procedural_texture("procedural:noise?size=32&seed=3", "x");
  EXPECT_EQ(n.width(0), 32);
  const Texture g = make_procedural_texture("procedural:grid?size=32&format=rgba32f", "x");
  EXPECT_EQ(g.format(), TexelFormat::Rgba32f);
  EXPECT_THROW(make_procedural_texture("procedural:plaid", "s.toml:3:1"), InputError);
  EXPECT_THROW(make_procedural_texture("procedural:checker?size=0", "x"), InputError);
  EXPECT_THROW(make_procedural_texture("procedural:checker?colour=red", "x"), InputError);
  EXPECT_THROW(make_procedural_texture("procedural:checker?size", "x"), InputError);
  // rows: the square's first rows (a 1-D array's layer is one), 1..size.
  const Texture row = make_procedural_texture("procedural:checker?size=64&cells=4&rows=1", "x");
  EXPECT_EQ(row.width(0), 64);
  EXPECT_EQ(row.height(0), 1);
  EXPECT_EQ(row.texel(0, 16, 0).r, c.texel(0, 16, 0).r);
  EXPECT_THROW(make_procedural_texture("procedural:checker?size=8&rows=0", "x"), InputError);
  EXPECT_THROW(make_procedural_texture("procedural:checker?size=8&rows=9", "x"), InputError);
}

std::string scene_error(const std::string& source, const std::string& base_dir) {
  const std::string text =
      "[textures.floor]\nsource = \"" + source + "\"\n[materials.m]\ntexture = \"floor\"\n";
  try {
    const Scene s = parse_scene(text, "s.toml", base_dir);
    (void)load_scene_texture(s, 0);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A bad procedural spec is refused while the scene is parsed, at the value's line:column (it
// used to name only the spec itself, when the texture was built).
TEST(SceneTextures, BadProceduralSpecsNameSceneFileLineAndColumn) {
  for (const char* spec : {"procedural:checker?size=0", "procedural:plaid", "procedural:grid?line",
                           "procedural:noise?octaves=13", "procedural:checker?format=rgb"}) {
    const std::string e = scene_error(spec, "");
    EXPECT_EQ(e.rfind("s.toml:2:10: textures.floor.source: procedural texture '", 0), 0) << e;
  }
  EXPECT_EQ(scene_error("procedural:checker?size=0", ""),
            "s.toml:2:10: textures.floor.source: procedural texture "
            "'procedural:checker?size=0': size must be an integer in [1, 8192]");
  EXPECT_EQ(scene_error("procedural:checker?size=8&cells=8", ""), "");
}

// Missing and unreadable texture files name the scene's line:column, then the file.
TEST_F(Loader, SceneTextureFileErrorsNameSceneFileLineAndColumn) {
  const std::string missing = scene_error("missing.png", dir_.string());
  EXPECT_EQ(missing.rfind("s.toml:2:10: textures.floor.source: ", 0), 0) << missing;
  EXPECT_NE(missing.find("missing.png: cannot open texture file: no such file"), std::string::npos)
      << missing;
  std::ofstream(dir_ / "junk.png") << "this is not a png";
  const std::string junk = scene_error("junk.png", dir_.string());
  EXPECT_EQ(junk.rfind("s.toml:2:10: textures.floor.source: ", 0), 0) << junk;
  EXPECT_NE(junk.find("junk.png: cannot read texture"), std::string::npos) << junk;
}

}  // namespace
}  // namespace texsim
