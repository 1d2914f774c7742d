// BC1–BC5 decoders (blocks/texture/decode/): directed cases from the Khronos Data Format
// Specification 1.3 tables, and every 4x4 block of several real textures encoded with
// libsquish and NVIDIA Texture Tools and decoded both by texsim and by an independent decoder
// (squish::Decompress; NVTT's libnvimage).
//
// Comparison rule. Both references return 8 bits per channel from their own 8-bit
// arithmetic: BC1 endpoints expanded by bit replication ((k << 3) | (k >> 2) for 5 bits, which
// is not round(255·k / 31): 24 -> 198, not 197), and interpolation by truncating integer
// division ((2·E0 + E1) / 3, (6·a0 + a1) / 7, ...). texsim returns the spec's exact value, which
// differs from that by up to one or two 8-bit steps. So each texel's channel is compared
// through its code, read from the block's layout: texsim's value must be the spec's exact
// value of that code (DFS 1.3 tables, computed here in double), and the reference's value must
// be its documented 8-bit arithmetic on the same code. Both hold or the texel is a mismatch;
// the count of mismatches must be 0. The report counts separately the texels where texsim
// rounded to 8 bits equals the reference ("exact") and where the two differ only through the
// reference's arithmetic ("rounding": the spec wins; directed cases pin the spec's values).
#include <gtest/gtest.h>
#include <nvtt/nvtt.h>
#include <png.h>
#include <squish.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/texture/decode/bc1_decoder.h"
#include "blocks/texture/decode/bc2_decoder.h"
#include "blocks/texture/decode/bc3_decoder.h"
#include "blocks/texture/decode/bc4_decoder.h"
#include "blocks/texture/decode/bc5_decoder.h"
#include "pipeline/reference/mesa_peer.h"

// libnvimage (NVTT 2.0.8) exports its block decoders but installs no header for them: the
// declarations of the four-by-four colour block (16 Color32 stored as b, g, r, a bytes) and
// of the blocks' decodeBlock members, whose symbols the library defines.
namespace nv {
class ColorBlock {
 public:
  std::array<uint8_t, 64> bgra{};
};
struct BlockDXT1 {
  std::array<uint8_t, 8> bytes;
  void decodeBlock(ColorBlock* block) const;
};
struct BlockDXT3 {
  std::array<uint8_t, 16> bytes;
  void decodeBlock(ColorBlock* block) const;
};
struct BlockDXT5 {
  std::array<uint8_t, 16> bytes;
  void decodeBlock(ColorBlock* block) const;
};
struct BlockATI1 {
  std::array<uint8_t, 8> bytes;
  void decodeBlock(ColorBlock* block) const;
};
struct BlockATI2 {
  std::array<uint8_t, 16> bytes;
  void decodeBlock(ColorBlock* block) const;
};
}  // namespace nv

