// Draw traces (traces/DRAWS.md): round trip, and every corruption is a clear InputError naming
// the record (and the frame and draw) and what is wrong. Corrupt files are made by patching a
// written file at offsets computed from DRAWS.md, with the CRCs recomputed where the point is
// to reach the check behind them.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "testbench/lib/temp_dir.h"
#include "traces/draw_trace.h"
#include "traces/trace_tools.h"

namespace texsim {
namespace {

DrawTexture make_texture(uint32_t id, uint32_t w, uint32_t h, uint32_t levels) {
  DrawTexture t;
  t.id = id;
  t.width = w;
  t.height = h;
  t.name = "tex " + std::to_string(id);
  for (uint32_t l = 0; l < levels; ++l) {
    std::vector<uint8_t> px(draw_level_bytes(w, h, l));
    for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<uint8_t>(i * 7 + l + id);
    t.levels.push_back(px);
  }
  return t;
}

Draw make_draw(uint32_t tex0, int units) {
  Draw d;
  d.state.viewport_w = 640;
  d.state.viewport_h = 480;
  d.state.depth_test = true;
  d.state.depth_func = 0x0203;
  d.state.blend = true;
  d.state.blend_src = 0x0306;
  d.state.blend_dst = 0;
  d.state.cull = true;
  d.state.cull_face = 0x0404;
  d.state.polygon_offset = true;
  d.state.offset_factor = -1;
  d.state.offset_units = -2;
  d.vertex_count = 4;
  d.position = {-1, -1, 0.5f, 1, 1, -1, 0.5f, 1, 1, 1, 0.25f, 2, -1, 1, 0, 1};
  for (int u = 0; u < units; ++u) {
    DrawUnit unit;
    unit.unit = static_cast<uint32_t>(u);
    unit.texture = tex0 + static_cast<uint32_t>(u);
    unit.wrap_s = 0x812F;
    unit.max_anisotropy = 4;
    unit.lod_bias = -0.5f;
    unit.env_mode = u == 0 ? 0x2100 : 0x0104;
    d.units.push_back(unit);
    d.st[u] = {0, 0, 1, 0, 1, 1, 0, 1.5f};
  }
  d.has_color = true;
  d.color = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 128, 1, 2, 3, 4};
  d.indices = {0, 1, 2, 0, 2, 3};
  return d;
}

DrawTrace sample() {
  DrawTrace t;
  t.source = "test capture";
  t.textures = {make_texture(0, 16, 8, 5), make_texture(1, 4, 4, 1)};
  DrawFrame f0{7, {make_draw(0, 2), make_draw(1, 1)}, {{"glScissor", 2}, {"glClear", 1}}};
  DrawFrame f1{9, {make_draw(0, 0)}, {}};
  t.frames = {f0, f1};
  return t;
}

std::vector<uint8_t> slurp(const std::string& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}
void spit(const std::string& p, const std::vector<uint8_t>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

// Offsets of the records of a file (DRAWS.md: tag, u32 length, u32 CRC, payload).
struct Rec {
  size_t at;
  std::string tag;
  uint32_t len;
};
std::vector<Rec> records(const std::vector<uint8_t>& b) {
  uint32_t src = 0;
  std::memcpy(&src, b.data() + 12, 4);
  size_t at = 16 + src + 4;
  std::vector<Rec> out;
  while (at + 12 <= b.size()) {
    uint32_t len = 0;
    std::memcpy(&len, b.data() + at + 4, 4);
    out.push_back({at, std::string(reinterpret_cast<const char*>(b.data() + at), 4), len});
    at += 12 + len;
  }
  return out;
}
void fix_crc(std::vector<uint8_t>& b, const Rec& r) {
  const auto crc = static_cast<uint32_t>(crc32(0, b.data() + r.at + 12, r.len));
  std::memcpy(b.data() + r.at + 8, &crc, 4);
}
template <class T>
void poke(std::vector<uint8_t>& b, size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);
}
const Rec& find(const std::vector<Rec>& rs, const std::string& tag, int nth = 0) {
  for (const Rec& r : rs) {
    if (r.tag == tag && nth-- == 0) return r;
  }
  throw std::runtime_error("no record " + tag);
}

std::string read_error(const std::string& path) {
  try {
    read_draw_trace(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class DrawTraceTest : public ::testing::Test {
 protected:
  TempDir dir{"draw_trace"};
  std::string path = dir.file("a.draws");
  void SetUp() override { write_draw_trace(path, sample()); }
  // Patches the good file with f, fixing the CRC of the record named (or none), and returns
  // the reader's error.
  template <class F>
  std::string corrupt(F f) {
    std::vector<uint8_t> b = slurp(path);
    f(b);
    const std::string bad = dir.file("bad.draws");
    spit(bad, b);
    return read_error(bad);
  }
};

TEST_F(DrawTraceTest, RoundTripKeepsEverything) {
  const DrawTrace a = sample();
  const DrawTrace b = read_draw_trace(path);
  EXPECT_EQ(b.source, a.source);
  ASSERT_EQ(b.textures.size(), 2u);
  EXPECT_EQ(b.textures[0].levels, a.textures[0].levels);
  EXPECT_EQ(b.textures[0].levels.size(), 5u);
  EXPECT_EQ(b.textures[0].levels[4].size(), 4u);  // 1x1 texel at level 4 of 16x8
  EXPECT_EQ(b.textures[1].name, "tex 1");
  ASSERT_EQ(b.frames.size(), 2u);
  EXPECT_EQ(b.frames[0].number, 7u);
  EXPECT_EQ(b.frames[1].number, 9u);
  EXPECT_EQ(b.frames[0].uninterpreted, a.frames[0].uninterpreted);
  ASSERT_EQ(b.frames[0].draws.size(), 2u);
  const Draw& d = b.frames[0].draws[0];
  const Draw& e = a.frames[0].draws[0];
  EXPECT_EQ(d.position, e.position);
  EXPECT_EQ(d.st[0], e.st[0]);
  EXPECT_EQ(d.st[1], e.st[1]);
  EXPECT_EQ(d.color, e.color);
  EXPECT_EQ(d.indices, e.indices);
  ASSERT_EQ(d.units.size(), 2u);
  EXPECT_EQ(d.units[1].texture, 1u);
  EXPECT_EQ(d.units[1].env_mode, 0x0104u);
  EXPECT_EQ(d.units[0].wrap_s, 0x812Fu);
  EXPECT_FLOAT_EQ(d.units[0].max_anisotropy, 4);
  EXPECT_FLOAT_EQ(d.units[0].lod_bias, -0.5f);
  EXPECT_TRUE(d.state.depth_test && d.state.blend && d.state.cull && d.state.polygon_offset);
  EXPECT_FALSE(d.state.alpha_test);
  EXPECT_EQ(d.state.blend_src, 0x0306u);
  EXPECT_EQ(d.state.cull_face, 0x0404u);
  EXPECT_FLOAT_EQ(d.state.offset_units, -2);
  EXPECT_TRUE(b.frames[1].draws[0].units.empty());
}

TEST_F(DrawTraceTest, EveryTruncationIsAnError) {
  const std::vector<uint8_t> b = slurp(path);
  for (size_t n = 0; n < b.size(); n += (n < 200 ? 1 : 37)) {
    std::vector<uint8_t> cut(b.begin(), b.begin() + static_cast<ptrdiff_t>(n));
    spit(dir.file("cut.draws"), cut);
    const std::string err = read_error(dir.file("cut.draws"));
    EXPECT_NE(err, "") << "cut at " << n;
  }
  const std::string err = read_error(dir.file("cut.draws"));
  EXPECT_NE(err.find("truncated"), std::string::npos) << err;
}

TEST_F(DrawTraceTest, BadChecksumsAreErrors) {
  const auto rs = records(slurp(path));
  EXPECT_NE(corrupt([&](auto& b) { b[find(rs, "DRAW").at + 40] ^= 1; }).find("CRC mismatch"),
            std::string::npos);
  EXPECT_NE(corrupt([&](auto& b) {
              b[12] ^= 0;
              b[17] ^= 1;
            }).find("header"),
            std::string::npos);
  const std::string e = corrupt([&](auto& b) { b[find(rs, "TEXR").at + 40] ^= 1; });
  EXPECT_NE(e.find("record 0 at byte"), std::string::npos) << e;
  EXPECT_NE(e.find("CRC mismatch"), std::string::npos) << e;
}

TEST_F(DrawTraceTest, HugeCountsAreRefusedBeforeAllocating) {
  const auto rs = records(slurp(path));
  std::string e =
      corrupt([&](auto& b) { poke<uint32_t>(b, find(rs, "DRAW").at + 4, 0xFFFFFFF0u); });
  EXPECT_NE(e.find("exceeds the limit"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "DRAW");
    poke<uint32_t>(b, r.at + 12 + 72, 0x7FFFFFFFu);  // vertex count
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("frame 7, draw 0"), std::string::npos) << e;
  EXPECT_NE(e.find("vertices, more than"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "DRAW");
    poke<uint32_t>(b, r.at + 12 + 76, 7u);  // index count, not a multiple of 3
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("not a multiple of 3"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "TEXR");
    poke<uint32_t>(b, r.at + 12 + 4, 100000u);  // width
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("outside 1..4096"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "TEXR");
    poke<uint32_t>(b, r.at + 12 + 16, 9u);  // levels of 16x8: at most 5
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("mip levels"), std::string::npos) << e;
}

TEST_F(DrawTraceTest, IndicesAndTextureIdsOutOfRangeAreErrors) {
  const auto rs = records(slurp(path));
  // Draw 0 of frame 7: 64 + 16 bytes of state and counts, 2 units of 36 bytes, 4 vertices of
  // 16 + 16 + 4 bytes, then the indices.
  const size_t idx = 12 + 80 + 72 + 4 * 36;
  std::string e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "DRAW");
    poke<uint32_t>(b, r.at + idx + 8, 4u);
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("frame 7, draw 0"), std::string::npos) << e;
  EXPECT_NE(e.find("index 2 is 4"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "DRAW");
    poke<uint32_t>(b, r.at + 12 + 80 + 36 + 4, 5u);  // unit entry 1's texture id
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("texture id 5 has no texture record"), std::string::npos) << e;
}

TEST_F(DrawTraceTest, NanVertexNamesFrameAndDraw) {
  const auto rs = records(slurp(path));
  const std::string e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "DRAW", 1);  // frame 7, draw 1
    poke<float>(b, r.at + 12 + 80 + 36 + 24 + 4, std::numeric_limits<float>::quiet_NaN());
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("frame 7, draw 1"), std::string::npos) << e;
  EXPECT_NE(e.find("vertex 1: clip-space position is NaN"), std::string::npos) << e;
  // The writer refuses it too.
  DrawTrace t = sample();
  t.frames[1].draws[0].position[2] = std::numeric_limits<float>::infinity();
  try {
    write_draw_trace(dir.file("inf.draws"), t);
    ADD_FAILURE() << "no error";
  } catch (const InputError& err) {
    EXPECT_NE(std::string(err.what())
                  .find("frame 9, draw 0: vertex 0: clip-space position is "
                        "infinite"),
              std::string::npos)
        << err.what();
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("inf.draws")));
}

