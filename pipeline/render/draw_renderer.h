#pragma once
// Renders the frames of a draw trace (traces/DRAWS.md) through texsim: per draw, triangles are
// clipped in clip space, projected, culled, rasterised with the edge rasteriser (top-left rule
// at pixel centres), depth-tested, textured through the texsim texture unit with exact
// derivatives, and coloured by the fixed-function colour stage (colour_stage.h).
// docs/architecture.md, "Draw traces". Arithmetic: clipping, projection and attribute planes
// in double; coverage in the edge rasteriser's fixed point (8 sub-pixel bits); depth as a
// 24-bit unsigned integer (round to nearest); colour as colour_stage.h says.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "blocks/base/tech_table.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/raster/edge_rasterizer.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/texture/pipeline_setup.h"
#include "pipeline/texture/unit_array.h"
#include "traces/draw_trace.h"

namespace texsim {

// What became of a frame's draws, triangles and fragments.
struct DrawRenderCounts {
  uint64_t draws = 0;                       // draws rendered
  uint64_t draws_refused = 0;               // draws left out (state the colour stage lacks)
  std::map<std::string, uint64_t> refused;  // why -> draws
  // Sampler states texsim approximates (what -> draw units), e.g. GL_CLAMP as clamp to edge.
  std::map<std::string, uint64_t> approximated;
  uint64_t triangles = 0;     // triangles of the rendered draws
  uint64_t clipped_away = 0;  // wholly outside the clip volume
  uint64_t culled = 0;        // faces culled
  uint64_t fragments = 0;     // pixels covered by the rasteriser
  uint64_t depth_killed = 0;  // failed the depth test (before texturing: early depth test)
  uint64_t alpha_killed = 0;  // failed the alpha test
  uint64_t blended = 0;       // written with blending
  uint64_t written = 0;       // reached the framebuffer
  uint64_t lookups = 0;       // fragments sent to the texture unit (one per enabled unit)
  void add(const DrawRenderCounts& o);
};

// The texture unit's look-ups against their ground truth (DrawRenderer::set_truth), per
// channel R, G, B, A on [0, 1], in double.
struct LookupAccuracy {
  uint64_t lookups = 0;
  uint64_t samples = 0;  // points the truth evaluated
  double sum_sq = 0;     // Σ (unit − truth)² over the look-ups' four channels
  double max_abs = 0;
  double mse() const { return lookups ? sum_sq / (4.0 * static_cast<double>(lookups)) : 0; }
  double psnr_db() const;  // 10 log10(1 / mse); 999 when equal
  void add(const LookupAccuracy& o);
};

struct RenderedFrame {
  uint32_t number = 0;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;   // RGBA8, the top row first
  std::vector<uint8_t> drawn;  // 1 where a fragment was written
  DrawRenderCounts counts;
  // With a ground truth: the frame shaded with the truth's texels instead of the unit's (the
  // same fragments and depth decisions as the unit's frame: its visibility), and the look-ups'
  // error. Empty without one.
  std::vector<uint8_t> truth_rgba, truth_drawn;
  LookupAccuracy accuracy;
  bool has_truth() const { return !truth_rgba.empty(); }
};

class DrawRenderer {
 public:
  // The texture unit holds every texture of `trace` (with its levels) and one material per
  // distinct (texture, sampler state) the frames `frames` (indices into trace.frames) use;
  // `file` names the trace in messages. With `timing` the unit is clocked (cycles, cache, DRAM).
  DrawRenderer(const DrawTrace& trace, const std::vector<size_t>& frames,
               const PipelineSetup& setup, const TechTable& tech, bool timing, std::string file);
  ~DrawRenderer();
  DrawRenderer(const DrawRenderer&) = delete;
  DrawRenderer& operator=(const DrawRenderer&) = delete;

  // Renders trace.frames[index] (one of the frames given to the constructor, in increasing
  // order) into a framebuffer cleared to black with depth 1. The window is the union of the
  // draws' viewports.
  RenderedFrame render(size_t index);