namespace texsim {
namespace {

// ---------------------------------------------------------------------------------------------
// Directed cases

std::array<uint8_t, 8> bc1_block(uint16_t c0, uint16_t c1, uint32_t bits) {
  return {static_cast<uint8_t>(c0 & 255U),           static_cast<uint8_t>(c0 >> 8),
          static_cast<uint8_t>(c1 & 255U),           static_cast<uint8_t>(c1 >> 8),
          static_cast<uint8_t>(bits & 255U),         static_cast<uint8_t>((bits >> 8) & 255U),
          static_cast<uint8_t>((bits >> 16) & 255U), static_cast<uint8_t>(bits >> 24)};
}
uint16_t rgb565(uint32_t r, uint32_t g, uint32_t b) {
  return static_cast<uint16_t>((r << 11) | (g << 5) | b);
}
float q(double num, double den) { return static_cast<float>(num / den); }

// Codes 0, 1, 2, 3 in texels 0..3 (row 0), repeated in every row.
constexpr uint32_t kCodes0123 = 0xE4E4E4E4U;

TEST(Bc1Decoder, SpecExampleFourColours) {
  // DFS 1.3's BC1 figure: colour0 = (29/31, 60/63, 1/31) > colour1 = (20/31, 2/63, 30/31).
  const auto blk = bc1_block(rgb565(29, 60, 1), rgb565(20, 2, 30), kCodes0123);
  const DecodedBlock d = Bc1Decoder().decode(blk);
  ASSERT_EQ(d.width, 4);
  ASSERT_EQ(d.height, 4);
  EXPECT_EQ(d.at(0, 0), glm::vec4(q(29, 31), q(60, 63), q(1, 31), 1));
  EXPECT_EQ(d.at(1, 0), glm::vec4(q(20, 31), q(2, 63), q(30, 31), 1));
  // Exact thirds: (2·c0 + c1) / 3 and (c0 + 2·c1) / 3 of the unpacked values.
  EXPECT_EQ(d.at(2, 0), glm::vec4(q(78, 93), q(122, 189), q(32, 93), 1));
  EXPECT_EQ(d.at(3, 0), glm::vec4(q(69, 93), q(64, 189), q(61, 93), 1));
  EXPECT_EQ(d.at(3, 3), d.at(3, 0));
}

TEST(Bc1Decoder, SpecExampleThreeColoursAndBlack) {
  // The same colours swapped: colour0 <= colour1, one exact half and code 3 = black.
  const auto blk = bc1_block(rgb565(20, 2, 30), rgb565(29, 60, 1), kCodes0123);
  const DecodedBlock rgb = Bc1Decoder().decode(blk);
  EXPECT_EQ(rgb.at(2, 1), glm::vec4(q(49, 62), q(62, 126), q(31, 62), 1));
  EXPECT_EQ(rgb.at(3, 1), glm::vec4(0, 0, 0, 1));  // BC1 with no alpha: opaque black
  Bc1Decoder::Config c;
  c.alpha = true;
  const DecodedBlock rgba = Bc1Decoder(c).decode(blk);
  EXPECT_EQ(rgba.at(3, 1), glm::vec4(0, 0, 0, 0));  // BC1 with alpha: transparent black
  EXPECT_EQ(rgba.at(2, 1), rgb.at(2, 1));
  EXPECT_EQ(rgba.at(0, 1).a, 1.0F);
}

TEST(Bc1Decoder, EqualColoursSelectThreeColourMode) {
  const uint16_t c = rgb565(7, 9, 11);
  Bc1Decoder::Config cfg;
  cfg.alpha = true;
  const DecodedBlock d = Bc1Decoder(cfg).decode(bc1_block(c, c, kCodes0123));
  EXPECT_EQ(d.at(2, 0), glm::vec4(q(14, 62), q(18, 126), q(22, 62), 1));
  EXPECT_EQ(d.at(3, 0), glm::vec4(0, 0, 0, 0));
  // BC2/BC3's colour block is always four colours: code 3 is a third, never transparent.
  std::array<uint8_t, 16> bc2{};
  const auto colour = bc1_block(c, c, kCodes0123);
  std::copy(colour.begin(), colour.end(), bc2.begin() + 8);
  const DecodedBlock d2 = Bc2Decoder().decode(bc2);
  EXPECT_EQ(d2.at(3, 0), glm::vec4(q(21, 93), q(27, 189), q(33, 93), 0));
}

TEST(Bc1Decoder, SpecWinsOverTruncatingReference) {
  // colour0 = (0, 1, 0) > colour1 = (0, 0, 1) as integers (32 > 1): four colours; blue 0 and 1.
  const auto blk = bc1_block(rgb565(0, 1, 0), rgb565(0, 0, 1), 0xAAAAAAAAU);  // code 2
  const DecodedBlock d = Bc1Decoder().decode(blk);
  // Spec: blue = (2·0 + 1) / 93 exactly; 255/93 = 2.74, rounded 3. squish: (2·0 + 8) / 3 = 2.
  EXPECT_EQ(d.at(0, 0).b, q(1, 93));
  EXPECT_EQ(std::lround(d.at(0, 0).b * 255.0), 3);
  std::array<uint8_t, 64> ref{};
  squish::Decompress(ref.data(), blk.data(), squish::kDxt1);
  EXPECT_EQ(ref[2], 2) << "squish truncates (2·E0 + E1) / 3";
}

TEST(Bc2Decoder, ExplicitAlphaNibbles) {
  std::array<uint8_t, 16> blk{};
  for (size_t t = 0; t < 16; ++t) {  // texel t's alpha = t, low nibble first
    blk[t / 2] = static_cast<uint8_t>(blk[t / 2] | (t << (4 * (t % 2))));
  }
  const auto colour = bc1_block(rgb565(31, 63, 31), 0, 0);
  std::copy(colour.begin(), colour.end(), blk.begin() + 8);
  const DecodedBlock d = Bc2Decoder().decode(blk);
  for (int t = 0; t < 16; ++t) {
    EXPECT_EQ(d.at(t % 4, t / 4).a, q(t, 15));
    EXPECT_EQ(d.at(t % 4, t / 4).r, 1.0F);
  }
}

std::array<uint8_t, 8> bc4_block(uint8_t r0, uint8_t r1, const std::array<uint32_t, 16>& codes) {
  std::array<uint8_t, 8> b{r0, r1};
  uint64_t bits = 0;
  for (int t = 15; t >= 0; --t) bits = (bits << 3) | codes[static_cast<size_t>(t)];
  for (size_t i = 0; i < 6; ++i) b[2 + i] = static_cast<uint8_t>(bits >> (8 * i));
  return b;
}
constexpr std::array<uint32_t, 16> kCodes8 = {0, 1, 2, 3, 4, 5, 6, 7, 7, 6, 5, 4, 3, 2, 1, 0};

TEST(Bc4Decoder, UnormSeventhsAndFifths) {
  const auto seven = Bc4Decoder::decode_channel(bc4_block(200, 10, kCodes8), false);
  EXPECT_EQ(seven[0], q(200, 255));
  EXPECT_EQ(seven[1], q(10, 255));
  for (int k = 1; k <= 6; ++k) {  // ((7 - k)·200 + k·10) / (7·255)
    EXPECT_EQ(seven[static_cast<size_t>(k + 1)], q((7 - k) * 200 + k * 10, 1785)) << k;
  }
  const auto five = Bc4Decoder::decode_channel(bc4_block(10, 200, kCodes8), false);
  for (int k = 1; k <= 4; ++k) {
    EXPECT_EQ(five[static_cast<size_t>(k + 1)], q((5 - k) * 10 + k * 200, 1275)) << k;
  }
  EXPECT_EQ(five[6], 0.0F);
  EXPECT_EQ(five[7], 1.0F);
  EXPECT_EQ(five[15], q(10, 255));
  const DecodedBlock d = Bc4Decoder().decode(bc4_block(10, 200, kCodes8));
  EXPECT_EQ(d.at(3, 0), glm::vec4(five[3], 0, 0, 1));
}

TEST(Bc4Decoder, SnormEndpointsMinusOneAndSignedCompare) {
  // red0 = 100 > red1 = -50 (0xCE): sevenths of k / 127.
  const auto s = Bc4Decoder::decode_channel(bc4_block(100, 0xCE, kCodes8), true);
  EXPECT_EQ(s[0], q(100, 127));
  EXPECT_EQ(s[1], q(-50, 127));
  EXPECT_EQ(s[4], q(4 * 100 + 3 * -50, 889));
  // red0 = -128 (0x80) <= red1 = 20: fifths with -128 read as -1 = -127/127; min -1, max 1.
  const auto f = Bc4Decoder::decode_channel(bc4_block(0x80, 20, kCodes8), true);
  EXPECT_EQ(f[0], -1.0F);
  EXPECT_EQ(f[2], q(4 * -127 + 20, 635));
  EXPECT_EQ(f[6], -1.0F);
  EXPECT_EQ(f[7], 1.0F);
  // As UNORM the same bytes compare 128 > 20: sevenths.
  const auto u = Bc4Decoder::decode_channel(bc4_block(0x80, 20, kCodes8), false);
  EXPECT_EQ(u[6], q(2 * 128 + 5 * 20, 1785));
  // The DFS leaves red0 = -127, red1 = -128 undefined: texsim compares the stored integers
  // (-127 > -128: sevenths), and every entry is then -1.
  const auto edge = Bc4Decoder::decode_channel(bc4_block(0x81, 0x80, kCodes8), true);
  for (float v : edge) EXPECT_EQ(v, -1.0F);
}

TEST(Bc5Decoder, TwoChannelsRedThenGreen) {
  std::array<uint8_t, 16> blk{};
  const auto r = bc4_block(0x80, 0, kCodes8);     // SNORM -128 <= 0: fifths
  const auto g = bc4_block(0x81, 0x7F, kCodes8);  // SNORM -127 <= 127: fifths
  std::copy(r.begin(), r.end(), blk.begin());
  std::copy(g.begin(), g.end(), blk.begin() + 8);
  Bc5Decoder::Config c;
  c.snorm = true;
  const DecodedBlock d = Bc5Decoder(c).decode(blk);
  EXPECT_EQ(d.at(0, 0), glm::vec4(-1.0F, -1.0F, 0, 1));  // -128 is -1
  EXPECT_EQ(d.at(2, 0), glm::vec4(q(4 * -127, 635), q(4 * -127 + 127, 635), 0, 1));
  // As UNORM: 128 > 0 and 129 > 127, both sevenths.
  const DecodedBlock u = Bc5Decoder().decode(blk);
  EXPECT_EQ(u.at(2, 0), glm::vec4(q(6 * 128, 1785), q(6 * 129 + 127, 1785), 0, 1));
}

TEST(BcDecoders, CostsAndTiming) {
  // The table of docs/derivations/bc-formats.md §7 (default technology table).
  const TechTable tech = TechTable::defaults();
  struct Row {
    OpCounts ops;
    TimingSpec t;
    uint64_t add, mul, cmp;
    uint32_t latency;
    double area;
  };
  Bc1Decoder::Config bc1a;
  bc1a.alpha = true;
  Bc4Decoder::Config snorm4;
  snorm4.snorm = true;
  Bc5Decoder::Config snorm5;
  snorm5.snorm = true;
  const std::vector<Row> rows = {
      {Bc1Decoder().ops_per_item(), Bc1Decoder().timing(tech), 9, 12, 55, 6, 132.5},
      {Bc1Decoder(bc1a).ops_per_item(), Bc1Decoder(bc1a).timing(tech), 9, 12, 71, 6, 140.5},
      {Bc2Decoder().ops_per_item(), Bc2Decoder().timing(tech), 6, 28, 48, 6, 254},
      {Bc3Decoder().ops_per_item(), Bc3Decoder().timing(tech), 26, 20, 71, 7, 221.5},
      {Bc4Decoder().ops_per_item(), Bc4Decoder().timing(tech), 20, 8, 23, 7, 95.5},
      {Bc4Decoder(snorm4).ops_per_item(), Bc4Decoder(snorm4).timing(tech), 20, 8, 25, 8, 96.5},
      {Bc5Decoder().ops_per_item(), Bc5Decoder().timing(tech), 40, 16, 46, 7, 191},
      {Bc5Decoder(snorm5).ops_per_item(), Bc5Decoder(snorm5).timing(tech), 40, 16, 50, 8, 193},
  };
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    EXPECT_EQ(r.ops.add, r.add) << i;
    EXPECT_EQ(r.ops.mul, r.mul) << i;
    EXPECT_EQ(r.ops.cmp, r.cmp) << i;
    EXPECT_EQ(r.t.latency, r.latency) << i;
    EXPECT_EQ(r.t.ii, 1u) << i;
    EXPECT_DOUBLE_EQ(r.t.area, r.area) << i;
  }
  Bc4Decoder::Config shared;
  shared.datapath = Datapath::Shared;  // one operator per kind: II = the most ops of a kind
  EXPECT_EQ(Bc4Decoder(shared).timing(tech).ii, 23u);
  EXPECT_EQ(Bc4Decoder().name(), "texture.decode.bc4");
}

// ---------------------------------------------------------------------------------------------
// Every block of real textures against the independent decoders

// The textures (glmark2-data, python-matplotlib-data): RGB, RGBA, grey + alpha; photographs,
// renderings, icons, text.
const std::vector<std::string> kTextures = {
    "/usr/share/glmark2/textures/crate-base.png",
    "/usr/share/glmark2/textures/desktop-window.png",
    "/usr/share/glmark2/textures/nasa1.png",
    "/usr/share/glmark2/textures/jellyfish256.png",
    "/usr/share/glmark2/textures/glyph-atlas.png",
    "/usr/share/matplotlib/mpl-data/sample_data/Minduka_Present_Blue_Pack.png",
    "/usr/share/matplotlib/mpl-data/sample_data/logo2.png",
};

struct Rgba8Image {
  int width = 0;  // cropped to whole blocks
  int height = 0;
  int stride = 0;  // bytes per row of the file's image
  std::vector<uint8_t> px;
  // The 16 RGBA texels of block (bx, by), row-major.
  std::array<uint8_t, 64> block(int bx, int by) const {
    std::array<uint8_t, 64> b{};
    for (int y = 0; y < 4; ++y) {
      const auto row = static_cast<size_t>(4 * by + y) * static_cast<size_t>(stride) +
                       16 * static_cast<size_t>(bx);
      std::copy_n(px.begin() + static_cast<std::ptrdiff_t>(row), 16,
                  b.begin() + static_cast<std::ptrdiff_t>(16 * y));
    }
    return b;
  }
};

Rgba8Image load_rgba(const std::string& path) {
  png_image img{};
  img.version = PNG_IMAGE_VERSION;
  Rgba8Image out;
  if (png_image_begin_read_from_file(&img, path.c_str()) == 0) return out;
  img.format = PNG_FORMAT_RGBA;
  out.px.resize(PNG_IMAGE_SIZE(img));
  if (png_image_finish_read(&img, nullptr, out.px.data(), 0, nullptr) == 0) return out;
  out.stride = static_cast<int>(PNG_IMAGE_ROW_STRIDE(img));
  out.width = static_cast<int>(img.width) / 4 * 4;
  out.height = static_cast<int>(img.height) / 4 * 4;
  return out;
}

// What one channel of a block may decode to, read from the block's layout: the texel's code,
// the spec's exact value of each code (DFS 1.3 tables, in double; rounded to float it is the
// correctly rounded value, as no k/d with d < 2^12 lies within 2^-53 of a float midpoint) and
// the value the references' documented 8-bit arithmetic gives for it.
struct ChannelModel {
  std::array<uint8_t, 16> code{};
  std::array<double, 16> spec{};
  std::array<int, 16> ref{};
  bool snorm = false;  // ref holds two's complement bytes
};
using BlockModel = std::array<ChannelModel, 4>;

// 5- or 6-bit k to 8 bits by bit replication, as both references expand BC1 endpoints.
int replicate(uint32_t k, int bits) {
  return static_cast<int>((k << (8 - bits)) | (k >> (2 * bits - 8)));
}

// BC1 colour block (and its alpha) at `b`.
void bc1_model(const uint8_t* b, bool three_colour_mode, BlockModel& m) {
  const uint32_t c0 = b[0] | (uint32_t{b[1]} << 8);
  const uint32_t c1 = b[2] | (uint32_t{b[3]} << 8);
  const bool four = !three_colour_mode || c0 > c1;
  const std::array<int, 3> bits = {5, 6, 5};
  const std::array<int, 3> shift = {11, 5, 0};
  for (size_t c = 0; c < 3; ++c) {
    const uint32_t mask = (1U << bits[c]) - 1;
    const uint32_t k0 = (c0 >> shift[c]) & mask;
    const uint32_t k1 = (c1 >> shift[c]) & mask;
    const double mx = mask;
    const int e0 = replicate(k0, bits[c]);
    const int e1 = replicate(k1, bits[c]);
    ChannelModel& ch = m[c];
    ch.spec[0] = k0 / mx;
    ch.spec[1] = k1 / mx;
    ch.ref[0] = e0;
    ch.ref[1] = e1;
    if (four) {
      ch.spec[2] = (2.0 * k0 + k1) / (3 * mx);
      ch.spec[3] = (k0 + 2.0 * k1) / (3 * mx);
      ch.ref[2] = (2 * e0 + e1) / 3;
      ch.ref[3] = (e0 + 2 * e1) / 3;
    } else {
      ch.spec[2] = (k0 + static_cast<double>(k1)) / (2 * mx);
      ch.ref[2] = (e0 + e1) / 2;
    }
  }
  ChannelModel& a = m[3];
  a.spec = {1, 1, 1, four ? 1.0 : 0.0};
  a.ref = {255, 255, 255, four ? 255 : 0};
  for (size_t t = 0; t < 16; ++t) {
    const auto code = static_cast<uint8_t>((b[4 + t / 4] >> (2 * (t % 4))) & 3U);
    m[0].code[t] = m[1].code[t] = m[2].code[t] = m[3].code[t] = code;
  }
}

// BC4 UNORM channel block at `b`.
ChannelModel bc4_model(const uint8_t* b) {
  ChannelModel ch;
  const int a0 = b[0];
  const int a1 = b[1];
  ch.spec[0] = a0 / 255.0;
  ch.spec[1] = a1 / 255.0;
  ch.ref[0] = a0;
  ch.ref[1] = a1;
  const int n = a0 > a1 ? 7 : 5;
  for (int k = 1; k < n; ++k) {
    const auto i = static_cast<size_t>(k) + 1;
    ch.spec[i] = ((n - k) * a0 + k * a1) / (255.0 * n);
    ch.ref[i] = ((n - k) * a0 + k * a1) / n;
  }
  if (n == 5) {
    ch.spec[6] = 0;
    ch.spec[7] = 1;
    ch.ref[6] = 0;
    ch.ref[7] = 255;
  }
  uint64_t bits = 0;
  for (int i = 5; i >= 0; --i) bits = (bits << 8) | b[2 + i];
  for (size_t t = 0; t < 16; ++t) ch.code[t] = static_cast<uint8_t>((bits >> (3 * t)) & 7U);
  return ch;
}

// BC4 SNORM channel block at `b`, against Mesa: the spec reads -128 as -1 = -127/127; Mesa
// interpolates the raw two's complement bytes (-128 kept) with C's division (toward zero),
// code 6 is -128, and its read-back as GL_BYTE turns -128 (-1.0) into -127.
ChannelModel bc4_snorm_mesa_model(const uint8_t* b) {
  ChannelModel ch = bc4_model(b);  // for the codes
  ch.snorm = true;
  const int s0 = b[0] >= 128 ? b[0] - 256 : b[0];
  const int s1 = b[1] >= 128 ? b[1] - 256 : b[1];
  const int e0 = std::max(s0, -127);
  const int e1 = std::max(s1, -127);
  std::array<int, 8> raw{s0, s1};
  ch.spec[0] = e0 / 127.0;
  ch.spec[1] = e1 / 127.0;
  const int n = s0 > s1 ? 7 : 5;
  for (int k = 1; k < n; ++k) {
    const auto i = static_cast<size_t>(k) + 1;
    ch.spec[i] = ((n - k) * e0 + k * e1) / (127.0 * n);
    raw[i] = ((n - k) * s0 + k * s1) / n;
  }
  if (n == 5) {
    ch.spec[6] = -1;
    ch.spec[7] = 1;
    raw[6] = -128;
    raw[7] = 127;
  }
  for (size_t i = 0; i < 8; ++i) ch.ref[i] = std::max(raw[i], -127) & 0xFF;
  return ch;
}

// BC2's explicit alpha at `b`: the code is the 4-bit value itself.
ChannelModel bc2_alpha_model(const uint8_t* b) {
  ChannelModel ch;
  for (size_t a = 0; a < 16; ++a) {
    ch.spec[a] = static_cast<double>(a) / 15.0;
    ch.ref[a] = static_cast<int>(a * 17);
  }
  for (size_t t = 0; t < 16; ++t)
    ch.code[t] = static_cast<uint8_t>((b[t / 2] >> (4 * (t % 2))) & 15U);
  return ch;
}

struct Tally {
  uint64_t blocks = 0;
  uint64_t values = 0;        // channel values compared
  uint64_t exact = 0;         // reference == texsim rounded to 8 bits
  uint64_t rounding = 0;      // differ only by the reference's 8-bit arithmetic (the spec wins)
  uint64_t mismatches = 0;    // anything else
  uint64_t three_colour = 0;  // BC1 blocks in the three-colour (punch-through) mode
  std::string first;          // the first mismatch
};

// The channels `channels` of a decoded block against the reference's RGBA8 texels, under the
// rule at the top of this file.
void compare_block(Tally& tally, const DecodedBlock& d, const std::array<uint8_t, 64>& ref,
                   const std::vector<int>& channels, const BlockModel& model, size_t block) {
  ++tally.blocks;
  for (size_t t = 0; t < 16; ++t) {
    for (int c : channels) {
      const auto ci = static_cast<size_t>(c);
      const ChannelModel& m = model[ci];
      const size_t code = m.code[t];
      const float v = d.texels[t][c];
      const int r8 = ref[4 * t + ci];
      ++tally.values;
      if (v == static_cast<float>(m.spec[code]) && r8 == m.ref[code]) {
        const long r = m.snorm ? std::lround(static_cast<double>(v) * 127.0) & 0xFF
                               : std::lround(static_cast<double>(v) * 255.0);
        ++(r == r8 ? tally.exact : tally.rounding);
      } else if (tally.mismatches++ == 0) {
        tally.first = "block " + std::to_string(block) + " texel " + std::to_string(t) +
                      " channel " + std::to_string(c) + " code " + std::to_string(code) +
                      ": texsim " + std::to_string(v) + ", spec " + std::to_string(m.spec[code]) +
                      ", reference " + std::to_string(r8) + " (expected " +
                      std::to_string(m.ref[code]) + ")";
      }
    }
  }
}

// Counts a BC1 block in the three-colour mode (colour0 <= colour1).
void count_mode(Tally& tally, const std::string& format, const uint8_t* b) {
  if (format == "BC1" && (b[0] | (b[1] << 8)) <= (b[2] | (b[3] << 8))) ++tally.three_colour;
}

void report(const char* format, const char* reference, const std::string& texture, const Tally& t) {
  std::printf(
      "%-4s %-8s %-30s blocks %6llu values %8llu exact %8llu rounding %7llu "
      "mismatches %llu three-colour %llu\n",
      format, reference, texture.substr(texture.rfind('/') + 1).c_str(),
      static_cast<unsigned long long>(t.blocks), static_cast<unsigned long long>(t.values),
      static_cast<unsigned long long>(t.exact), static_cast<unsigned long long>(t.rounding),
      static_cast<unsigned long long>(t.mismatches),
      static_cast<unsigned long long>(t.three_colour));
  EXPECT_EQ(t.mismatches, 0u) << format << " vs " << reference << " on " << texture << ": "
                              << t.first;
  EXPECT_GT(t.blocks, 0u);
}

// One format under comparison: texsim's decoder, the channels a reference returns, and the
// block's model.
struct FormatCase {
  const char* name;
  int bytes;
  std::function<DecodedBlock(const uint8_t*)> decode;
  std::vector<int> channels;
  std::function<BlockModel(const uint8_t*)> model;
};

std::vector<FormatCase> format_cases() {
  Bc1Decoder::Config bc1a;
  bc1a.alpha = true;  // both references decode code 3 of a three-colour block as transparent
  const Bc1Decoder bc1(bc1a);
  const Bc2Decoder bc2;
  const Bc3Decoder bc3;
  const Bc4Decoder bc4;
  const Bc5Decoder bc5;
  return {
      {"BC1",
       8,
       [=](const uint8_t* b) { return bc1.decode(std::span<const uint8_t, 8>(b, 8)); },
       {0, 1, 2, 3},
       [](const uint8_t* b) {
         BlockModel m;
         bc1_model(b, true, m);
         return m;
       }},
      {"BC2",
       16,
       [=](const uint8_t* b) { return bc2.decode(std::span<const uint8_t, 16>(b, 16)); },
       {0, 1, 2, 3},
       [](const uint8_t* b) {
         BlockModel m;
         bc1_model(b + 8, false, m);
         m[3] = bc2_alpha_model(b);
         return m;
       }},
      {"BC3",
       16,
       [=](const uint8_t* b) { return bc3.decode(std::span<const uint8_t, 16>(b, 16)); },
       {0, 1, 2, 3},
       [](const uint8_t* b) {
         BlockModel m;
         bc1_model(b + 8, false, m);
         m[3] = bc4_model(b);
         return m;
       }},
      {"BC4",
       8,
       [=](const uint8_t* b) { return bc4.decode(std::span<const uint8_t, 8>(b, 8)); },
       {0},
       [](const uint8_t* b) {
         return BlockModel{bc4_model(b), {}, {}, {}};
       }},
      {"BC5",
       16,
       [=](const uint8_t* b) { return bc5.decode(std::span<const uint8_t, 16>(b, 16)); },
       {0, 1},
       [](const uint8_t* b) {
         return BlockModel{bc4_model(b), bc4_model(b + 8), {}, {}};
       }},
  };
}

// squish's decoding of one block, as RGBA8. squish::Decompress knows BC1–BC3 only; a BC4
// channel block is BC3's alpha block (DFS 1.3), so BC4 and BC5 go through its BC3 alpha path.
std::array<uint8_t, 64> squish_decode(const std::string& format, const uint8_t* b) {
  std::array<uint8_t, 64> rgba{};
  if (format == "BC1" || format == "BC2" || format == "BC3") {
    const int flags = format == "BC1"   ? squish::kDxt1
                      : format == "BC2" ? squish::kDxt3
                                        : squish::kDxt5;
    squish::Decompress(rgba.data(), b, flags);
    return rgba;
  }
  for (int channel = 0; channel < (format == "BC5" ? 2 : 1); ++channel) {
    std::array<uint8_t, 16> bc3{};
    std::copy_n(b + 8 * static_cast<size_t>(channel), 8, bc3.begin());
    std::array<uint8_t, 64> out{};
    squish::Decompress(out.data(), bc3.data(), squish::kDxt5);
    for (size_t t = 0; t < 16; ++t) rgba[4 * t + static_cast<size_t>(channel)] = out[4 * t + 3];
  }
  return rgba;
}

TEST(BcDecoders, EveryBlockOfRealTexturesMatchesSquish) {
  // Encoded with squish's range fit (fast; BC1 tries both the three- and four-colour modes).
  const std::array<int, 5> flags = {squish::kDxt1, squish::kDxt3, squish::kDxt5, squish::kBc4,
                                    squish::kBc5};
  const auto cases = format_cases();
  for (const std::string& path : kTextures) {
    const Rgba8Image img = load_rgba(path);
    ASSERT_GT(img.width, 0) << "cannot read " << path;
    for (size_t f = 0; f < cases.size(); ++f) {
      const FormatCase& fc = cases[f];
      Tally tally;
      std::array<uint8_t, 16> blk{};
      for (int by = 0; by < img.height / 4; ++by) {
        for (int bx = 0; bx < img.width / 4; ++bx) {
          const auto src = img.block(bx, by);
          squish::Compress(src.data(), blk.data(), flags[f] | squish::kColourRangeFit);
          count_mode(tally, fc.name, blk.data());
          compare_block(tally, fc.decode(blk.data()), squish_decode(fc.name, blk.data()),
                        fc.channels, fc.model(blk.data()),
                        static_cast<size_t>(by) * static_cast<size_t>(img.width / 4) +
                            static_cast<size_t>(bx));
        }
      }
      report(fc.name, "squish", path, tally);
    }
  }
}

// Collects NVTT's compressed output (no header) in memory.
class NvttSink : public nvtt::OutputHandler {
 public:
  std::vector<uint8_t> bytes;
  void beginImage(int, int, int, int, int, int) override {}
  bool writeData(const void* data, int size) override {
    const auto* p = static_cast<const uint8_t*>(data);
    bytes.insert(bytes.end(), p, p + size);
    return true;
  }
};

std::vector<uint8_t> nvtt_compress(const Rgba8Image& img, nvtt::Format format) {
  std::vector<uint8_t> bgra(static_cast<size_t>(img.width) * static_cast<size_t>(img.height) * 4);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const auto s =
          static_cast<size_t>(y) * static_cast<size_t>(img.stride) + 4 * static_cast<size_t>(x);
      const auto d =
          (static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)) * 4;
      bgra[d] = img.px[s + 2];
      bgra[d + 1] = img.px[s + 1];
      bgra[d + 2] = img.px[s];
      bgra[d + 3] = img.px[s + 3];
    }
  }
  nvtt::InputOptions in;
  in.setTextureLayout(nvtt::TextureType_2D, img.width, img.height);
  in.setMipmapData(bgra.data(), img.width, img.height);
  in.setMipmapGeneration(false);
  nvtt::CompressionOptions co;
  co.setFormat(format);
  co.setQuality(nvtt::Quality_Fastest);
  NvttSink sink;
  nvtt::OutputOptions out;
  out.setOutputHandler(&sink);
  out.setOutputHeader(false);
  nvtt::Compressor().process(in, co, out);
  return sink.bytes;
}