TEST_F(DrawTraceTest, StructureErrors) {
  const auto rs = records(slurp(path));
  std::string e = corrupt([&](auto& b) { std::memcpy(b.data(), "TEXSIMTR", 8); });
  EXPECT_NE(e.find("bad magic"), std::string::npos) << e;
  e = corrupt([&](auto& b) { poke<uint32_t>(b, 8, 2u); });
  EXPECT_NE(e.find("unknown version 2"), std::string::npos) << e;
  e = corrupt([&](auto& b) { std::memcpy(b.data() + find(rs, "FRAM").at, "XXXX", 4); });
  EXPECT_NE(e.find("unknown record tag"), std::string::npos) << e;
  e = corrupt([&](auto& b) {  // frame numbers must increase: 9 -> 3
    const Rec& r = find(rs, "FRAM", 1);
    poke<uint32_t>(b, r.at + 12, 3u);
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("numbers must increase"), std::string::npos) << e;
  e = corrupt([&](auto& b) {  // frame end claims 3 draws
    const Rec& r = find(rs, "FEND");
    poke<uint32_t>(b, r.at + 12, 3u);
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("frame end counts 3 draws, the frame has 2"), std::string::npos) << e;
  e = corrupt([&](auto& b) {
    const Rec& r = find(rs, "TEND");
    poke<uint64_t>(b, r.at + 12 + 8, 99u);
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("records lost"), std::string::npos) << e;
  e = corrupt([&](auto& b) { b.push_back(0); });
  EXPECT_NE(e.find("unexpected bytes after the end marker"), std::string::npos) << e;
  e = corrupt([&](auto& b) {  // an unknown depth function
    const Rec& r = find(rs, "DRAW");
    poke<uint32_t>(b, r.at + 12 + 28, 0x0300u);
    fix_crc(b, r);
  });
  EXPECT_NE(e.find("depth function 0x0300 is not known"), std::string::npos) << e;
}

TEST_F(DrawTraceTest, WriterRefusesBadInputAndLeavesNoFile) {
  DrawTrace t = sample();
  t.frames[0].draws[0].indices[1] = 9;
  EXPECT_THROW(write_draw_trace(dir.file("x.draws"), t), InputError);
  t = sample();
  t.textures[1].id = 0;  // twice
  EXPECT_THROW(write_draw_trace(dir.file("x.draws"), t), InputError);
  t = sample();
  t.textures[0].levels[2].pop_back();
  EXPECT_THROW(write_draw_trace(dir.file("x.draws"), t), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.draws")));
}

TEST_F(DrawTraceTest, TraceInfoSummarisesFramesAndTextures) {
  std::ostringstream out;
  EXPECT_EQ(trace_info(path, out), 0);  // `texsim trace info` recognises the magic
  const std::string s = out.str();
  EXPECT_NE(s.find("source:     test capture"), std::string::npos) << s;
  EXPECT_NE(s.find("frame 7: 2 draws, 8 vertices, 4 triangles, 3 texture bindings; 3 calls not "
                   "interpreted: glClear 1, glScissor 2"),
            std::string::npos)
      << s;
  EXPECT_NE(s.find("frame 9: 1 draws, 4 vertices, 2 triangles"), std::string::npos) << s;
  EXPECT_NE(s.find("textures:   2 (748 bytes of texels)"), std::string::npos) << s;
  EXPECT_NE(s.find("id 0  16x8  5 levels  684 bytes  tex 0"), std::string::npos) << s;
}

}  // namespace
}  // namespace texsim
