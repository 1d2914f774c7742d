// Compressed textures in a run: where the decoder sits ([pipeline] decompress) changes what the
// caches hold and the bytes they move, never the image; the decompressor reads exactly the
// blocks a line of decoded texels needs; bad compress keys name the scene's line.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/texture/decode/block_decoder.h"
#include "blocks/texture/decode/compressed_texture.h"
#include "pipeline/app/run.h"
#include "pipeline/image_io/dds_file.h"
#include "pipeline/image_io/etc_encoder.h"
#include "pipeline/image_io/ktx_file.h"
#include "pipeline/image_io/squish_encoder.h"
#include "pipeline/texture/block_decompressor.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

// A level-0-only texture of w × h made of random ETC2 RGB8 blocks.
Texture random_etc2(int w, int h, uint32_t seed) {
  auto blocks = std::make_shared<Texture::Blocks>();
  blocks->format = CompressedFormat::Etc2Rgb8;
  std::mt19937 rng(seed);
  std::vector<uint8_t> bytes(static_cast<size_t>((w + 3) / 4) * static_cast<size_t>((h + 3) / 4) *
                             8);
  for (auto& b : bytes) b = static_cast<uint8_t>(rng());
  blocks->levels.push_back(bytes);
  return texture_from_blocks("etc", blocks, {w}, {h}, nullptr);
}

TEST(CompressedTexture, StoreHoldsEveryBlockDecoded) {
  const Texture t = random_etc2(10, 6, 1);  // partial edge blocks
  ASSERT_TRUE(t.compressed());
  EXPECT_EQ(t.bytes_per_texel(), 4);
  const std::vector<uint8_t>& b = t.blocks()->levels[0];
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 10; ++x) {
      const size_t block = static_cast<size_t>((y / 4) * 3 + x / 4) * 8;
      const DecodedBlock d = decode_block(CompressedFormat::Etc2Rgb8, b.data() + block);
      ASSERT_EQ(t.texel(0, x, y), d.at(x % 4, y % 4)) << x << "," << y;
    }
  }
  EXPECT_EQ(&t.reference(), &t);  // blocks with no source: their own truth
}

// Counts every read the level behind the decompressor gets.
struct CountingMemory final : LineMemory {
  std::vector<uint64_t> addrs;
  uint64_t read_line(uint64_t now, uint64_t addr, uint32_t, int) override {
    addrs.push_back(addr);
    return now + 10;
  }
};

TEST(BlockDecompressor, ReadsTheBlocksOfTheLinesTexelsOnce) {
  for (const TexelLayout layout : {TexelLayout::Tiled4x4, TexelLayout::Linear}) {
    TextureSet set;
    set.add(random_etc2(64, 64, 2));
    set.place(layout);
    const Texture& t = set[0];
    CountingMemory dram;
    BlockDecompressor d(&dram, &set, [](CompressedFormat) {
      return BlockDecompressor::Timing{3, 2};
    });
    // Line 5 of the decoded texels (64-byte lines, 16 texels of 4 bytes).
    const uint64_t line = t.base() + uint64_t{5} * 64;
    const uint64_t ready = d.read_line(100, line, 64, 0);
    // The blocks the line's texels need, found texel by texel from the texture's addresses.
    std::vector<uint64_t> want;
    for (int y = 0; y < 64; ++y) {
      for (int x = 0; x < 64; ++x) {
        if (t.address(0, x, y) / 64 != line / 64) continue;
        const uint64_t b = t.block_address(0, x, y) / 64 * 64;
        if (std::find(want.begin(), want.end(), b) == want.end()) want.push_back(b);
      }
    }
    EXPECT_EQ(dram.addrs, want) << to_string(layout);
    // Tiled: a line is one 4x4 tile, one block; linear: 16 texels of a row, 4 blocks.
    const uint64_t blocks = layout == TexelLayout::Tiled4x4 ? 1 : 4;
    EXPECT_EQ(d.stats().blocks, blocks);
    EXPECT_EQ(ready, 100 + 10 + 3 + 2 * (blocks - 1));  // the DRAM, then the blocks in turn
  }
}

struct Outcome {
  std::unique_ptr<RunCapture> capture = std::make_unique<RunCapture>();
  nlohmann::json report;
};

