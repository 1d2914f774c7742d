#pragma once
// The texture units' memory: one L1 texture cache per unit, then (shared by all units) an
// optional L2 and the DRAM: the flat channel (a latency plus a bandwidth limit, the default) or
// channels, banks and row buffers. docs/timing-model.md#memory-hierarchy.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "blocks/texture/memory/banked_dram.h"
#include "blocks/texture/memory/dram_model.h"
#include "blocks/texture/memory/l2_cache.h"
#include "blocks/texture/memory/level_probe.h"
#include "blocks/texture/memory/line_memory.h"
#include "blocks/texture/memory/texture_cache.h"
#include "pipeline/texture/block_decompressor.h"
#include "pipeline/texture/pipeline_setup.h"

namespace texsim {

class MemorySystem {
 public:
  // `units` L1s of setup.cache, and the levels behind them from setup.
  MemorySystem(const PipelineSetup& setup, int units);
  // The levels point at each other (and the units at them): never copied or moved.
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;

  int units() const { return static_cast<int>(l1_.size()); }
  TextureCache& l1(int unit) { return *l1_[static_cast<size_t>(unit)]; }
  const TextureCache& l1(int unit) const { return *l1_[static_cast<size_t>(unit)]; }
  // Where an L1 miss goes.
  LineMemory& behind_l1() { return to_next_; }
  const L2Cache* l2() const { return l2_.get(); }
  const BankedDram* banked() const { return banked_.get(); }
  // With block-compressed textures in `textures` and decompression before the L1 or after
  // the L2: puts the decompressor in front of the level that holds decoded texels last.
  // Once, after the textures are placed.
  void attach_textures(const TextureSet& textures,
                       std::function<BlockDecompressor::Timing(CompressedFormat)> timing);
  const BlockDecompressor* decompressor() const { return decompressor_.get(); }
  // The L1s' counters summed.
  TextureCache::Stats l1_totals() const;
  // DRAM figures of either model: requests, bytes, and the busiest channel's busy cycles.
  DramModel::Stats dram_totals() const;
  // The levels behind the L1s, nearest first: {"l2", "dram"} or {"dram"}.
  std::vector<std::string> levels() const;
  // f(level, now, ready, unit) sees every request a level receives (level: an index into
  // levels()); the timing does not change.
  void observe(const std::function<void(int level, uint64_t now, uint64_t ready, int unit)>& f);

 private:
  std::vector<std::unique_ptr<TextureCache>> l1_;  // by unit; stable addresses
  DramModel dram_;
  std::unique_ptr<BankedDram> banked_;
  std::unique_ptr<L2Cache> l2_;
  // Requests into the level behind the L1s, and (with an L2) into the DRAM behind it.
  LevelProbe to_next_, to_dram_;
  LineMemory* dram_level_ = nullptr;  // the flat or the banked DRAM
  PipelineSetup::Decompress decompress_;
  std::unique_ptr<BlockDecompressor> decompressor_;
};

}  // namespace texsim