// libnvimage's decoding of one block, as RGBA8.
std::array<uint8_t, 64> nvimage_decode(const char* format, const uint8_t* b) {
  nv::ColorBlock cb;
  if (std::string(format) == "BC1") {
    nv::BlockDXT1 blk{};
    std::copy_n(b, 8, blk.bytes.begin());
    blk.decodeBlock(&cb);
  } else if (std::string(format) == "BC2") {
    nv::BlockDXT3 blk{};
    std::copy_n(b, 16, blk.bytes.begin());
    blk.decodeBlock(&cb);
  } else if (std::string(format) == "BC3") {
    nv::BlockDXT5 blk{};
    std::copy_n(b, 16, blk.bytes.begin());
    blk.decodeBlock(&cb);
  } else if (std::string(format) == "BC4") {
    nv::BlockATI1 blk{};
    std::copy_n(b, 8, blk.bytes.begin());
    blk.decodeBlock(&cb);
  } else {
    nv::BlockATI2 blk{};
    std::copy_n(b, 16, blk.bytes.begin());
    blk.decodeBlock(&cb);
  }
  std::array<uint8_t, 64> rgba{};
  for (size_t t = 0; t < 16; ++t) {
    rgba[4 * t] = cb.bgra[4 * t + 2];
    rgba[4 * t + 1] = cb.bgra[4 * t + 1];
    rgba[4 * t + 2] = cb.bgra[4 * t];
    rgba[4 * t + 3] = cb.bgra[4 * t + 3];
  }
  return rgba;
}

