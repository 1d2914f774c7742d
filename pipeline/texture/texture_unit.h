#pragma once
// The clocked texture unit (ПНТ, first slice), assembled from the stages its materials need
// (stages/material_stages.h): [coordinates → derivatives] [relief] → LOD → texel address
// generation (or a footprint filter) → texel fetch (cache + the memory behind it) → blend
// [→ lighting]. The unit clocks them; the stages own their blocks, counters and report rows.
// docs/architecture.md describes the stages; docs/timing-model.md the timing.
#include <toml++/toml.h>

#include <array>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/sample_op.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_cache.h"
#include "blocks/texture/memory/texture_memory.h"
#include "blocks/texture/sampler/fixed_sampler.h"
#include "blocks/texture/sampler/linear_batch.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/kernel/clocked_pipeline.h"
#include "pipeline/texture/coord_method.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/memory_system.h"
#include "pipeline/texture/pipeline_setup.h"
#include "pipeline/texture/stages/fetch_stage.h"
#include "pipeline/texture/stages/material_stages.h"
#include "pipeline/texture/stages/unit_stage.h"

namespace texsim {

// Where a fixed-arithmetic material's results come from instead of FixedSampler in process: a
// board running the RTL sampler (pipeline/app/board_sampler.h), given the material and the
// fragment's fixed-point input.
class FixedSamplerBoard {
 public:
  virtual ~FixedSamplerBoard() = default;
  virtual FixedSampler::Result sample(int material, const FixedSampler::Input& in) = 0;
  // Several fragments of one material at once, results in order (a board packs them into few
  // round trips); by default one sample() each.
  virtual void sample_batch(int material, std::span<const FixedSampler::Input> in,
                            std::span<FixedSampler::Result> out) {
    for (size_t i = 0; i < in.size(); ++i) out[i] = sample(material, in[i]);
  }
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
  // Two-step timing, with no fragment in flight: the earliest cycle the next fragment can start
  // the cache stage (stages take items in order; drops only add cycles).
  uint64_t next_start_bound() const { return pipe_->start_at(cache_slot_, 0); }
  void commit() {
    if (done_) {  // the fragment took its whole way in process()
      done_ = false;
      return;
    }
    commit_deferred();
  }
  // Whether the processed fragment's commit() stays in this unit (its look-ups all hit the L1,
  // FetchStage::recorded_local), so it may be committed at once, out of the global order.
  bool pending_local() const { return early_ && (done_ || fetch_.recorded_local()); }
  // Queued timing (a unit of several without quad merging; UnitArray): process() filters the
  // fragment and makes its L1 look-ups at once, and only its way through the clocked pipeline
  // waits, as a Timing, for its turn in the units' cycle order: begin_timing() runs it up to
  // the cache stage (or, if its look-ups all hit as they came, the whole way: timing_done()), and
  // commit_timing() sends its misses to the level behind and runs the rest. The L1 sees the
  // unit's look-ups in the same order as when each fragment waits whole, and the shared levels
  // the same requests at the same cycles, so every figure is the same; a waiting fragment is
  // then a few words, not the fragment.
  struct Timing {
    std::array<uint32_t, kSlots> ii{};        // extra issue cycles, by pipeline stage
    std::array<uint64_t, 2> front_latency{};  // extra latency of the front-end stages
    uint32_t misses = 0;     // its lines that missed the L1 (FetchStage keeps them)
    int32_t frame_end = -1;  // frames_[frame_end] ends before it (cycles taken then)
    bool local = false;      // no look-up was recorded (FetchStage::recorded_local): it stays here
  };
  void set_queued_timing(bool on);
  // Where process() writes the fragment's Timing (queued timing): the caller's slot for it, so
  // it is written once, in place (null: the unit's own).
  void set_timing_out(Timing* out) { timing_out_ = out ? out : &own_timing_; }
  // Nothing waits in the unit: a fixed-slot fragment whose look-ups all hit takes its whole way in
  // process() (timing_done(); commit_timing() then does nothing), as a unit on its own would.
  void set_issue_now(bool on) { issue_now_ = on; }
  // The cycle the fragment starts the cache stage (not meaningful if timing_done()).
  uint64_t begin_timing(const Timing& t);
  bool timing_done() const { return done_; }
  void commit_timing(const Timing& t);
  // Whether a fragment that stays in the unit may take its whole way at once, in process()
  // (then commit() does nothing), and be committed out of the global order (pending_local);
  // off when every fragment must be committed in that order (a timeline records the items in
  // commit order).
  void set_early_commit(bool on) { early_ = on; }

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
  int front_count(int m) const {
    const FrontEndStage* fe = paths_[static_cast<size_t>(m)].stages.front;
    return fe ? fe->count() : 0;
  }
  // The shading frames of the scene's primitives (indexed by Fragment::prim), which relief and
  // lighting need for the view vector. Without them a material with either effect is refused.
  void set_surfaces(std::vector<SurfaceFrame> frames) { surfaces_ = std::move(frames); }
  // Relief loop steps and height reads of material m over the run (0 without relief).
  uint64_t material_relief_steps(int m) const;
  uint64_t material_relief_fetches(int m) const;
  bool material_has_relief(int m) const;
  const MaterialSetup& material(int m) const { return mats_[static_cast<size_t>(m)]; }
  // Whether material m's colours come from FixedSampler (`filter.arithmetic = "fixed"`).
  bool material_fixed(int m) const { return paths_[static_cast<size_t>(m)].fixed != nullptr; }
  // Fixed-arithmetic materials' results from `board` (null: FixedSampler in process); its
  // fragments must use their material's own texture.
  void set_fixed_board(FixedSamplerBoard* board) { fixed_board_ = board; }
  // The last fixed-arithmetic fragment's FixedSampler result: levels, δ, texel addresses.
  const FixedSampler::Result& last_fixed() const { return fixed_last_; }
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
  // Summed over the materials' front ends.
  const FrontEndStats& front_end_stats() const;

