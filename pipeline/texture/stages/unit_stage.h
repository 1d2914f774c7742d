#pragma once
// The stages a texture unit is assembled from (docs/architecture.md#the-texture-unit). Each
// effect of a material — coordinate front end, relief, LOD, address generation or a footprint
// filter, blend, lighting — is a stage object that owns its block's configuration, counters,
// timing and report rows. The unit's clocked pipeline has one stage per slot below that some
// material occupies, shared by the materials (one hardware unit each) and sized for the
// slowest of them; the texel fetch (the cache slot) is one per unit.
// Virtual calls are made at setup and report time only: per fragment, the unit's templated
// kernels call the stages' own non-virtual methods (a footprint or visibility-aware filter,
// relief and lighting, whose work per fragment is far larger, are called through their base).
#include <cstdint>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

#include "blocks/base/fragment.h"
#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/base/timing_spec.h"
#include "blocks/texture/memory/texture_memory.h"
#include "pipeline/geometry/surface_frame.h"
#include "pipeline/kernel/clocked_pipeline.h"

namespace texsim {

class FetchStage;

struct BlockUse {
  std::string name;        // e.g. "lod", "filter.trilinear", "blend", "cache"
  std::string arithmetic;  // which number format the datapath uses
  TimingSpec timing;
  OpCounts ops;                        // total over the run
  uint64_t texels = 0;                 // texels it fetched through the cache over the run
  std::vector<std::string> materials;  // materials that use it
  uint64_t border_taps = 0;  // taps that read the border colour instead (no texel, no memory)
};

// The unit's pipeline slots, in pipeline order.
enum class Slot : uint8_t { Coords, Derivs, Relief, Lod, Address, Cache, Blend, Lighting };
inline constexpr int kSlots = 8;

// The unit's clocked pipeline being planned: the slots some material's stage occupies, each
// sized for the slowest (and, in the front end, the widest) of them.
class SlotPlan {
 public:
  explicit SlotPlan(uint32_t fifo_depth) : fifo_depth_(fifo_depth) {}
  // A stage occupies slot s: the slot's latency is the largest, its lanes the most.
  void occupy(Slot s, uint32_t latency, uint32_t lanes = 1);
  // A block shared by every material (the same timing whoever declares it).
  void set(Slot s, const TimingSpec& t, uint32_t max_inflight = 0);
  bool has(Slot s) const { return present_[static_cast<int>(s)]; }
  const TimingSpec& timing(Slot s) const { return timing_[static_cast<int>(s)]; }
  // Assigns the present slots their pipeline stages, in slot order.
  void finish();
  // Pipeline stage of slot s after finish(); -1 when absent.
  int index(Slot s) const { return index_[static_cast<int>(s)]; }
  // Present slots in front of LOD that take a fragment's front-end costs (coordinates,
  // derivatives).
  int front_slots() const { return static_cast<int>(has(Slot::Coords)) + has(Slot::Derivs); }
  // Whether the pipeline is the front end then LOD, address, cache and blend only.
  bool sampler_only() const { return !has(Slot::Relief) && !has(Slot::Lighting); }
  std::vector<StageConfig> stages() const;

 private:
  uint32_t fifo_depth_;
  bool present_[kSlots] = {};
  TimingSpec timing_[kSlots];
  uint32_t inflight_[kSlots] = {};
  int index_[kSlots] = {-1, -1, -1, -1, -1, -1, -1, -1};
};

// What one material's report rows are made from: its name, the technology, the fragments it
// textured, and what earlier stages give later ones (the taps the address stage generated,
// which the blend blends).
struct StageReport {
  const std::string& material;
  const TechTable& tech;
  uint64_t fragments = 0;
  uint64_t taps = 0;
  uint64_t border_taps = 0;  // of those, the taps that read the border colour (no texel read)
  void add(std::vector<BlockUse>& out, std::string name, std::string arith, const TimingSpec& t,
           const OpCounts& ops, uint64_t texels = 0) const {
    out.push_back({std::move(name), std::move(arith), t, ops, texels, {material}});
  }
};

class UnitStage {
 public:
  virtual ~UnitStage() = default;
  // Sizes the slots the stage occupies.
  virtual void declare(SlotPlan& plan, const TechTable& tech) const = 0;
  // After the plan is final: what the stage takes from the shared slots (e.g. its throughput
  // in a slot sized for a wider unit, or the slot it adds issue cycles to).
  virtual void bind(const SlotPlan& /*plan*/, const TechTable& /*tech*/) {}
  // Appends the stage's report rows (none for a stage the material's fragments pass through).
  virtual void rows(StageReport& r, std::vector<BlockUse>& out) const = 0;
};

// A fragment of a material with stages around its filter (relief, lighting): its coordinates
// (which relief shifts), its primitive's shading frame and view vector, and the issue cycles
// those stages add, by pipeline stage.
struct SurfaceItem {
  Fragment g;
  const SurfaceFrame& sf;
  glm::dvec3 view_ts;
  bool timed = false;
  uint32_t* extra_ii = nullptr;  // one per pipeline stage (timed)
};

// A stage around the filter: enter() before the fragment is filtered, leave() after.
class SurfaceStage : public UnitStage {
 public:
  virtual void enter(SurfaceItem& it, FetchStage& fetch) = 0;
  virtual Rgba leave(const SurfaceItem& it, const Rgba& c) = 0;
};

// A filter other than LOD → address → blend (a footprint filter, the visibility-aware filter):
// one block that scans, weights and accumulates in the address slot; its texels go through
// the cache and the blend normalises.
class FilterStage : public UnitStage {
 public:
  struct Result {
    Rgba colour;
    uint32_t address_cycles = 1;  // issue cycles in the address slot (>= 1)
    uint64_t texels = 0;
    const std::vector<uint64_t>* lines = nullptr;  // their distinct cache lines (timed)
  };
  // `surface`: the fragment's surface (null for a material without relief or lighting).
  virtual Result filter(const Fragment& f, const Texture& tex, const SurfaceItem* surface,
                        bool timed, const FetchStage& fetch) = 0;
};

}  // namespace texsim
