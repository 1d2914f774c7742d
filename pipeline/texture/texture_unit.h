#pragma once
// The clocked texture unit (ПНТ, first slice): [coordinates → derivatives, when a material has a
// coordinate unit] → LOD → texel address generation → texture cache + DRAM → blend, built from
// a scene's materials. Only the blocks some material needs are
// instantiated. docs/architecture.md describes the stages; docs/timing-model.md the timing.
#include <toml++/toml.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/linear_batch.h"
#include "blocks/texture/sampler/lod_unit.h"
#include "blocks/texture/sampler/texel_address_gen.h"
#include "blocks/texture/sampler/texel_blend.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/texture/coord_method.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/footprint_filter.h"
#include "pipeline/texture/memory_system.h"
#include "pipeline/texture/pipeline_setup.h"

namespace texsim {

struct BlockUse {
  std::string name;        // e.g. "lod", "filter.trilinear", "blend", "cache"
  std::string arithmetic;  // which number format the datapath uses
  TimingSpec timing;
  OpCounts ops;                        // total over the run
  uint64_t texels = 0;                 // texels it fetched through the cache over the run
  std::vector<std::string> materials;  // materials that use it
};

// Fragments a coordinate front end produced and what became of them.
struct FrontEndStats {
  uint64_t generated = 0;  // pixels the coordinate units computed
  uint64_t occluded = 0;   // left after the front end: hidden by a nearer plane, or covered twice
  uint64_t rejected = 0;   // coordinates rejected by the block (not textured)
};

struct FrameStats {
  uint32_t frame = 0;
  uint64_t fragments = 0;
  uint64_t cycles = 0;  // cycle at which the frame's last fragment left the pipeline
};

class TextureUnit {
 public:
  // With `timing` false the unit is functional only: colours and op counts, no cache or clock.
  TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
              const PipelineSetup& setup, const TechTable& tech, bool timing);
  // Unit `unit` of several (UnitArray): its L1 is memory.l1(unit), its misses go to
  // memory.behind_l1(), and it is timed in two steps (process() runs a fragment up to the
  // cache stage; commit() makes its look-ups), so that a scheduler can order the units'
  // requests to the shared levels by cycle. No batched datapath in this mode.
  TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
              const PipelineSetup& setup, const TechTable& tech, MemorySystem& memory, int unit);
  TextureUnit(const TextureUnit&) = delete;
  TextureUnit& operator=(const TextureUnit&) = delete;
  ~TextureUnit();

  // Two-step timing (the constructor with a MemorySystem): the cycle the last processed
  // fragment starts the cache stage, and the rest of its way (once per processed fragment,
  // before the next one).
  uint64_t pending_start() const { return defer_start_; }
  void commit();

  // Filters one fragment with its material's blocks and the fragment's own texture (f.tex, an
  // index into the unit's TextureSet); in timing mode also sends it through the clocked
  // pipeline and the cache. Fragments must arrive in order. `front` is null, or the
  // fragment's costs in the coordinate front end (one per stage of its material's coordinate
  // unit, as CoordUnit::generate gives them).
  Rgba process(const Fragment& f, int material, const ItemCost* front = nullptr);
  // Fragments f[0 .. n) of one material, without front-end costs: the same colours (out[i]),
  // counts and cycles as n calls of process(f[i], material). A bilinear or trilinear
  // material's fragments go through the batched SIMD datapath (LinearBatchSampler) first; the
  // cache and the clocked pipeline then take them one by one, in order.
  void process_batch(const Fragment* f, size_t n, int material, Rgba* out);

  // Coordinate front end: the stages (0, 1 or 2: coordinates, derivatives) in front of LOD,
  // present only when some material has a coordinate unit.
  int front_stages() const { return front_; }
  // Front-end stages of material m's coordinate unit (costs per fragment; 0 without one).
  int front_count(int m) const { return paths_[static_cast<size_t>(m)].front_count; }
  // The shading frames of the scene's primitives (indexed by Fragment::prim), which relief and
  // lighting need for the view vector. Without them a material with either effect is refused.
  void set_surfaces(std::vector<SurfaceFrame> frames) { surfaces_ = std::move(frames); }
  // Relief loop steps and height reads of material m over the run (0 without relief).
  uint64_t material_relief_steps(int m) const {
    return paths_[static_cast<size_t>(m)].relief_steps;
  }
  uint64_t material_relief_fetches(int m) const {
    return paths_[static_cast<size_t>(m)].relief_fetches;
  }
  bool material_has_relief(int m) const { return paths_[static_cast<size_t>(m)].relief != nullptr; }
  const MaterialSetup& material(int m) const { return mats_[static_cast<size_t>(m)]; }
  const Texture& texture_of(int m) const {
    return textures_[mats_[static_cast<size_t>(m)].texture];
  }
  // Runs material m's coordinate unit over a screen triangle (its map in texels of the
  // material's texture): fragments in the unit's traversal order and their front-end costs;
  // counts the unit's operations.
  void generate_coords(int material, const CoordTriangle& tri, std::vector<CoordUnitFragment>& out,
                       std::vector<ItemCost>& costs);
  // A generated fragment that leaves after the front end (occluded, covered twice, or its
  // coordinates rejected): its front-end issue cycles are charged to the next fragment in those
  // stages; it costs nothing further.
  void drop(int material, const ItemCost* front, bool rejected);
  const FrontEndStats& front_end_stats() const { return front_stats_; }

  bool timing() const { return timing_; }
  // Checks what every timed run must satisfy: the total cycles, or a stage's last issue slot
  // when that ends later, are at least the stage's busy issue slots ÷ its lanes, and the total
  // cycles at least the DRAM channel's busy cycles. Throws
  // std::logic_error naming the stage and the figures if not (a defect of the model).
  void check_timing_invariants() const;
  uint64_t fragments() const { return fragments_; }
  uint64_t cycles() const { return pipe_ ? pipe_->run_end() : 0; }
  std::vector<BlockUse> blocks() const;
  // The blocks material m used, with only its own operations and texels (cache excluded).
  std::vector<BlockUse> material_blocks(int m) const;
  // Fragments material m textured.
  uint64_t material_fragments(int m) const { return paths_[static_cast<size_t>(m)].fragments; }
  int material_count() const { return static_cast<int>(mats_.size()); }
  const ClockedPipeline* pipeline() const { return pipe_.get(); }
  const TextureCache& cache() const { return cache_; }
  const MemorySystem& memory() const { return *mem_; }
  MemorySystem& memory() { return *mem_; }
  // Tag look-ups quad merging saved: lines a quad's earlier lane had looked up.
  uint64_t quad_merged_lookups() const { return quad_merged_; }
  const std::vector<FrameStats>& frames() const {
    // The current frame's cycles are the pipeline's so far (set here, not per fragment).
    if (pipe_ && !frames_.empty()) frames_.back().cycles = pipe_->run_end();
    return frames_;
  }

 private:
  // One material's blocks. Op counts depend only on the probe number N of each fragment, so
  // the hot path counts fragments and probes and blocks() multiplies the per-fragment and
  // per-probe counts of the blocks: exact, and three increments instead of three OpCounts sums.
  struct Path;
  TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
              const PipelineSetup& setup, const TechTable& tech, bool timing,
              std::unique_ptr<MemorySystem> own, MemorySystem* shared, int unit);
  // The per-fragment datapath of one material, chosen at construction (filter, layout, the
  // number of front-end stages, functional or timed) so the hot path has no run-time switches
  // on the configuration.
  using Kernel = Rgba (TextureUnit::*)(const Fragment&, Path&, const Texture&, const ItemCost*);
  using BatchKernel = void (TextureUnit::*)(const Fragment*, size_t, Path&, const Texture&, Rgba*);
  struct Path {
    Kernel kernel = nullptr;
    // The batched datapath (null: fragments go one by one) and the sampler it runs.
    BatchKernel batch_kernel = nullptr;
    std::shared_ptr<const LinearBatchSampler> batch;
    LodUnit lod;
    TexelAddressGen addr;
    uint64_t fragments = 0;
    uint64_t aniso_fragments = 0;  // fragments with N > 1
    uint64_t probes = 0;           // Σ N over all fragments
    // Extra issue cycles in the blend and cache stages for N = 1..16 probes (N × taps per
    // probe taps at taps_per_cycle and texels_per_cycle): a table instead of two divisions.
    uint32_t blend_extra_ii[17] = {};
    const FootprintFilter* footprint = nullptr;  // set: this path is one footprint filter block
    OpCounts footprint_ops;                      // counted per call (data-dependent)
    uint64_t footprint_texels = 0;
    uint32_t cache_extra_ii[17] = {};
    // Coordinate front end of this material (null: none).
    const CoordUnit* coords = nullptr;
    OpCounts coord_ops, deriv_ops;
    int front_count = 0;  // its unit's stages (costs per fragment)
    // Added issue cycles per front-end stage so the shared stage (sized for the widest unit)
    // gives this unit its own throughput: ceil(ii × lanes_stage / lanes_unit) − 1.
    uint32_t front_extra[2] = {};
    // Relief and lighting of this material (null: none), their operations and the relief's
    // loop steps and height reads (data-dependent, counted per call).
    const ReliefEffect* relief = nullptr;
    const LightingEffect* lighting = nullptr;
    OpCounts relief_ops, normal_ops, shader_ops;
    uint64_t relief_steps = 0, relief_fetches = 0;
    uint32_t relief_step_ii = 1, light_extra_ii = 0;
    // Where the relief's reads lie in memory: the height texture, the colour texture (read by
    // the visibility-aware filter) and the distance map's volume (one byte per voxel).
    const Texture* relief_height = nullptr;
    const Texture* relief_colour = nullptr;
    uint64_t volume_base = 0;
    // The visibility-aware filter (when the relief has one): its operations, texels read
    // (colours and trace heights) and issue cycles per read.
    OpCounts vis_ops;
    uint64_t vis_texels = 0;
    uint32_t vis_ii = 1;
  };
  // Tag look-ups of the fragment's distinct lines at cycle `start`; returns the cycles the
  // cache stage waits beyond its hit latency (DRAM refills).
  uint64_t cache_lookups(const FilterTaps& taps, const Texture& tex, uint64_t start);
  // The same for the quads of a linear probe (one or two levels), under layout L.
  template <TexelLayout L>
  [[gnu::always_inline]] inline uint64_t cache_lookups(const TexelQuad* q, int n,
                                                       const Texture& tex, uint64_t start);
  // access_lines with quad merging: a line the open quad already looked up is not looked up
  // again.
  uint64_t access_quad_lines(const uint64_t* lines, int n, uint64_t texels, uint64_t start);
  // Charges the DRAM refills of lines[0 .. n) looked up at `start`; returns the extra wait.
  [[gnu::always_inline]] inline uint64_t access_lines(const uint64_t* lines, int n, uint64_t texels,
                                                      uint64_t start);
  // Kernels: kFront is the number of front-end stages of a timed unit, -1 for a functional
  // one. process_any handles every filter with the general tap list; process_linear a
  // bilinear or trilinear material with quads in registers (falling back to process_any for
  // anisotropic fragments or a texture not in layout L).
  template <int kFront>
  Rgba process_any(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  template <FilterMode kFilter, TexelLayout L, int kFront>
  Rgba process_linear(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  template <int kFront>
  Rgba process_taps(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                    const LodResult& lod);
  // A batch of fragments on one texture (n <= LinearBatch::kMax) through the batched sampler;
  // the fragments it leaves undone through process_linear.
  template <FilterMode kFilter, TexelLayout L, int kFront>
  void batch_linear(const Fragment* f, size_t n, Path& p, const Texture& tex, Rgba* out);
  template <int kFront>
  static BatchKernel pick_batch_kernel(FilterMode filter, TexelLayout layout);
  // Sets p's batched datapath when material m can use one.
  void choose_batch(Path& p, const MaterialSetup& m);
  template <int kFront>
  static Kernel pick_kernel(FilterMode filter, TexelLayout layout, bool quads);
  Kernel choose_kernel(const Path& p) const;
  // Sends the fragment through the clocked pipeline; `lookups(start)` does its cache look-ups.
  template <int kFront, class Lookups>
  [[gnu::always_inline]] inline void issue_timed(Path& p, const ItemCost* front, uint32_t probes,
                                                 Lookups&& lookups);
  // The fixed stage sequence of a unit without relief or lighting stages.
  template <int kFront, class Lookups>
  [[gnu::always_inline]] inline void issue_fixed_stages(Path& p, const ItemCost* front,
                                                        uint32_t probes, Lookups& lookups);
  void count_fragment(const Fragment& f, Path& p, uint32_t probes) {
    ++p.fragments;
    p.aniso_fragments += probes > 1;
    p.probes += probes;
    count_frame(f);
  }
  uint64_t cache_lookups(const std::vector<TexelRef>& texels, const Texture& tex, uint64_t start);
  Rgba process_footprint(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  Rgba filter_fragment(const Fragment& f, Path& p, const ItemCost* front);
  // Relief → filter → lighting for a material with either effect.
  Rgba process_surface(const Fragment& f, Path& p, int material, const ItemCost* front);
  // The visibility-aware filter of a relief material in place of its filter: the filter's
  // reads occupy the address stage (one per issue cycle) and go through the cache.
  Rgba process_visible(const Fragment& g, Path& p, const glm::dvec3& view_ts,
                       const SurfaceFrame& sf, const ItemCost* front);
  // The distinct cache lines of a relief block's reads, sorted.
  void relief_lines(const Path& p, const std::vector<ReliefRead>& reads,
                    std::vector<uint64_t>& lines) const;
  // Extra issue cycles of the relief and lighting stages for the current fragment.
  void add_effect_costs(int s, ItemCost& c) const {
    if (s == relief_stage_) c.extra_ii += cur_relief_ii_;
    if (s == light_stage_) c.extra_ii += cur_light_ii_;
  }
  // The current fragment's relief reads looked up in the cache at `start` (the cache stage,
  // before the filter's: the cache and DRAM see requests in time order); returns the wait
  // beyond the hit latency (0 without relief reads). Their issue cycles are the relief
  // stage's steps (one bilinear read per step), not the cache stage's.
  uint64_t relief_lookups(uint64_t start);
  // Cost of front-end stage s for a fragment of path p (with the dropped fragments' cycles).
  ItemCost front_cost(const Path& p, const ItemCost* front, int s) {
    ItemCost c;
    if (front && s < p.front_count) c = front[s];
    c.extra_ii += p.front_extra[s] + pending_front_[s];
    pending_front_[s] = 0;
    return c;
  }
  void count_frame(const Fragment& f) {
    if (quad_merge_) note_quad(f);
    if (frames_.empty() || frames_.back().frame != f.frame) new_frame(f);
    ++frames_.back().fragments;
    ++fragments_;
  }
  void new_frame(const Fragment& f);
  // Quad merging: whether f opens a new quad (QuadAssembler's rule: same frame, primitive and
  // 2x2 square as the previous fragment, and a lane not yet taken, continue it).
  void note_quad(const Fragment& f);

  TextureSet& textures_;
  std::vector<MaterialSetup> mats_;
  std::vector<Path> paths_;
  PipelineSetup setup_;
  TechTable tech_;
  bool timing_;
  TexelBlend blend_;
  std::unique_ptr<MemorySystem> own_memory_;  // set: a unit on its own (first constructor)
  MemorySystem* mem_;
  TextureCache& cache_;  // this unit's L1
  LineMemory* next_;     // where its misses go
  int unit_ = 0;
  // Quad merging ([pipeline] quad_merge): the open quad, and the lines its lanes looked up
  // with the cycle each is ready; a later lane reading one of them makes no look-up.
  bool quad_merge_ = false;
  uint32_t quad_frame_ = 0, quad_prim_ = 0, quad_x_ = 0, quad_y_ = 0, quad_mask_ = 0;
  bool quad_open_ = false;
  std::vector<std::pair<uint64_t, uint64_t>> quad_lines_;  // (line, ready)
  uint64_t quad_merged_ = 0;                               // look-ups saved
  // Two-step timing: the costs of the fragment in flight, its arrival and start at the cache
  // stage, and its recorded look-ups (groups of lines, each with its texels).
  bool defer_ = false, recording_ = false;
  std::vector<ItemCost> defer_costs_;
  uint64_t defer_arrival_ = 0, defer_start_ = 0;
  struct LineGroup {
    size_t first, count;
    uint64_t texels;
  };
  std::vector<LineGroup> rec_groups_;
  std::vector<uint64_t> rec_lines_;
  // Runs the fragment through the pipeline with cost_at(stage, start) — at once, or in two
  // steps in a unit of several.
  template <class CostFn>
  void issue_any(CostFn&& cost_at);
  std::unique_ptr<ClockedPipeline> pipe_;
  FilterTaps taps_;
  std::unique_ptr<LinearBatch> batch_out_;  // the batched sampler's results
  std::vector<TexelRef> fetched_;           // texels of the current footprint-filter fragment
  std::vector<uint64_t> lines_;
  uint64_t fragments_ = 0;
  int front_ = 0;
  int base_ = 0;  // index of the LOD stage: after the front end and the relief stage
  int relief_stage_ = -1, light_stage_ = -1;  // -1: no material needs the stage
  uint32_t cur_relief_ii_ = 0, cur_light_ii_ = 0;
  uint64_t cur_relief_texels_ = 0;         // the current fragment's relief reads (timed)
  std::vector<ReliefRead> relief_reads_;   // the current fragment's relief reads
  std::vector<ReliefRead> fetched_reads_;  // its visibility-aware filter's reads
  std::vector<uint64_t> relief_lines_;     // their distinct cache lines
  std::vector<std::unique_ptr<ReliefEffect>> reliefs_;
  std::vector<std::unique_ptr<LightingEffect>> lightings_;
  std::vector<SurfaceFrame> surfaces_;
  uint32_t pending_front_[2] = {};  // issue cycles of dropped fragments, per front-end stage
  FrontEndStats front_stats_;
  mutable std::vector<FrameStats> frames_;
};

}  // namespace texsim