  bool timing() const { return timing_; }
  // Checks what every timed run must satisfy: the total cycles, or a stage's last issue slot
  // when that ends later, are at least the stage's busy issue slots ÷ its lanes, and the total
  // cycles at least the DRAM channel's busy cycles. Throws
  // std::logic_error naming the stage and the figures if not (a defect of the model).
  void check_timing_invariants() const;
  uint64_t fragments() const { return fragments_; }
  uint64_t cycles() const { return pipe_ ? pipe_->run_end() : 0; }
  std::vector<BlockUse> blocks() const;
  // Blocks of compressed textures decoded: in the fetch stage (decompression after the L1)
  // or, counted by the first unit only, in the shared memory's decompressor.
  PerCompressedFormat decoded_blocks() const;
  // Fragments filtered on srgb8_a8 textures and the texels they read: what the sRGB decoder
  // works on (one per texel before the filter, one per fragment after it).
  uint64_t srgb_fragments() const;
  uint64_t srgb_texels() const;
  // The blocks material m used, with only its own operations and texels (cache excluded).
  std::vector<BlockUse> material_blocks(int m) const;
  // Fragments material m textured.
  uint64_t material_fragments(int m) const { return paths_[static_cast<size_t>(m)].fragments; }
  // What one operation (Fragment::op) cost material m's fragments: tallied for the explicit
  // operations only (index SampleOp::kSample stays 0; the material's other fragments are its
  // implicit samples). ops are those the operation's own datapath uses (LodUnit::ops_for, the
  // address generator's or the gather unit's, the blend's per tap); issue_cycles are the
  // address slot's (one per probe).
  struct OpTally {
    uint64_t fragments = 0, taps = 0, issue_cycles = 0;
    OpCounts ops;
  };
  using OpTallies = std::array<OpTally, kSampleOps>;
  const OpTallies& material_op_tallies(int m) const {
    return paths_[static_cast<size_t>(m)].op_tallies;
  }
  int material_count() const { return static_cast<int>(mats_.size()); }
  const ClockedPipeline* pipeline() const { return pipe_.get(); }
  const TextureCache& cache() const { return fetch_.cache(); }
  const MemorySystem& memory() const { return *mem_; }
  const TextureSet& textures() const { return textures_; }
  MemorySystem& memory() { return *mem_; }
  // Tag look-ups quad merging saved: lines a quad's earlier lane had looked up.
  uint64_t quad_merged_lookups() const { return fetch_.merged_lookups(); }
  const std::vector<FrameStats>& frames() const {
    // The current frame's cycles are the pipeline's so far (set here, not per fragment).
    if (pipe_ && !frames_.empty()) frames_.back().cycles = pipe_->run_end();
    return frames_;
  }