TEST(BcDecoders, EveryBlockOfRealTexturesMatchesNvimage) {
  const std::array<nvtt::Format, 5> formats = {
      nvtt::Format_BC1a, nvtt::Format_BC2, nvtt::Format_BC3, nvtt::Format_BC4, nvtt::Format_BC5};
  const auto cases = format_cases();
  for (const std::string& path : kTextures) {
    const Rgba8Image img = load_rgba(path);
    ASSERT_GT(img.width, 0) << "cannot read " << path;
    for (size_t f = 0; f < cases.size(); ++f) {
      const FormatCase& fc = cases[f];
      const std::vector<uint8_t> data = nvtt_compress(img, formats[f]);
      const size_t blocks =
          static_cast<size_t>(img.width / 4) * static_cast<size_t>(img.height / 4);
      ASSERT_EQ(data.size(), blocks * static_cast<size_t>(fc.bytes)) << fc.name << " " << path;
      Tally tally;
      for (size_t i = 0; i < blocks; ++i) {
        const uint8_t* b = data.data() + i * static_cast<size_t>(fc.bytes);
        count_mode(tally, fc.name, b);
        compare_block(tally, fc.decode(b), nvimage_decode(fc.name, b), fc.channels, fc.model(b), i);
      }
      report(fc.name, "nvimage", path, tally);
    }
  }
}

