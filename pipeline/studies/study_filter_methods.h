#pragma once
// The methods `texsim study filters` compares. Every hardware method is a texture-unit
// material: the trilinear baselines are LOD + trilinear address configurations, the footprint
// filters (EWA, weight maps, multi-ellipse probes, Feline, SPAF) are MaterialSetup::footprint
// blocks, so the study's cycles are the cycles `texsim run` simulates. Software peers
// (OpenImageIO's lookups, Mesa's rendered views) are functional only.
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/scene/scene.h"
#include "pipeline/studies/study_filters.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

// Per-fragment figures a footprint block reports beyond the texture unit's counters: its
// statistics, and the shader-like issue model computed from its op counts (not a pipeline
// model: what the same arithmetic and reads would cost issued on a shader core).
struct FilterTally {
  OpCounts ops;
  uint64_t texels = 0, visited = 0, map_reads = 0, fallbacks = 0;
  double shader_cycles = 0;
};

// Shader-like issue model: the arithmetic runs on ALUs issuing kAluOpsPerCycle; each texel
// read (and each filtered weight-map read) is one texture instruction, kTexFetchesPerCycle;
// the slower of the two bounds the fragment.
constexpr double kAluOpsPerCycle = 16.0;
constexpr double kTexFetchesPerCycle = 4.0;

// The issue model's rates as a parameter: the default is the study's 16 : 4 (4 : 1); the
// thesis's platform, a Radeon RX 460 (896 ALU lanes, 56 texture units), is 16 : 1
// (ShaderIssue::rx460(): the same texture rate, four times the ALU rate).
struct ShaderIssue {
  double alu_per_cycle = kAluOpsPerCycle;
  double tex_per_cycle = kTexFetchesPerCycle;
  double ratio() const { return alu_per_cycle / tex_per_cycle; }
  static ShaderIssue rx460() { return {896.0 / 56.0 * kTexFetchesPerCycle, kTexFetchesPerCycle}; }
};

// A footprint block as the texture unit's FootprintFilter that also tallies what each call
// reports (the unit calls filter() once per fragment, in order).
class TalliedFootprint : public FootprintFilter {
 public:
  // Weight-map reads the shader model leaves to the texture unit: `entries` entries per
  // filtered read, `tmu_ops` arithmetic per read done there (0, 0: no map).
  void set_map_read(uint32_t entries, double tmu_ops) {
    entries_per_map_read_ = entries;
    tmu_ops_per_map_read_ = tmu_ops;
  }
  const FilterTally& tally() const { return tally_; }
  // Clears the tally; the shader-like model of the calls that follow uses `issue`.
  void reset_tally(const ShaderIssue& issue = {}) const {
    tally_ = {};
    issue_ = issue;
  }

 protected:
  void count(const OpCounts& ops, const FilterStats& s) const;

 private:
  uint32_t entries_per_map_read_ = 0;
  double tmu_ops_per_map_read_ = 0;
  // Mutable: the unit holds its filter const; the tally is an observer's record, not state
  // the filter's result depends on.
  mutable FilterTally tally_;
  mutable ShaderIssue issue_;
};

struct StudyFilterMethod {
  std::string name;
  std::string family;  // baseline, ewa, weights, weight map, probes, spaf, oiio, mesa
  std::string arithmetic;
  MaterialSetup material;                           // hardware: the texture unit's material
  std::shared_ptr<const TalliedFootprint> tallied;  // its footprint block (null: baseline)
  // Software peer: a functional lookup without cycles or cache (empty for hardware methods).
  std::function<Rgba(const Texture&, const Fragment&)> peer;
  // Software renderer: draws the whole view (the study's scene of one plane) and returns the
  // colours of `fragments`' pixels, in their order (empty for other methods).
  std::function<std::vector<Rgba>(const Texture&, const Scene& view,
                                  const std::vector<Fragment>& fragments)>
      render;
  std::string compare_to;  // also report the NMSE of this method's image against that method's
  uint64_t map_bytes = 0;  // weight-map memory
  bool hardware() const { return !peer && !render; }
};

// Every method of the study, in table order; `opt.oiio` adds the OpenImageIO peer, `opt.mesa`
// the Mesa rows whose driver starts (a driver that cannot start is named in `log`, if given).
std::vector<StudyFilterMethod> study_filter_methods(const StudyFiltersOptions& opt,
                                                    std::ostream* log = nullptr);

// The methods `texsim study thesis` compares (docs/studies/thesis-configuration.md): texsim's
// configuration (reconstruction term 1, Cholesky map transform, exact weights) and the thesis
// configuration (no reconstruction term, the seed's formula (5) map transform and θ/L/d weight
// rule), each with computed, mapped, uniform and V(d)-edge weights. Names are stable: the study
// looks them up (kThesis* below).
std::vector<StudyFilterMethod> thesis_filter_methods();

// One method over one view's fragments: colours in fragment order and what it cost.
struct StudyFilterRun {
  std::vector<Rgba> colours;
  FilterTally tally;     // ops, texels, … and the shader-like model
  uint64_t cycles = 0;   // the texture unit's cycles (hardware methods)
  uint64_t misses = 0;   // its texture cache's misses
  uint32_t latency = 0;  // LOD + address/filter stage latency of the unit
  double area = 0;       // the unit's LOD and filter datapaths (blend excluded)
};

// Runs `m` over `fragments` (in order) on texture 0 of `textures`: a hardware method through a
// fresh TextureUnit with the default [pipeline] (PipelineSetup{}) and its material, timing on;
// a software peer functionally; a renderer draws `view` (required for it). `issue`: the
// shader-like model's rates.
StudyFilterRun run_study_filter_method(const StudyFilterMethod& m, TextureSet& textures,
                                       const std::vector<Fragment>& fragments,
                                       const TechTable& tech, const Scene* view = nullptr,
                                       const ShaderIssue& issue = {});

}  // namespace texsim
