#include "blocks/texture/memory/dram_model.h"

#include <algorithm>
#include <cmath>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<DramModel>);

DramModel::Config DramModel::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({"latency", "bytes_per_cycle"});
  Config c;
  c.latency = static_cast<uint32_t>(r.get_int("latency", c.latency, 0, 1'000'000));
  c.bytes_per_cycle = r.get_double("bytes_per_cycle", c.bytes_per_cycle);
  if (!(c.bytes_per_cycle >= kMinBytesPerCycle && c.bytes_per_cycle <= 1e6)) {
    r.fail("bytes_per_cycle", "must be in [1/1024, 1e6]");
  }
  return c;
}

DramModel::DramModel() : cfg_(Config{}) {}

TimingSpec DramModel::timing(const TechTable& tech) const {
  return derive_timing(tech, OpCounts{}, static_cast<double>(cfg_.latency), Datapath::Spatial);
}

uint64_t DramModel::read(uint64_t now, uint32_t bytes) {
  const double transfer = bytes / cfg_.bytes_per_cycle;
  const double start = std::max(static_cast<double>(now), channel_free_);
  channel_free_ = start + transfer;
  ++stats_.requests;
  stats_.bytes += bytes;
  busy_ += transfer;
  stats_.busy_cycles = static_cast<uint64_t>(std::ceil(busy_));
  return static_cast<uint64_t>(std::ceil(channel_free_)) + cfg_.latency;
}

}  // namespace texsim