TEST(BcDecoders, Bc4AndBc5UnormAndSnormMatchMesaOnRandomBlocks) {
  // No library on the system decodes SNORM RGTC; Mesa does (through the EGL peer). softpipe
  // reads back through Mesa's C decoder, whose 8-bit arithmetic the models state; llvmpipe's
  // read-back does not follow that arithmetic, so it is not the reference here.
  // Random blocks, with -128 endpoints and the -127/-128 pair forced into some of them.
  const MesaPeer mesa(MesaDriver::Softpipe);
  if (!mesa.available()) GTEST_SKIP() << mesa.why_not();
  std::mt19937 rng(5);
  constexpr int kRow = 64;  // blocks per row and rows: 4096 blocks
  for (const bool two : {false, true}) {
    for (const bool snorm : {false, true}) {
      const size_t bytes = two ? 16 : 8;
      std::vector<uint8_t> blocks(size_t{kRow} * kRow * bytes);
      for (auto& x : blocks) x = static_cast<uint8_t>(rng());
      for (size_t i = 0; i < 48; ++i) {
        uint8_t* b = blocks.data() + 16 * bytes * i;  // every 16th block
        b[0] = i % 3 == 1 ? 0x81 : 0x80;
        b[1] = i % 3 == 0 ? b[1] : 0x80;
      }
      const uint32_t format = two ? (snorm ? 0x8DBE : 0x8DBD) : (snorm ? 0x8DBC : 0x8DBB);
      const MesaImage img =
          mesa.decode_blocks(format, 4 * kRow, 4 * kRow, blocks, snorm ? 0x1400 : 0x1401);
      Bc4Decoder::Config c4;
      c4.snorm = snorm;
      Bc5Decoder::Config c5;
      c5.snorm = snorm;
      Tally tally;
      for (size_t i = 0; i < size_t{kRow} * kRow; ++i) {
        const uint8_t* b = blocks.data() + bytes * i;
        const DecodedBlock d = two ? Bc5Decoder(c5).decode(std::span<const uint8_t, 16>(b, 16))
                                   : Bc4Decoder(c4).decode(std::span<const uint8_t, 8>(b, 8));
        BlockModel m{};
        m[0] = snorm ? bc4_snorm_mesa_model(b) : bc4_model(b);
        if (two) m[1] = snorm ? bc4_snorm_mesa_model(b + 8) : bc4_model(b + 8);
        std::array<uint8_t, 64> ref{};
        for (size_t t = 0; t < 16; ++t) {
          const size_t x = 4 * (i % kRow) + t % 4;
          const size_t y = 4 * (i / kRow) + t / 4;
          std::copy_n(img.rgba.begin() + static_cast<std::ptrdiff_t>((y * 4 * kRow + x) * 4), 4,
                      ref.begin() + static_cast<std::ptrdiff_t>(4 * t));
        }
        compare_block(tally, d, ref, two ? std::vector<int>{0, 1} : std::vector<int>{0}, m, i);
      }
      report(two ? (snorm ? "BC5s" : "BC5") : (snorm ? "BC4s" : "BC4"), "Mesa", "random blocks",
             tally);
    }
  }
}

