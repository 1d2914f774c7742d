#include "pipeline/texture/memory_system.h"

#include <algorithm>
#include <stdexcept>

namespace texsim {

MemorySystem::MemorySystem(const PipelineSetup& setup, int units)
    : dram_(setup.dram), decompress_(setup.decompress) {
  if (units < 1 || units > static_cast<int>(PipelineSetup::kMaxUnits))
    throw std::invalid_argument("memory system: units must be in [1, 64]");
  for (int u = 0; u < units; ++u) l1_.push_back(std::make_unique<TextureCache>(setup.cache));
  LineMemory* dram = &dram_;
  if (setup.dram_kind == PipelineSetup::DramKind::Banked) {
    banked_ = std::make_unique<BankedDram>(setup.banked);
    banked_->validate(setup.has_l2 ? setup.l2.line_bytes : setup.cache.line_bytes);
    dram = banked_.get();
  }
  dram_level_ = dram;
  to_next_.set_next(dram);
  if (setup.has_l2) {
    to_dram_.set_next(dram);
    l2_ = std::make_unique<L2Cache>(setup.l2, to_dram_);
    l2_->validate(setup.cache.line_bytes);
    to_next_.set_next(l2_.get());
  }
}

void MemorySystem::attach_textures(
    const TextureSet& textures, std::function<BlockDecompressor::Timing(CompressedFormat)> timing) {
  if (decompressor_ || !textures.any_compressed() ||
      decompress_ == PipelineSetup::Decompress::AfterL1)
    return;
  if (decompress_ == PipelineSetup::Decompress::AfterL2) {  // between the L1s and the L2
    decompressor_ = std::make_unique<BlockDecompressor>(l2_.get(), &textures, std::move(timing));
    to_next_.set_next(decompressor_.get());
    return;
  }
  // Before the L1: in front of DRAM, so that every cache holds decoded texels.
  decompressor_ = std::make_unique<BlockDecompressor>(dram_level_, &textures, std::move(timing));
  (l2_ ? to_dram_ : to_next_).set_next(decompressor_.get());
}

std::vector<std::string> MemorySystem::levels() const {
  if (l2_) return {"l2", "dram"};
  return {"dram"};
}

void MemorySystem::observe(
    const std::function<void(int level, uint64_t now, uint64_t ready, int unit)>& f) {
  to_next_.set_observer([f](uint64_t now, uint64_t ready, int unit) { f(0, now, ready, unit); });
  if (l2_)
    to_dram_.set_observer([f](uint64_t now, uint64_t ready, int unit) { f(1, now, ready, unit); });
}

DramModel::Stats MemorySystem::dram_totals() const {
  if (!banked_) return dram_.stats();
  const BankedDram::Stats& b = banked_->stats();
  DramModel::Stats t;
  t.requests = b.requests;
  t.bytes = b.bytes;
  for (uint64_t c : b.bus_busy_cycles) t.busy_cycles = std::max(t.busy_cycles, c);
  return t;
}

TextureCache::Stats MemorySystem::l1_totals() const {
  TextureCache::Stats t;
  for (const auto& c : l1_) {
    const TextureCache::Stats& s = c->stats();
    t.accesses += s.accesses;
    t.hits += s.hits;
    t.misses += s.misses;
    t.texel_reads += s.texel_reads;
    t.fill_bytes += s.fill_bytes;
  }
  return t;
}

}  // namespace texsim