const char* kScene = R"([output]
width = 64
height = 48
[camera]
position = [0.0, 1.0, 0.0]
look_at = [0.0, 0.2, -6.0]
fov_y = 60.0
[textures.floor]
source = "procedural:checker?size=64&cells=8"
compress = { format = "bc1_rgb", encoder = "squish", quality = "range" }
[materials.m]
texture = "floor"
filter = { mode = "trilinear", address = "wrap" }
[[planes]]
material = "m"
origin = [-8.0, 0.0, -0.5]
edge_u = [16.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -16.0]
uv_scale = [4.0, 4.0]
)";

// A run of the scene `text`, or with `trace` set, of that trace's fragments and textures.
Outcome run_scene(const std::string& text, const TempDir& dir, std::vector<std::string> sets,
                  const std::string& trace = "") {
  const std::string path = dir.file("s.toml");
  std::ofstream(path) << text;
  RunOptions opt;
  opt.scene = path;
  opt.trace = trace;
  opt.reference = "none";
  opt.threads = 1;
  opt.out = dir.file(trace.empty() ? "out" : "out_trace");
  opt.overrides = std::move(sets);
  Outcome o;
  o.capture->write_outputs = true;
  opt.capture = o.capture.get();
  std::ostringstream log;
  run_simulation(opt, log);
  std::ifstream in(opt.out + "/report.json");
  o.report = nlohmann::json::parse(in);
  return o;
}

TEST(DecompressPlacement, ChangesTheCachesBytesNotTheImage) {
  TempDir dir("decompress");
  const Outcome after_l1 = run_scene(kScene, dir, {"pipeline.decompress=\"after_l1\""});
  const Outcome before_l1 = run_scene(kScene, dir, {"pipeline.decompress=\"before_l1\""});
  const Outcome after_l2 =
      run_scene(kScene, dir, {"pipeline.decompress=\"after_l2\"", "pipeline.l2.size_bytes=65536"});
  EXPECT_EQ(before_l1.capture->image->rgb, after_l1.capture->image->rgb);
  EXPECT_EQ(after_l2.capture->image->rgb, after_l1.capture->image->rgb);
  const auto& a = after_l1.report;
  const auto& b = before_l1.report;
  EXPECT_EQ(a["decompress"]["placement"], "after_l1");
  EXPECT_EQ(b["decompress"]["placement"], "before_l1");
  EXPECT_GT(a["decompress"]["blocks_by_format"]["bc1_rgb"].get<uint64_t>(), 0u);
  EXPECT_TRUE(a["blocks"].contains("decode.bc1_rgb")) << a["blocks"].dump();
  // Blocks in the L1 (8 bytes per 16 texels) against decoded texels (4 bytes each): the
  // compressed L1 misses less and fills fewer bytes; DRAM moves blocks either way.
  EXPECT_LT(a["cache"]["misses"].get<uint64_t>(), b["cache"]["misses"].get<uint64_t>());
  EXPECT_LT(a["cache"]["fill_bytes"].get<uint64_t>(), b["cache"]["fill_bytes"].get<uint64_t>());
  EXPECT_EQ(b["decompress"]["decoded_lines"], b["cache"]["misses"]);
  // After the L2: the L2 holds blocks, the L1 decoded texels (the L1 as before_l1's).
  EXPECT_EQ(after_l2.report["cache"]["misses"], b["cache"]["misses"]);
  EXPECT_EQ(after_l2.report["decompress"]["decoded_lines"], b["cache"]["misses"]);
}

TEST(DecompressPlacement, ADdsFileIsATextureOfItsBlocks) {
  TempDir dir("decompress_dds");
  Rgba8Image img;
  img.width = 32;
  img.height = 16;
  for (int i = 0; i < 32 * 16; ++i) {
    img.rgba.insert(img.rgba.end(), {static_cast<uint8_t>(i * 7), static_cast<uint8_t>(i),
                                     static_cast<uint8_t>(255 - i / 2), 255});
  }
  const EncodedLevel e = squish_encode(img, FileBlockFormat::Bc1Unorm, SquishFit::Range);
  write_dds_file(dir.file("t.dds"), as_compressed_image(e));
  std::string scene = kScene;
  scene.replace(scene.find("procedural:checker?size=64&cells=8"),
                std::string("procedural:checker?size=64&cells=8").size(), "t.dds");
  scene.erase(scene.find("compress ="),
              scene.find('\n', scene.find("compress =")) - scene.find("compress ="));
  const Outcome o = run_scene(scene, dir, {});
  EXPECT_GT(o.report["decompress"]["blocks_by_format"]["bc1_rgba"].get<uint64_t>(), 0u);
}