// BC1-BC3 against Mesa's S3TC decoder (softpipe, through the EGL peer): every block of the real
// textures as squish encodes them (range fit, so BC1 has three- and four-colour blocks) and
// 4096 random blocks per format, which reach both BC1 modes in equal shares. Mesa's arithmetic
// on the 8-bit expanded endpoints is squish's (bit replication, truncating division), so the
// same per-code model states what Mesa must return.
TEST(BcDecoders, Bc1ToBc3MatchMesaOnRealTexturesAndRandomBlocks) {
  const MesaPeer mesa(MesaDriver::Softpipe);
  if (!mesa.available()) GTEST_SKIP() << mesa.why_not();
  const auto cases = format_cases();
  // GL_COMPRESSED_RGBA_S3TC_DXT1/3/5_EXT.
  const std::array<uint32_t, 3> gl = {0x83F1, 0x83F2, 0x83F3};
  const std::array<int, 3> flags = {squish::kDxt1, squish::kDxt3, squish::kDxt5};
  std::mt19937 rng(11);
  for (size_t f = 0; f < 3; ++f) {
    const FormatCase& fc = cases[f];
    const auto bytes = static_cast<size_t>(fc.bytes);
    // One texture's blocks, then random ones, each set decoded by Mesa in one upload.
    std::vector<std::pair<std::string, std::vector<uint8_t>>> sets;
    int bw = 0, bh = 0;
    {
      const Rgba8Image img = load_rgba(kTextures.front());
      ASSERT_GT(img.width, 0) << "cannot read " << kTextures.front();
      bw = img.width / 4;
      bh = img.height / 4;
      std::vector<uint8_t> data(static_cast<size_t>(bw) * static_cast<size_t>(bh) * bytes);
      for (int by = 0; by < bh; ++by) {
        for (int bx = 0; bx < bw; ++bx) {
          const auto src = img.block(bx, by);
          squish::Compress(src.data(),
                           data.data() + (static_cast<size_t>(by) * static_cast<size_t>(bw) +
                                          static_cast<size_t>(bx)) *
                                             bytes,
                           flags[f] | squish::kColourRangeFit);
        }
      }
      sets.emplace_back(kTextures.front(), std::move(data));
    }
    std::vector<uint8_t> random(size_t{64} * 64 * bytes);
    for (auto& x : random) x = static_cast<uint8_t>(rng());
    sets.emplace_back("random blocks", std::move(random));
    for (const auto& [name, blocks] : sets) {
      const int row = name == "random blocks" ? 64 : bw;
      const int rows = name == "random blocks" ? 64 : bh;
      const MesaImage img = mesa.decode_blocks(gl[f], 4 * row, 4 * rows, blocks);
      Tally tally;
      for (size_t i = 0; i < blocks.size() / bytes; ++i) {
        const uint8_t* b = blocks.data() + bytes * i;
        std::array<uint8_t, 64> ref{};
        for (size_t t = 0; t < 16; ++t) {
          const size_t x = 4 * (i % static_cast<size_t>(row)) + t % 4;
          const size_t y = 4 * (i / static_cast<size_t>(row)) + t / 4;
          std::copy_n(img.rgba.begin() +
                          static_cast<std::ptrdiff_t>((y * 4 * static_cast<size_t>(row) + x) * 4),
                      4, ref.begin() + static_cast<std::ptrdiff_t>(4 * t));
        }
        count_mode(tally, fc.name, b);
        compare_block(tally, fc.decode(b), ref, fc.channels, fc.model(b), i);
      }
      report(fc.name, "Mesa", name, tally);
    }
  }
}

}  // namespace
}  // namespace texsim