 private:
  // One material: its stages, the kernels chosen for them, and the fragments it textured.
  struct Path;
  // A sampler's LOD unit and address generator (with a fragment's offsets folded in).
  struct AltSampler {
    LodUnit lod;
    TexelAddressGen gen;
  };
  TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials,
              const PipelineSetup& setup, const TechTable& tech, bool timing,
              std::unique_ptr<MemorySystem> own, MemorySystem* shared, int unit);
  // The per-fragment datapath of one material, chosen at construction (filter, layout, the
  // number of front-end slots, functional or timed) so the hot path has no run-time switches
  // on the configuration.
  using Kernel = Rgba (TextureUnit::*)(const Fragment&, Path&, const Texture&, const ItemCost*);
  using BatchKernel = void (TextureUnit::*)(const Fragment*, size_t, Path&, const Texture&, Rgba*);
  struct Path {
    Kernel kernel = nullptr;
    Kernel layered_kernel = nullptr;  // for fragments on a layered texture (null: a filter stage)
    // The batched datapath (null: fragments go one by one) and the sampler it runs.
    BatchKernel batch_kernel = nullptr;
    std::shared_ptr<const LinearBatchSampler> batch;
    // `filter.arithmetic = "fixed"`: the colour is FixedSampler's (null: the float32 path's).
    std::shared_ptr<const FixedSampler> fixed;
    MaterialStages stages;
    // The material's sampler is unnormalised: every fragment takes process_op.
    bool unnormalized = false;
    // Sampler state other than the material's own, for fragments that pick it (a record's
    // `sampler`, its constant offsets): built on first use, by sampler id and offsets.
    std::map<uint32_t, std::unique_ptr<const AltSampler>> alt;
    uint64_t fragments = 0;
    uint64_t srgb_fragments = 0, srgb_texels = 0;  // on srgb8_a8 textures (filter_srgb)
    OpTallies op_tallies{};
  };
  // Sizes the pipeline's slots from every material's stages and builds it (timed).
  void plan_pipeline();
  // Kernels: kFront is the number of front-end slots of a timed unit, -1 for a functional
  // one, kAnyStages for a unit with other slots (relief, lighting) or timed in two steps.
  // process_any handles LOD → address → blend with the general tap list; process_linear a
  // bilinear or trilinear material with quads in registers (falling back to process_taps for
  // anisotropic fragments or a texture not in layout L); process_filter a filter stage.
  template <int kFront>
  Rgba process_any(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  template <FilterMode kFilter, TexelLayout L, int kFront>
  Rgba process_linear(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  template <int kFront>
  Rgba process_taps(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                    const LodResult& lod);
  Rgba process_filter(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  // A layered texture's fragment (cube, cube array, array): the face or layer selector, the
  // LOD on the face's derivatives, LayeredAddressGen's taps, then blend and fetch as
  // process_taps; never batched.
  template <int kFront>
  Rgba process_layered(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  // A 3-D texture's fragment (one by one): λ from the three derivatives of (u, v, r = f.w),
  // VolumeAddressGen's eight taps per level, blended as any taps; the cache reads the lines of
  // the texels' 3-D addresses (Texture::volume_address). Its probes: taps / taps_per_probe
  // (a 3-D level takes two of the 2-D address slot's cycles).
  template <int kFront>
  Rgba process_volume(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                      const AltSampler* alt);
  // A layered fragment's sampler state other than its material's (null: the material's);
  // throws when its sampler is unnormalised.
  const AltSampler* layered_sampler(const Fragment& f, Path& p, const Texture& tex);
  // A batch of fragments on one texture (n <= LinearBatch::kMax) through the batched sampler;
  // the fragments it leaves undone through process_linear.
  template <FilterMode kFilter, TexelLayout L, int kFront>
  void batch_linear(const Fragment* f, size_t n, Path& p, const Texture& tex, Rgba* out);
  // Timed: the cache look-ups and clocked pipeline of a batch the sampler filtered (b), in
  // order; the fragments it left undone through the scalar kernel.
  template <FilterMode kFilter, TexelLayout L, int kFront>
  void finish_timed_batch(const Fragment* f, size_t n, Path& p, const Texture& tex,
                          const LinearBatch& b, Rgba* out);
  // Timed, the batch's done fragments [first, end) with their lines (LinearBatch::has_lines):
  // their L1 look-ups in order first, then the clocked pipeline, the misses read from the level
  // behind at their fragment's cycle (FetchStage::looks_up_ahead); kQuads quads a fragment.
  template <int kQuads>
  void timed_run(const Fragment* f, size_t first, size_t end, Path& p, const LinearBatch& b);
  // The functional batch's colours out and its done fragments counted as count_fragment
  // would, in order; the undone ones through the scalar kernel.
  void finish_functional_batch(const Fragment* f, size_t n, Path& p, const LinearBatch& b,
                               Rgba* out);
  template <int kFront>
  static BatchKernel pick_batch_kernel(FilterMode filter, TexelLayout layout);
  // Sets p's batched datapath when material m can use one.
  void choose_batch(Path& p, const MaterialSetup& m);
  template <int kFront>
  static Kernel pick_kernel(FilterMode filter, TexelLayout layout, bool quads, bool layered);
  Kernel choose_kernel(const Path& p, bool layered = false) const;
  // Sends a fragment of the LOD → address → blend path through the clocked pipeline;
  // `lookups(start)` does its cache look-ups.
  template <int kFront, class Lookups>
  [[gnu::always_inline]] inline void issue_timed(Path& p, const ItemCost* front, uint32_t probes,
                                                 uint64_t texels, Lookups&& lookups);
  // The fixed slot sequence of a unit without relief or lighting slots.
  template <int kFront, class Lookups>
  [[gnu::always_inline]] inline void issue_fixed_stages(Path& p, const ItemCost* front,
                                                        uint32_t probes, uint64_t texels,
                                                        Lookups& lookups);
  // A unit of several with the fixed slot sequence: the first of its two steps (commit() the
  // second), unrolled.
  template <int kFront, class Lookups>
  void issue_two_step(Path& p, const ItemCost* front, uint32_t probes, uint64_t texels,
                      Lookups& lookups);
  // Any slot sequence, by index: the extra issue cycles of the address, cache and blend slots,
  // those the surface stages added, and the reads they staged before the cache look-ups.
  // address_latency: added to the address slot's latency for this item (a cube's face
  // selector, docs/texture-types.md §4).
  template <class Lookups>
  void issue_general(Path& p, const ItemCost* front, uint32_t address_ii, uint32_t cache_ii,
                     uint32_t blend_ii, Lookups&& lookups, uint64_t address_latency = 0);
  void count_fragment(const Fragment& f, Path& p, uint32_t probes) {
    ++p.fragments;
    p.stages.address->count(probes);
    count_frame(f);
  }
  Rgba filter_fragment(const Fragment& f, Path& p, const ItemCost* front);
  // A fixed-arithmetic material's fragment: the float32 kernel counts and times it (its texel
  // reads are the same but where λ rounds the other way), FixedSampler gives its colour.
  Rgba filter_fixed(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  // The memory image and description FixedSampler reads of texture t (made on first use).
  struct FixedTexture {
    FixedSampler::TextureDesc desc;
    std::vector<uint32_t> image;
  };
  const FixedTexture& fixed_texture(uint32_t t);
  std::map<uint32_t, FixedTexture> fixed_textures_;
  FixedSampler::Result fixed_last_;
  FixedSamplerBoard* fixed_board_ = nullptr;
  // process_batch() on a board: the batch's results fetched in one call, taken in order by
  // filter_fixed() while its inputs match (a fragment that does not match asks the board alone).
  std::vector<FixedSampler::Input> fixed_ahead_in_;
  std::vector<FixedSampler::Result> fixed_ahead_;
  size_t fixed_ahead_at_ = 0;
  // filter_fragment on an srgb8_a8 texture: counts the decoder's work, and decodes the filtered
  // colour when the decoder sits after the filter.
  Rgba filter_srgb(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  // A fragment with an explicit operation (f.op != 0): tallied, then a gather through the
  // gather unit, the others through the material's kernel.
  Rgba process_op(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  Rgba process_gather(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                      const TexelAddressGen::Config& c);
  // A fragment whose sampler state is not its material's own (another sampler of the table,
  // an unnormalised sampler, constant offsets of its own): the sampler's LOD unit and taps, then
  // the blend or the reducer, counted in the material's rows; never batched.
  Rgba process_alt(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front,
                   const AltSampler& s);
  const AltSampler& alt_sampler(const Fragment& f, Path& p, uint16_t sampler, bool gather);
  // A material whose sampler reduces (min/max) or compares depth: taps, then the reducer.
  Rgba process_reduced(const Fragment& f, Path& p, const Texture& tex, const ItemCost* front);
  // The surface stages' enter(), the filter, their leave() for a material with any.
  Rgba process_surface(const Fragment& f, Path& p, int material, const ItemCost* front);
  // Cost of front-end slot s for a fragment of path p (with the dropped fragments' cycles).
  ItemCost front_cost(const Path& p, const ItemCost* front, int s) {
    ItemCost c = p.stages.front ? p.stages.front->cost(front, s) : ItemCost{};
    c.extra_ii += owed_[s];
    owed_[s] = 0;
    return c;
  }
  void count_frame(const Fragment& f) {
    if (fetch_.quad_merge()) fetch_.note_quad(f);
    if (frames_.empty() || frames_.back().frame != f.frame) new_frame(f);
    ++frames_.back().fragments;
    ++fragments_;
  }
  void new_frame(const Fragment& f);
  // The first stage of type S of material m, or null (report time).
  template <class S>
  const S* find_stage(int m) const {
    for (const auto& s : paths_[static_cast<size_t>(m)].stages.all) {
      if (const auto* t = dynamic_cast<const S*>(s.get())) return t;
    }
    return nullptr;
  }

  TextureSet& textures_;
  std::vector<MaterialSetup> mats_;
  std::vector<Path> paths_;
  PipelineSetup setup_;
  TechTable tech_;
  TimingSpec cube_select_;  // the face selector's ii and latency (CubeFaceSelect::timing)
  bool timing_;
  // Compressed textures: the decompressor in the memory system, or the blocks in the L1.
  void attach_decoders();
  std::unique_ptr<MemorySystem> own_memory_;  // set: a unit on its own (first constructor)
  MemorySystem* mem_;
  FetchStage fetch_;  // the cache slot: this unit's L1 and the memory behind it
  // Two-step timing: the costs of the fragment in flight, its arrival and start at the cache
  // slot.
  bool defer_ = false;
  int unit_ = 0;  // index among the units sharing the memory system
  std::vector<ItemCost> defer_costs_;
  uint64_t defer_arrival_ = 0, defer_start_ = 0;
  // Two-step timing of the fixed slot sequence (front end, LOD, address, cache, blend): the
  // kernels and commit() unroll the stages.
  bool two_step_fixed_ = false;
  bool early_ = true, done_ = false;  // set_early_commit; the fragment in flight is done
  void commit_deferred();             // commit() of a fragment that waited for its turn
  void issue_deferred_tail();         // the stages from the cache slot on, with defer_costs_
  // Queued timing: the costs of the fragment processed (c[0 .. n)) as its Timing.
  void keep_timing(const ItemCost* c, int n);
  // begin_timing() and commit_timing() for the fixed slot sequence of kN stages: the costs
  // read from the Timing as the unrolled stages need them.
  template <int kN>
  uint64_t begin_fixed(const Timing& t, bool whole);
  template <int kN>
  void commit_fixed(const Timing& t, uint64_t wait);
  bool queued_ = false, issue_now_ = false;
  Timing own_timing_;
  Timing* timing_out_ = &own_timing_;
  int32_t frame_end_ = -1;  // queued timing: the frame the fragment being processed ended
  // Queued timing: the costs process() computes (defer_costs_ belong to the begun fragment).
  std::array<ItemCost, kSlots> scratch_{};
  // Runs the fragment through the pipeline with cost_at(stage, start) — at once, or in two
  // steps in a unit of several.
  template <class CostFn>
  void issue_any(CostFn&& cost_at);
  std::unique_ptr<ClockedPipeline> pipe_;
  FilterTaps taps_;
  std::unique_ptr<LinearBatch> batch_out_;  // the batched sampler's results
  // timed_run's lines that missed the L1, and per fragment where its own end (from index 1).
  std::vector<uint64_t> batch_missed_;
  std::vector<uint32_t> batch_missed_end_;
  uint64_t fragments_ = 0;
  // The sRGB decoder (its work counted per material, filter_srgb); texels a footprint filter
  // read, so far.
  SrgbDecoder srgb_;
  uint64_t filter_texels_ = 0;
  int front_ = 0;  // front-end slots
  // Pipeline stages of the address, cache and blend slots, and whether the pipeline is the
  // front end and those four sampler slots only (the fixed kernels).
  int address_ = 0, cache_slot_ = 0, blend_ = 0;
  bool sampler_only_ = true;
  // The current fragment's surface (process_surface), and the issue cycles its surface stages
  // add per pipeline stage (zero outside process_surface).
  const SurfaceItem* surface_ = nullptr;
  uint32_t item_extra_[kSlots] = {};
  std::vector<SurfaceFrame> surfaces_;
  uint32_t owed_[2] = {};  // issue cycles of dropped fragments, per front-end slot
  mutable FrontEndStats front_stats_;
  mutable std::vector<FrameStats> frames_;
};

}  // namespace texsim