std::string scene_error(const std::string& compress) {
  std::string scene = kScene;
  const size_t at = scene.find("compress =");
  scene.replace(at, scene.find('\n', at) - at, compress);
  try {
    TempDir dir("decompress_err");
    (void)run_scene(scene, dir, {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DecompressPlacement, BadKeysNameTheSceneLine) {
  const std::string unknown = scene_error("compress = { format = \"bc9\" }");
  EXPECT_NE(unknown.find("s.toml:10:"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown compressed format 'bc9'"), std::string::npos) << unknown;
  const std::string wrong = scene_error("compress = { format = \"bc4\", encoder = \"squish\" }");
  EXPECT_NE(wrong.find("encoder 'squish' cannot make 'bc4'"), std::string::npos) << wrong;
  const std::string none = scene_error("compress = { format = \"eac_r11_snorm\" }");
  EXPECT_NE(none.find("no encoder makes 'eac_r11_snorm'"), std::string::npos) << none;
  const std::string quality =
      scene_error("compress = { format = \"astc_4x4\", quality = \"slow\" }");
  EXPECT_NE(quality.find("unknown astcenc quality 'slow'"), std::string::npos) << quality;
  const std::string both = scene_error("compress = { format = \"bc1_rgb\" }\nformat = \"r8\"");
  EXPECT_NE(both.find("either compressed or stored in a 'format'"), std::string::npos) << both;
  const std::string l2 = [] {
    try {
      TempDir dir("decompress_l2");
      (void)run_scene(kScene, dir, {"pipeline.decompress=\"after_l2\""});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  }();
  EXPECT_NE(l2.find("\"after_l2\" needs an L2"), std::string::npos) << l2;
}

// ETC2, EAC and BC7 are encoded by texsim's own encoders (their default), named in the
// report's textures[]; a KTX file of ETC2 blocks is a texture of its blocks.
TEST(DecompressPlacement, TexsimEncodersAndKtxFilesMakeTextures) {
  TempDir dir("decompress_texsim");
  const auto with = [](const std::string& compress) {
    std::string scene = kScene;
    const size_t at = scene.find("compress =");
    scene.replace(at, scene.find('\n', at) - at, compress);
    return scene;
  };
  for (const auto& [format, label] : std::vector<std::pair<std::string, std::string>>{
           {"etc2_rgba8", "(etc2_rgba8,texsim) [texsim etc encoder (ETC2_RGBA8, normal)]"},
           {"eac_rg11", "[texsim etc encoder (EAC_RG11_UNORM, normal)]"},
           {"bc7", "(bc7,texsim) [texsim bc7 encoder (modes 6 and 5, normal)]"}}) {
    const Outcome o = run_scene(with("compress = { format = \"" + format + "\" }"), dir, {});
    EXPECT_GT(o.report["decompress"]["blocks_by_format"][format].get<uint64_t>(), 0u) << format;
    const std::string t = o.report["textures"][0].get<std::string>();
    EXPECT_NE(t.find(label), std::string::npos) << t;
  }
  const std::string fast = scene_error("compress = { format = \"bc7\", quality = \"slow\" }");
  EXPECT_NE(fast.find("unknown texsim quality 'slow' (one of fast, normal)"), std::string::npos)
      << fast;
  Rgba8Image img{32, 16, {}};
  for (int i = 0; i < 32 * 16; ++i) {
    img.rgba.insert(img.rgba.end(), {static_cast<uint8_t>(i * 7), static_cast<uint8_t>(i),
                                     static_cast<uint8_t>(255 - i / 2), 255});
  }
  write_ktx_file(dir.file("t.ktx"),
                 as_compressed_image(etc_encode(img, FileBlockFormat::Etc2Rgb8, EtcEffort::Fast)));
  std::string scene = with("");
  scene.replace(scene.find("procedural:checker?size=64&cells=8"),
                std::string("procedural:checker?size=64&cells=8").size(), "t.ktx");
  const Outcome o = run_scene(scene, dir, {});
  EXPECT_GT(o.report["decompress"]["blocks_by_format"]["etc2_rgb8"].get<uint64_t>(), 0u);
  EXPECT_NE(o.report["textures"][0].get<std::string>().find("[file t.ktx (ETC2_RGB8)]"),
            std::string::npos)
      << o.report["textures"][0];
}

// The covered pixels of `img` on its canvas (the buffers of a scene run and a trace run may
// span different parts of it), -1 where no fragment wrote.
std::vector<float> on_canvas(const ImageRgb& img) {
  std::vector<float> out(static_cast<size_t>(img.canvas_width) * img.canvas_height * 3, -1.0f);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const size_t i = static_cast<size_t>(y) * img.width + x;
      if (img.covered[i] == 0) continue;
      const size_t o = (static_cast<size_t>(img.y0 + y) * img.canvas_width + img.x0 + x) * 3;
      for (size_t k = 0; k < 3; ++k) out[o + k] = img.rgb[i * 3 + k];
    }
  }
  return out;
}

// A trace records each texture's storage (version 3): its run converts or encodes the textures
// as the scene run does, so it gives the scene run's image and memory figures.
TEST(DecompressPlacement, ATraceRunStoresTheTexturesAsTheSceneDoes) {
  std::string converted = kScene;
  const size_t at = converted.find("compress =");
  converted.replace(at, converted.find('\n', at) - at, "format = \"rgb565\"");
  for (const std::string& scene : {std::string(kScene), converted}) {
    SCOPED_TRACE(scene.substr(scene.find("[textures")));
    TempDir dir("decompress_trace");
    const std::string path = dir.file("s.toml"), trc = dir.file("t.trc");
    std::ofstream(path) << scene;
    ASSERT_GT(generate_scene_trace(path, trc), 0u);
    const Outcome a = run_scene(scene, dir, {});
    const Outcome b = run_scene(scene, dir, {}, trc);
    EXPECT_EQ(on_canvas(*a.capture->image), on_canvas(*b.capture->image));
    EXPECT_EQ(a.report["fragments"], b.report["fragments"]);
    EXPECT_EQ(a.report["cycles"], b.report["cycles"]);
    for (const char* key : {"cache", "dram", "decompress"}) {
      EXPECT_EQ(a.report.contains(key), b.report.contains(key)) << key;
      if (a.report.contains(key)) {
        EXPECT_EQ(a.report[key], b.report[key]) << key;
      }
    }
    EXPECT_EQ(a.report["blocks"].contains("decode.bc1_rgb"), scene == kScene);
    EXPECT_EQ(b.report["blocks"].contains("decode.bc1_rgb"), scene == kScene);
  }
}

TEST(DecompressPlacement, AnUnknownStorageInATraceNamesTheFileAndTheEntry) {
  TempDir dir("decompress_trace_err");
  const std::string trc = dir.file("t.csv");
  for (const auto& [storage, what] : std::vector<std::pair<std::string, std::string>>{
           {"format=rgb999", "unknown texel format 'rgb999'"},
           {"compress=bc9", "unknown compressed format 'bc9'"},
           {"compress=bc4,squish", "encoder 'squish' cannot make 'bc4'"},
           {"compress=eac_r11_snorm", "no encoder makes 'eac_r11_snorm'"},
           {"compress=astc_4x4,astcenc,slow", "unknown astcenc quality 'slow'"},
           {"compress=bc1_rgb,squish,range,x", "more than FORMAT,ENCODER,QUALITY"}}) {
    std::ofstream(trc) << "# texture 0 floor procedural:checker?size=64&cells=8 64 64 " << storage
                       << "\nframe,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy\n"
                          "0,0,1,1,0,0.5,0.5,0.01,0,0,0.01\n";
    std::string msg;
    try {
      (void)run_scene(kScene, dir, {}, trc);
    } catch (const InputError& e) {
      msg = e.what();
    }
    std::string want = trc;
    want.append(": texture table entry 0 ('floor'): storage '").append(storage).append("'");
    EXPECT_NE(msg.find(want), std::string::npos) << msg;
    EXPECT_NE(msg.find(what), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace texsim
