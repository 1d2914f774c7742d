// A scene's fixed-arithmetic sampler materials through the link: the host sends each
// material's state and texture memory image in CONFIGURE chunks and its fragments in STREAMs
// (rtl_model/link/sampler_link.h) to the virtual board, which runs the Verilated sampler
// (rtl_model/verilator/sampler_rtl_block.h); every colour, level, δ and texel address that
// comes back equals the texture unit's with `filter.arithmetic = "fixed"`, so the pixels the
// board colours are the C++ run's. One texel word changed on the way is caught.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/app/board_sampler.h"
#include "pipeline/app/run.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"
#include "rtl_model/link/hid_transport.h"
#include "rtl_model/link/lerp_link.h"
#include "rtl_model/link/link_host.h"
#include "rtl_model/link/sampler_link.h"
#include "rtl_model/link/virtual_board.h"
#include "rtl_model/verilator/lerp_rtl_block.h"
#include "rtl_model/verilator/sampler_rtl_block.h"

namespace texsim::link {
namespace {

// The materials the RTL sampler covers at its build parameters (fixed arithmetic for them).
bool covered(const MaterialSetup& m, const Texture& tex) {
  if (m.footprint || m.relief || m.lighting || m.coords) return false;
  if (!FixedSampler::covers(m.filter, m.lod, nullptr)) return false;
  const TexelAddressGen::Config d;
  return m.filter.sub_texel_bits == d.sub_texel_bits && m.filter.mipmap_bits == d.mipmap_bits &&
         FixedSampler::covers_texture(tex, nullptr);
}

uint32_t rgba8(const Rgba& c) {
  uint32_t v = 0;
  for (int k = 0; k < 4; ++k) {
    const float x = std::clamp(c[k], 0.0f, 1.0f) * 255.0f;
    v |= static_cast<uint32_t>(std::lrint(x)) << (8 * k);
  }
  return v;
}

struct BoardRun {
  uint64_t fragments = 0, equal = 0, colour_equal = 0;
  uint64_t configure_messages = 0, board_vectors = 0;
  LinkStats stats;
};

// Up to `most` fragments of the scene's covered materials; with `corrupt`, the first texel word
// the first fragment reads is changed in the image sent to the board.
BoardRun run_on_board(const std::string& name, uint64_t most, bool corrupt = false) {
  const Scene scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/" + name + ".toml");
  std::vector<MaterialSetup> mats = build_materials(scene);
  TextureSet set;
  for (size_t i = 0; i < scene.textures.size(); ++i) set.add(load_scene_texture(scene, i));
  for (MaterialSetup& m : mats) m.filter.fixed_arithmetic = covered(m, set[m.texture]);
  TextureUnit unit(set, mats, PipelineSetup{}, scene.tech, false);
  std::vector<std::vector<Fragment>> by_mat(mats.size());
  uint64_t taken = 0;
  generate_fragments(scene, 0, [&](const Fragment& f) {
    const auto m = static_cast<size_t>(scene.primitives[f.prim].material);
    if (taken >= most || !mats[m].filter.fixed_arithmetic || f.op != 0 || f.lod_bias != 0.0f ||
        f.offset_u != 0 || f.offset_v != 0 || f.sampler != 0 ||
        f.tex != static_cast<uint32_t>(mats[m].texture))
      return;
    by_mat[m].push_back(f);
    ++taken;
  });
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(make_rtl_sampler_block());
  VirtualBoard board(std::move(blocks));
  LinkOptions opt;
  opt.batch = 20 * kSamplerWords;  // whole fragments per STREAM
  LinkHost host(board, opt);
  host.select("texsim_sampler");
  BoardRun run;
  bool corrupted = false;
  for (size_t m = 0; m < mats.size(); ++m) {
    const std::vector<Fragment>& frags = by_mat[m];
    if (frags.empty()) continue;
    const Texture& tex = unit.texture_of(static_cast<int>(m));
    const FixedSampler fs(FixedSampler::config_of(mats[m].filter, mats[m].lod));
    const FixedSampler::TextureDesc desc = FixedSampler::describe(tex);
    std::vector<uint32_t> mem = FixedSampler::memory_image(tex);
    if (corrupt && !corrupted) {
      const FixedSampler::Result r = fs.sample(FixedSampler::to_input(frags[0]), desc, mem);
      mem[r.addr[0]] ^= 0x00FFFFFFu;
      corrupted = true;
    }
    for (std::vector<uint8_t>& payload : sampler_configuration(fs.config(), desc, mem)) {
      host.configure(std::move(payload));
      ++run.configure_messages;
    }
    std::vector<uint32_t> words(frags.size() * kSamplerWords);
    for (size_t i = 0; i < frags.size(); ++i) {
      encode_fragment(
          FixedSampler::to_input(frags[i]),
          std::span<uint32_t, kSamplerWords>(words.data() + i * kSamplerWords, kSamplerWords));
    }
    const std::vector<uint32_t> back = host.stream(words);
    for (size_t i = 0; i < frags.size(); ++i) {
      const FixedSampler::Result b = decode_result(
          std::span<const uint32_t, kSamplerWords>(back.data() + i * kSamplerWords, kSamplerWords));
      const uint32_t colour = rgba8(unit.process(frags[i], static_cast<int>(m)));
      const FixedSampler::Result& u = unit.last_fixed();
      run.colour_equal += b.rgba == colour;
      run.equal += b.rgba == colour && b.rgba == u.rgba && b.level_hi == u.level_hi &&
                   b.level_lo == u.level_lo && b.delta == u.delta && b.addr == u.addr;
      ++run.fragments;
    }
  }
  run.board_vectors = host.counters().vectors;
  run.stats = host.stats();
  std::cout << "texsim_sampler on the virtual board, " << name << ": " << run.fragments
            << " fragments, " << run.equal << " equal to the texture unit (fixed arithmetic), "
            << run.colour_equal << " colours equal; " << run.configure_messages
            << " CONFIGURE messages, " << run.stats.requests << " requests, "
            << run.stats.reports_out << " reports out, " << run.stats.reports_in << " reports in\n";
  return run;
}

TEST(RtlSamplerBoard, SceneThroughTheLinkEqualsTheUnit) {
  for (const char* s : {"footprint_filters", "bunny"}) {
    const BoardRun r = run_on_board(s, 1200);
    EXPECT_GT(r.fragments, 0u) << s;
    EXPECT_EQ(r.equal, r.fragments) << s;
    EXPECT_EQ(r.board_vectors, r.fragments * kSamplerWords) << s;
    EXPECT_EQ(r.stats.retransmits, 0u) << s;
  }
}

TEST(RtlSamplerBoard, FragmentsPerStreamFitTheMessageAndTheHidQueue) {
  // 83 fragments: 996 words, the most under kMaxStreamVectors (1000).
  EXPECT_EQ(board::fragments_per_stream(kMaxPayload, kMaxReportsPerMessage), 83u);
  // Over USB two responses in flight must fit hidraw's 64-report queue: 38 fragments make a
  // response of 32 reports, 39 of 33.
  EXPECT_EQ(board::fragments_per_stream(kMaxPayload, 32), 38u);
  // A board that takes 64-byte payloads: one fragment (6 + 48 bytes) per STREAM.
  EXPECT_EQ(board::fragments_per_stream(64, kMaxReportsPerMessage), 1u);
}

TEST(RtlSamplerBoard, CorruptedTexelIsCaught) {
  const BoardRun r = run_on_board("footprint_filters", 300, true);
  EXPECT_GT(r.fragments, 0u);
  EXPECT_LT(r.colour_equal, r.fragments);
}

// The bilinear lerp on the board: the scene's own lerp operands (both levels of each fragment
// of its fixed materials, the texels FixedSampler read and its weights) streamed through the
// Verilated bilinear_lerp; returns the results equal to BilinearLerp's. With `flip`, lerp
// `flip` has the red and blue channels of its four texels inverted on the way.
struct LerpRun {
  uint64_t lerps = 0, equal = 0, board_vectors = 0, requests = 0;
};
LerpRun lerps_on_board(const std::string& name, uint64_t most, uint64_t flip = UINT64_MAX) {
  const Scene scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/" + name + ".toml");
  std::vector<MaterialSetup> mats = build_materials(scene);
  TextureSet set;
  for (size_t i = 0; i < scene.textures.size(); ++i) set.add(load_scene_texture(scene, i));
  std::vector<LerpOperands> ops;
  std::vector<uint32_t> want;
  const BilinearLerp cpp({8, 8});
  std::vector<std::vector<uint32_t>> images(set.size());
  generate_fragments(scene, 0, [&](const Fragment& f) {
    const auto m = static_cast<size_t>(scene.primitives[f.prim].material);
    if (ops.size() >= most || !covered(mats[m], set[mats[m].texture]) ||
        f.tex != static_cast<uint32_t>(mats[m].texture))
      return;
    const Texture& tex = set[mats[m].texture];
    std::vector<uint32_t>& mem = images[static_cast<size_t>(mats[m].texture)];
    if (mem.empty()) mem = FixedSampler::memory_image(tex);
    const FixedSampler fs(FixedSampler::config_of(mats[m].filter, mats[m].lod));
    std::array<FixedSampler::LerpInput, 2> in{};
    fs.sample(FixedSampler::to_input(f), FixedSampler::describe(tex), mem, &in);
    for (const FixedSampler::LerpInput& l : in) {
      LerpOperands op;
      for (size_t k = 0; k < 4; ++k) op.quad[k] = static_cast<uint32_t>(l.quad[k]);
      op.fx = l.fx;
      op.fy = l.fy;
      ops.push_back(op);
      want.push_back(static_cast<uint32_t>(cpp.lerp(l.quad, l.fx, l.fy)));
    }
  });
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(make_rtl_lerp_block());
  VirtualBoard board(std::move(blocks));
  LinkOptions opt;
  opt.batch = 200 * kLerpWords;
  LinkHost host(board, opt);
  host.select("bilinear_lerp");
  host.configure(lerp_configuration({8, 8}));
  std::vector<uint32_t> words(ops.size() * kLerpWords);
  for (size_t i = 0; i < ops.size(); ++i) {
    LerpOperands op = ops[i];
    if (i == flip)
      for (uint32_t& t : op.quad) t ^= 0x00FF00FFu;
    encode_lerp(op, std::span<uint32_t, kLerpWords>(words.data() + i * kLerpWords, kLerpWords));
  }
  const std::vector<uint32_t> back = host.stream(words);
  LerpRun r;
  for (size_t i = 0; i < ops.size(); ++i) r.equal += back[i * kLerpWords] == want[i];
  r.lerps = ops.size();
  r.board_vectors = host.counters().vectors;
  r.requests = host.stats().requests;
  std::cout << "bilinear_lerp on the virtual board, " << name << ": " << r.lerps << " lerps, "
            << r.equal << " equal to BilinearLerp, " << r.requests << " requests\n";
  return r;
}

TEST(RtlSamplerBoard, SceneLerpsThroughTheLinkEqualBilinearLerp) {
  for (const char* s : {"footprint_filters", "bunny"}) {
    const LerpRun r = lerps_on_board(s, 4000);
    EXPECT_EQ(r.lerps, 4000u) << s;
    EXPECT_EQ(r.equal, r.lerps) << s;
    EXPECT_EQ(r.board_vectors, r.lerps * kLerpWords) << s;
  }
  // Texels changed on the way: that lerp, and only it, differs.
  for (uint64_t at : {5u, 77u, 1234u}) {
    const LerpRun r = lerps_on_board("bunny", 2000, at);
    EXPECT_EQ(r.equal + 1, r.lerps) << at;
  }
}

TEST(RtlSamplerBoard, LerpConfigurationOtherThanTheBuildsIsRefused) {
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(make_rtl_lerp_block());
  VirtualBoard board(std::move(blocks));
  LinkHost host(board, LinkOptions{});
  host.select("bilinear_lerp");
  host.configure(lerp_configuration({8, 8}));
  EXPECT_THROW(host.configure(lerp_configuration({8, 6})), LinkError);
  EXPECT_THROW(host.configure({8}), LinkError);
  EXPECT_THROW(host.configure({0, 8}), LinkError);
}

TEST(RtlSamplerBoard, StateOtherThanTheBuildsIsRefused) {
  std::vector<std::unique_ptr<BoardBlock>> blocks;
  blocks.push_back(make_rtl_sampler_block());
  VirtualBoard board(std::move(blocks));
  LinkHost host(board, LinkOptions{});
  host.select("texsim_sampler");
  FixedSampler::Config c;
  c.sub_bits = 4;
  const std::vector<uint32_t> mem(4, 0);
  EXPECT_THROW(host.configure(sampler_configuration(c, FixedSampler::TextureDesc{}, mem)[0]),
               LinkError);
  std::vector<uint8_t> past = sampler_configuration({}, {}, mem)[1];
  EXPECT_THROW(host.configure(past), LinkError);  // a chunk before any state: no memory yet
}

// `texsim run SCENE --board virtual`: the trilinear material with fixed arithmetic, sampled by
// the RTL on the virtual board, gives the image of the same run in process.
RunCapture run_scene(const std::string& board, std::string* log_out = nullptr,
                     const std::string& arithmetic = "fixed") {
  RunOptions opt;
  opt.scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/footprint_filters.toml";
  opt.overrides = {"materials.trilinear.filter.arithmetic=\"" + arithmetic + "\""};
  opt.functional = true;
  opt.reference = "none";
  opt.workload = false;
  opt.truth_cache = false;
  opt.board = board;
  RunCapture cap;
  opt.capture = &cap;
  std::ostringstream log;
  run_simulation(opt, log);
  if (log_out) *log_out = log.str();
  return cap;
}

TEST(RtlSamplerBoard, RunWithVirtualBoardGivesTheCppImage) {
  std::string log;
  const RunCapture cpp = run_scene("");
  const RunCapture rtl = run_scene("virtual", &log);
  ASSERT_TRUE(cpp.image && rtl.image);
  EXPECT_NE(log.find("texsim_sampler runs the fixed-arithmetic materials trilinear"),
            std::string::npos)
      << log;
  EXPECT_EQ(rtl.image->rgb, cpp.image->rgb);
  EXPECT_EQ(rtl.image->covered, cpp.image->covered);
  // Several fragments per round trip: the unit's batches go out in STREAMs of up to 83.
  EXPECT_NE(log.find("(up to 83 fragments per STREAM)"), std::string::npos) << log;
  EXPECT_GT(rtl.board_fragments, 0u);
  EXPECT_LT(rtl.board_streams * 10, rtl.board_fragments)
      << rtl.board_streams << " STREAMs for " << rtl.board_fragments << " fragments";
  // The board's bilinear_lerp ran both lerps of every fragment, each equal to the C++ model's.
  EXPECT_EQ(rtl.board_lerps, 2 * rtl.board_fragments);
  EXPECT_NE(log.find("each equal to BilinearLerp"), std::string::npos) << log;
  // The key takes effect: the float32 path's image differs (by an LSB on some pixels).
  const RunCapture fl = run_scene("", nullptr, "float");
  EXPECT_NE(fl.image->rgb, cpp.image->rgb);
}

TEST(RtlSamplerBoard, RunWithHidWithoutDeviceFailsCleanly) {
  if (!HidTransport::enumerate(kDefaultVid, kDefaultPid).empty())
    GTEST_SKIP() << "a board is attached";
  try {
    run_scene("hid");
    ADD_FAILURE() << "--board hid ran without a device";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--board hid"), std::string::npos) << e.what();
  }
}

TEST(RtlSamplerBoard, HidWithoutDeviceFailsCleanly) {
  if (!HidTransport::enumerate(kDefaultVid, kDefaultPid).empty())
    GTEST_SKIP() << "a board is attached";
  EXPECT_THROW({ const HidTransport hid(kDefaultVid, kDefaultPid); }, LinkError);
}

}  // namespace
}  // namespace texsim::link
