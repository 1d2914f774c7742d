#include "blocks/raster/rect_scan/outline_comparator.h"

#include "blocks/base/block.h"
#include "blocks/base/config_reader.h"

namespace texsim {

static_assert(Block<OutlineComparator>);

OutlineComparator::Config OutlineComparator::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown({});
  return {};
}

OutlineMemory::OutlineMemory(const RowLine& line, int32_t major0, int32_t major1, int32_t minor0,
                             int32_t minor1)
    : line_(line), major0_(major0), major1_(major1), minor0_(minor0), minor1_(minor1) {
  if (major1_ >= major0_ && minor1_ >= minor0_) {
    words_.assign(
        static_cast<size_t>(major1_ - major0_ + 1) * static_cast<size_t>(minor1_ - minor0_ + 1), 0);
  }
}

uint64_t OutlineMemory::draw(const EdgeRasterizer::Setup& st) {
  // The hardware draws each edge line with a DDA along the rows (additions only); the model
  // marks the same pixels by comparing the sides of consecutive pixels of each digital row.
  uint64_t marks = 0;
  if (words_.empty()) return 0;
  const auto side = [&](int e, int32_t major, int32_t minor) {
    const int32_t x = line_.x_major ? major : minor, y = line_.x_major ? minor : major;
    return EdgeRasterizer::inside(st, e, EdgeRasterizer::edge_value(st, e, x, y));
  };
  for (int32_t major = major0_ + 1; major <= major1_; ++major) {
    const int64_t n = major - major0_;
    const auto dm = static_cast<int32_t>(line_.offset(n) - line_.offset(n - 1));
    for (int32_t minor = minor0_; minor <= minor1_; ++minor) {
      uint8_t w = 0;
      for (int e = 0; e < 3; ++e) {
        if (side(e, major, minor) != side(e, major - 1, minor - dm))
          w |= static_cast<uint8_t>(1 << e);
      }
      words_[index(major, minor)] = w;
      marks += w != 0;
    }
  }
  return marks;
}

OpCounts OutlineComparator::ops_per_item() const {
  OpCounts o;
  o.mem = 1;
  o.cmp = 1;
  return o;
}

TimingSpec OutlineComparator::timing(const TechTable& t) const {
  return derive_timing(t, ops_per_item(), ops_per_item(), Datapath::Spatial);
}

}  // namespace texsim