  const UnitArray& units() const { return *units_; }
  // The textures as the units placed them; `observer` sees every look-up sent to the unit (its
  // tex: an index into them), in the unit's order, e.g. to characterise the workload.
  const TextureSet& textures() const { return textures_; }
  void set_lookup_observer(std::function<void(const Fragment&)> observer) {
    observer_ = std::move(observer);
  }
  // Computes each look-up's ground truth too: the level-0 texture reconstructed bilinearly in
  // double, integrated over the pixel through its triangle's exact screen→texture map (the
  // perspective-correct attribute planes as a projective map) by `integrate`; render() then
  // fills RenderedFrame's truth figures.
  // The truth runs on `threads` threads (0: one per hardware thread); the figures do not depend
  // on the count.
  void set_truth(const PixelIntegrator& integrate, int threads) {
    truth_.emplace(integrate);
    truth_threads_ = threads;
  }
  // "name (W×H, L levels)" of each texture, for reports.
  std::vector<std::string> texture_names() const;
  // What each material is: its texture and GL sampler state mapped to texsim's.
  const std::vector<std::string>& material_notes() const { return notes_; }

 private:
  struct Tri;
  void render_draw(const Draw& d, uint32_t frame, size_t draw_index, RenderedFrame& out);
  void raster_triangle(const Draw& d, const Tri& t, uint32_t frame, RenderedFrame& out);
  // The triangle's fragments (frags_, look_) through the texture unit, then the colour stage.
  void texture_fragments(const Draw& d);
  void shade_fragments(const Draw& d, RenderedFrame& out);
  // The colour stage into one framebuffer with the given texels; `counts` (null: the truth's
  // frame) receives the counts, and only then is depth written.
  void shade_into(const Draw& d, const std::vector<Rgba>* texels, int width, int height,
                  std::vector<uint8_t>& rgba, std::vector<uint8_t>& drawn,
                  DrawRenderCounts* counts);
  // The truth of unit u's look-ups of the current triangle (look_[u]) with material m.
  void truth_lookups(size_t u, int m);

  const DrawTrace& trace_;
  std::string file_;
  TextureSet textures_;
  std::map<uint32_t, int> tex_index_;  // texture id -> index in textures_
  // (texture id, sampler) -> material; one map key per distinct DrawUnit sampler state.
  using SamplerKey = std::array<uint32_t, 7>;
  static SamplerKey sampler_key(const DrawUnit& u);
  std::map<SamplerKey, int> materials_;
  std::vector<std::string> notes_;
  std::unique_ptr<UnitArray> units_;
  EdgeRasterizer raster_;
  // The frame in flight.
  std::vector<uint32_t> depth_;
  uint32_t prim_ = 0;
  // Per triangle: the fragments that passed the depth test, and their texture look-ups.
  struct Frag {
    int x, y;  // window pixel (GL: y up)
    uint32_t z;
    Rgba colour;
  };
  std::vector<Frag> frags_;
  std::vector<Fragment> look_[kDrawMaxUnits];
  std::vector<Rgba> texel_[kDrawMaxUnits];
  // Ground truth (set_truth): the triangle's screen→texture map per unit (image pixel
  // coordinates, pixel centres at +0.5), and its look-ups' truth texels.
  std::optional<PixelIntegrator> truth_;
  ProjectiveMap map_[kDrawMaxUnits];
  std::vector<Rgba> truth_texel_[kDrawMaxUnits];
  std::vector<int> truth_samples_;
  int truth_threads_ = 1;
  LookupAccuracy* accuracy_ = nullptr;
  DrawRenderCounts* counts_ = nullptr;
  std::function<void(const Fragment&)> observer_;
};

// A draw trace's texture with its own levels (RGBA8), as the renderer's unit holds it.
Texture texture_of_draw(const DrawTexture& t);

// The texsim material of one GL texture unit's sampler state, and what texsim approximates
// ("" when exact): texsim has one filter for magnification and minification, and no
// nearest-texel + linear-mip filter.
MaterialSetup material_for_sampler(const DrawUnit& u, int texture, std::string& approximation);

}  // namespace texsim
