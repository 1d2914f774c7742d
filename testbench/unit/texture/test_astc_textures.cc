// AstcDecoder against the ARM reference codec on real textures: each texture is compressed by
// astcenc (-cl, -fast) at one footprint, decoded by astcenc to FP16 OpenEXR, and every texel
// of every block is compared with AstcDecoder (Float16 bit for bit; Unorm16 and Unorm8 as the
// same interpolation results). The table in docs/derivations/astc.md §9 comes from this output.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "testbench/lib/astc_reference.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

using astc_reference::AstcFile;
using astc_reference::Image;
using astc_reference::Tally;

struct TextureCase {
  const char* path;
  const char* footprint;
};

constexpr const char* kGlmark = "/usr/share/glmark2/textures/";
constexpr const char* kMatplotlib = "/usr/share/matplotlib/mpl-data/sample_data/";

class AstcTextures : public ::testing::TestWithParam<TextureCase> {};

TEST_P(AstcTextures, EveryTexelMatchesAstcenc) {
  const TextureCase& c = GetParam();
  if (!std::filesystem::exists(astc_reference::kAstcenc) || !std::filesystem::exists(c.path)) {
    GTEST_SKIP() << "astcenc or " << c.path << " missing (scripts/setup-debian.sh installs them)";
  }
  const TempDir dir("texsim_astc");
  const std::string astc = dir.file("t.astc"), exr = dir.file("t.exr");
  ASSERT_TRUE(astc_reference::run_astcenc({"-cl", c.path, astc, c.footprint, "-fast"}));
  ASSERT_TRUE(astc_reference::run_astcenc({"-dl", astc, exr}));
  AstcFile f;
  Image ref;
  ASSERT_TRUE(astc_reference::read_astc(astc, &f));
  ASSERT_TRUE(astc_reference::read_exr(exr, &ref));
  Tally t;
  astc_reference::compare_blocks(f, ref, &t);
  EXPECT_EQ(t.mismatches, 0U);
  EXPECT_EQ(t.error_blocks, 0U);  // the encoder writes legal blocks only
  std::string what = std::filesystem::path(c.path).filename().string();
  what += ' ';
  what += c.footprint;
  std::printf("%s\n", astc_reference::tally_row(what, t).c_str());
}

std::string in(const char* folder, const char* name) { return std::string(folder) + name; }

// Paths live as long as the test program: the parameters point into them.
const std::string kJelly = in(kGlmark, "jellyfish256.png");
const std::string kCaustics = in(kGlmark, "jellyfish-caustics-01.png");
const std::string kWindow = in(kGlmark, "desktop-window.png");
const std::string kNasa = in(kGlmark, "nasa1.png");
const std::string kGlyphs = in(kGlmark, "glyph-atlas.png");
const std::string kLogo = in(kMatplotlib, "logo2.png");
const std::string kPresent = in(kMatplotlib, "Minduka_Present_Blue_Pack.png");

INSTANTIATE_TEST_SUITE_P(
    RealTextures, AstcTextures,
    ::testing::Values(TextureCase{kJelly.c_str(), "4x4"}, TextureCase{kCaustics.c_str(), "6x6"},
                      TextureCase{kWindow.c_str(), "8x8"}, TextureCase{kNasa.c_str(), "12x12"},
                      TextureCase{kGlyphs.c_str(), "8x6"}, TextureCase{kLogo.c_str(), "10x5"},
                      TextureCase{kLogo.c_str(), "12x12"}, TextureCase{kPresent.c_str(), "5x4"}));

}  // namespace
}  // namespace texsim
