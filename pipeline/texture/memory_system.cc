#include "pipeline/texture/memory_system.h"

#include <stdexcept>

namespace texsim {

MemorySystem::MemorySystem(const PipelineSetup& setup, int units) : dram_(setup.dram) {
  if (units < 1 || units > static_cast<int>(PipelineSetup::kMaxUnits))
    throw std::invalid_argument("memory system: units must be in [1, 64]");
  for (int u = 0; u < units; ++u) l1_.push_back(std::make_unique<TextureCache>(setup.cache));
  behind_l1_ = &dram_;
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
