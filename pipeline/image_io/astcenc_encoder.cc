#include "pipeline/image_io/astcenc_encoder.h"

#include <astcenc.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <thread>
#include <tuple>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/astc_file.h"

#ifndef TEXSIM_ASTCENC_VERSION
#define TEXSIM_ASTCENC_VERSION "4"
#endif

namespace texsim {

namespace {

constexpr int kMaxSide = 16384;
constexpr const char* kCodec = "astcenc";
constexpr int kMaxThreads = 64;
std::atomic<int> g_threads{1};

float preset_quality(AstcPreset p) {
  switch (p) {
    case AstcPreset::Fastest:
      return ASTCENC_PRE_FASTEST;
    case AstcPreset::Fast:
      return ASTCENC_PRE_FAST;
    case AstcPreset::Medium:
      return ASTCENC_PRE_MEDIUM;
    case AstcPreset::Thorough:
      return ASTCENC_PRE_THOROUGH;
  }
  return ASTCENC_PRE_MEDIUM;
}

void check(astcenc_error e, const std::string& what) {
  if (e != ASTCENC_SUCCESS)
    throw InputError(kCodec, what + " failed: " + astcenc_get_error_string(e));
}

// A codec context with the lock that keeps it to one image at a time.
struct Context {
  std::mutex busy;
  astcenc_context* ctx = nullptr;
  Context() = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context() {
    if (ctx != nullptr) astcenc_context_free(ctx);
  }
};

using ContextKey = std::tuple<int, int, AstcPreset, bool, int>;  // ..., threads

// The process's contexts, made on first use (a failed one is not kept).
Context& context_for(const AstcencOptions& o, int threads) {
  static std::mutex table_lock;
  static std::map<ContextKey, std::unique_ptr<Context>> table;
  const std::lock_guard<std::mutex> lock(table_lock);
  std::unique_ptr<Context>& slot =
      table[ContextKey{o.block_w, o.block_h, o.preset, o.srgb, threads}];
  if (!slot) {
    astcenc_config config{};
    check(astcenc_config_init(o.srgb ? ASTCENC_PRF_LDR_SRGB : ASTCENC_PRF_LDR,
                              static_cast<unsigned>(o.block_w), static_cast<unsigned>(o.block_h), 1,
                              preset_quality(o.preset), 0, &config),
          "astcenc_config_init");
    auto c = std::make_unique<Context>();
    check(astcenc_context_alloc(&config, static_cast<unsigned>(threads), &c->ctx),
          "astcenc_context_alloc");
    slot = std::move(c);
  }
  return *slot;
}

}  // namespace

void set_astcenc_threads(int threads) { g_threads = std::clamp(threads, 1, kMaxThreads); }
int astcenc_threads() { return g_threads; }

const char* astc_preset_name(AstcPreset p) {
  switch (p) {
    case AstcPreset::Fastest:
      return "fastest";
    case AstcPreset::Fast:
      return "fast";
    case AstcPreset::Medium:
      return "medium";
    case AstcPreset::Thorough:
      return "thorough";
  }
  return "medium";
}

EncodedLevel astcenc_encode(const Rgba8Image& img, const AstcencOptions& o) {
  check_encoder_input(img, kCodec, kMaxSide);
  if (!is_astc_2d_footprint(o.block_w, o.block_h))
    throw InputError(kCodec, "block size " + std::to_string(o.block_w) + "x" +
                                 std::to_string(o.block_h) + " is not an ASTC 2-D footprint");
  Rgba8Image padded = padded_to_blocks(img, o.block_w, o.block_h);
  const size_t blocks = static_cast<size_t>(padded.width / o.block_w) *
                        static_cast<size_t>(padded.height / o.block_h);
  EncodedLevel out;
  out.format = FileBlockFormat::Astc;
  out.width = img.width;
  out.height = img.height;
  out.block_w = o.block_w;
  out.block_h = o.block_h;
  out.bytes.resize(blocks * 16);

  void* planes[1] = {padded.rgba.data()};
  astcenc_image image{};
  image.dim_x = static_cast<unsigned>(padded.width);
  image.dim_y = static_cast<unsigned>(padded.height);
  image.dim_z = 1;
  image.data_type = ASTCENC_TYPE_U8;
  image.data = planes;
  const astcenc_swizzle identity{ASTCENC_SWZ_R, ASTCENC_SWZ_G, ASTCENC_SWZ_B, ASTCENC_SWZ_A};
  const int threads = astcenc_threads();
  Context& c = context_for(o, threads);
  {
    const std::lock_guard<std::mutex> lock(c.busy);
    // Every thread of the context joins the one image (astcenc shares the blocks out).
    std::vector<astcenc_error> err(static_cast<size_t>(threads), ASTCENC_SUCCESS);
    auto work = [&](int t) {
      err[static_cast<size_t>(t)] = astcenc_compress_image(
          c.ctx, &image, &identity, out.bytes.data(), out.bytes.size(), static_cast<unsigned>(t));
    };
    {
      std::vector<std::jthread> helpers;
      for (int t = 1; t < threads; ++t) helpers.emplace_back(work, t);
      work(0);
    }  // the helpers join here
    for (const astcenc_error e : err) check(e, "astcenc_compress_image");
    check(astcenc_compress_reset(c.ctx), "astcenc_compress_reset");
  }
  std::ostringstream prov;
  prov << "libastcenc " << TEXSIM_ASTCENC_VERSION << " (" << (o.srgb ? "-cs" : "-cl") << " "
       << o.block_w << "x" << o.block_h << " -" << astc_preset_name(o.preset) << ")";
  out.provenance = prov.str();
  return out;
}

}  // namespace texsim
