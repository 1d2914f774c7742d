#pragma once
// The clocked texture unit (ПНТ, first slice): LOD → texel address generation → texture cache
// + DRAM → blend, built from a scene's materials. Only the blocks some material needs are
// instantiated. docs/architecture.md describes the stages; docs/timing-model.md the timing.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "blocks/dram_model.h"
#include "blocks/lod_unit.h"
#include "blocks/op_counts.h"
#include "blocks/tech_table.h"
#include "blocks/texel_address_gen.h"
#include "blocks/texel_blend.h"
#include "blocks/texture_cache.h"
#include "blocks/texture_memory.h"
#include "pipeline/clocked_pipeline.h"
#include "pipeline/footprint_filter.h"
#include "traces/fragment.h"

namespace texsim {

struct MaterialSetup {
  std::string name;
  int texture = 0;
  LodUnit::Config lod;
  TexelAddressGen::Config filter;
  // A footprint filter (EWA, multi-probe, Feline, SPAF) replaces the LOD → address → blend
  // path for this material when set; null for the classic path.
  std::shared_ptr<const FootprintFilter> footprint;
  AddressMode address_u() const { return footprint ? footprint->address_u() : filter.address_u; }
  AddressMode address_v() const { return footprint ? footprint->address_v() : filter.address_v; }
};

struct PipelineSetup {
  uint32_t fifo_depth = 4;
  TexelLayout layout = TexelLayout::Tiled4x4;
  TextureCache::Config cache;
  DramModel::Config dram;
  TexelBlend::Config blend;
  // Reads [pipeline] (keys fifo_depth, layout, cache, dram, blend); errors name file:line:col.
  static PipelineSetup from_toml(const toml::table& t, const std::string& source);
};

// Reads a material's effect tables ("filter", "lod") into a MaterialSetup.
MaterialSetup material_from_toml(const std::string& name, int texture, const toml::table& effects,
                                 const std::string& source);

struct BlockUse {
  std::string name;             // e.g. "lod", "filter.trilinear", "blend", "cache"
  std::string arithmetic;       // which number format the datapath uses
  TimingSpec timing;
  OpCounts ops;                 // total over the run
  std::vector<std::string> materials;  // materials that use it
};

struct FrameStats {
  uint32_t frame = 0;
  uint64_t fragments = 0;
  uint64_t cycles = 0;  // cycle at which the frame's last fragment left the pipeline
};

class TextureUnit {
 public:
  // With `timing` false the unit is functional only: colours and op counts, no cache or clock.
  TextureUnit(TextureSet& textures, std::vector<MaterialSetup> materials, const PipelineSetup& setup,
              const TechTable& tech, bool timing);

  // Filters one fragment with its material's blocks; in timing mode also sends it through the
  // clocked pipeline and the cache. Fragments must arrive in order.
  Rgba process(const Fragment& f, int material);

  bool timing() const { return timing_; }
  uint64_t fragments() const { return fragments_; }
  uint64_t cycles() const { return pipe_ ? pipe_->cycles() : 0; }
  std::vector<BlockUse> blocks() const;
  const ClockedPipeline* pipeline() const { return pipe_.get(); }
  const TextureCache& cache() const { return cache_; }
  const DramModel& dram() const { return dram_; }
  const std::vector<FrameStats>& frames() const {
    // The current frame's cycles are the pipeline's so far (set here, not per fragment).
    if (pipe_ && !frames_.empty()) frames_.back().cycles = pipe_->cycles();
    return frames_;
  }

 private:
  // One material's blocks. Op counts depend only on the probe number N of each fragment, so
  // the hot path counts fragments and probes and blocks() multiplies the per-fragment and
  // per-probe counts of the blocks: exact, and three increments instead of three OpCounts sums.
  struct Path {
    LodUnit lod;
    TexelAddressGen addr;
    int texture = 0;
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
  };
  // Tag look-ups of the fragment's distinct lines at cycle `start`; returns the cycles the
  // cache stage waits beyond its hit latency (DRAM refills).
  uint32_t cache_lookups(const FilterTaps& taps, const Texture& tex, uint64_t start);
  uint32_t cache_lookups(const std::vector<TexelRef>& texels, const Texture& tex, uint64_t start);
  Rgba process_footprint(const Fragment& f, Path& p, const Texture& tex);
  void count_frame(const Fragment& f);

  TextureSet& textures_;
  std::vector<MaterialSetup> mats_;
  std::vector<Path> paths_;
  PipelineSetup setup_;
  TechTable tech_;
  bool timing_;
  TexelBlend blend_;
  TextureCache cache_;
  DramModel dram_;
  std::unique_ptr<ClockedPipeline> pipe_;
  FilterTaps taps_;
  std::vector<TexelRef> fetched_;  // texels of the current footprint-filter fragment
  std::vector<uint64_t> lines_;
  uint64_t fragments_ = 0;
  mutable std::vector<FrameStats> frames_;
};

}  // namespace texsim
