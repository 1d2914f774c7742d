#pragma once
// The texture units' memory: one L1 texture cache per unit, and the level behind the L1s
// (shared by all units). Today's default is one unit whose L1 misses go to the flat DRAM
// (a latency plus a bandwidth-limited channel). docs/timing-model.md#memory-hierarchy.
#include <cstdint>
#include <memory>
#include <vector>

#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/line_memory.h"
#include "blocks/texture/memory/texture_cache.h"
#include "pipeline/texture/pipeline_setup.h"

namespace texsim {

class MemorySystem {
 public:
  // `units` L1s of setup.cache, and the levels behind them from setup.
  MemorySystem(const PipelineSetup& setup, int units);

  int units() const { return static_cast<int>(l1_.size()); }
  TextureCache& l1(int unit) { return *l1_[static_cast<size_t>(unit)]; }
  const TextureCache& l1(int unit) const { return *l1_[static_cast<size_t>(unit)]; }
  // Where an L1 miss goes.
  LineMemory& behind_l1() { return *behind_l1_; }
  const DramModel& dram() const { return dram_; }
  // The L1s' counters summed.
  TextureCache::Stats l1_totals() const;

 private:
  std::vector<std::unique_ptr<TextureCache>> l1_;  // by unit; stable addresses
  DramModel dram_;
  LineMemory* behind_l1_ = nullptr;
};

}  // namespace texsim
