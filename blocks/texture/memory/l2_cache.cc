#include "blocks/texture/memory/l2_cache.h"

#include <algorithm>
#include <bit>
#include <limits>
#include <stdexcept>

#include "blocks/base/block.h"

namespace texsim {

static_assert(Block<L2Cache>);

namespace {
constexpr uint64_t kInvalid = std::numeric_limits<uint64_t>::max();
}

L2Cache::Config L2Cache::Config::from_toml(const ConfigReader& r) {
  r.reject_unknown(
      {"size_bytes", "ways", "line_bytes", "slices", "ports", "hit_latency", "mshrs", "prefetch"});
  Config c;
  c.size_bytes = static_cast<uint32_t>(r.get_int("size_bytes", c.size_bytes, 1024, 1 << 30));
  c.ways = static_cast<uint32_t>(r.get_int("ways", c.ways, 1, 64));
  c.line_bytes = static_cast<uint32_t>(r.get_int("line_bytes", c.line_bytes, 16, 4096));
  c.slices = static_cast<uint32_t>(r.get_int("slices", c.slices, 1, 64));
  c.ports = static_cast<uint32_t>(r.get_int("ports", c.ports, 1, 64));
  c.hit_latency = static_cast<uint32_t>(r.get_int("hit_latency", c.hit_latency, 1, 1000));
  c.mshrs = static_cast<uint32_t>(r.get_int("mshrs", c.mshrs, 1, 4096));
  c.prefetch = static_cast<Prefetch>(
      r.get_choice("prefetch", static_cast<int>(c.prefetch), {"none", "next_line"}));
  if (!std::has_single_bit(c.line_bytes)) r.fail("line_bytes", "must be a power of two");
  if (!std::has_single_bit(c.slices)) r.fail("slices", "must be a power of two");
  const uint64_t per_set = uint64_t{c.slices} * c.ways * c.line_bytes;
  if (c.size_bytes % per_set != 0 || !std::has_single_bit(c.size_bytes / per_set)) {
    r.fail("size_bytes", "must be slices x ways x line_bytes x (a power of two) sets; " +
                             std::to_string(c.size_bytes) + " is not a multiple of " +
                             std::to_string(per_set) + " by a power of two");
  }
  return c;
}

std::string L2Cache::Config::line_error(uint32_t l1_line_bytes) const {
  if (l1_line_bytes == 0 || !std::has_single_bit(l1_line_bytes) || l1_line_bytes > line_bytes) {
    return "l2.line_bytes (" + std::to_string(line_bytes) + ") must be a multiple of the " +
           std::to_string(l1_line_bytes) + "-byte L1 line";
  }
  return "";
}

L2Cache::L2Cache(const Config& c, LineMemory& next) : cfg_(c), next_(&next) {
  if (!std::has_single_bit(c.line_bytes) || !std::has_single_bit(c.slices) || c.ways == 0 ||
      c.ports == 0 || c.mshrs == 0) {
    throw std::invalid_argument("l2: bad geometry");
  }
  const uint64_t per_set = uint64_t{c.slices} * c.ways * c.line_bytes;
  if (c.size_bytes % per_set != 0 || !std::has_single_bit(c.size_bytes / per_set))
    throw std::invalid_argument("l2: sets per slice must be 2^n");
  sets_ = static_cast<uint32_t>(c.size_bytes / per_set);
  line_shift_ = static_cast<uint32_t>(std::countr_zero(c.line_bytes));
  slice_bits_ = static_cast<uint32_t>(std::countr_zero(c.slices));
  ways_.assign(static_cast<size_t>(c.slices) * sets_ * c.ways, Way{kInvalid, 0, 0, false});
  slices_.resize(c.slices);
  for (Slice& s : slices_) s.mshr_release.assign(c.mshrs, 0);
  stats_.slice_accesses.assign(c.slices, 0);
}

void L2Cache::validate(uint32_t l1_line_bytes) const {
  if (const std::string e = cfg_.line_error(l1_line_bytes); !e.empty())
    throw std::invalid_argument(e);
}

uint64_t L2Cache::accept(Slice& s, uint64_t now) {
  // In call order: a request is accepted no earlier than the one before it in its slice.
  if (now > s.port_cycle) {
    s.port_cycle = now;
    s.port_used = 0;
  } else if (s.port_used == cfg_.ports) {
    ++s.port_cycle;
    s.port_used = 0;
  }
  ++s.port_used;
  return s.port_cycle;
}

size_t L2Cache::take_mshr(Slice& s, uint64_t t, uint64_t& issue) {
  const auto it = std::min_element(s.mshr_release.begin(), s.mshr_release.end());
  issue = std::max(t, *it);
  return static_cast<size_t>(it - s.mshr_release.begin());
}

L2Cache::Way* L2Cache::find(uint64_t line) {
  const uint64_t slice = line & (cfg_.slices - 1);
  const uint64_t set = (line >> slice_bits_) & (sets_ - 1);
  Way* const w = ways_.data() + (slice * sets_ + set) * cfg_.ways;
  for (uint32_t i = 0; i < cfg_.ways; ++i) {
    if (w[i].tag == line) return w + i;
  }
  return nullptr;
}

L2Cache::Way* L2Cache::victim(uint64_t line) {
  // The least recently used way of the line's set (the first of equals; empty ways have 0).
  const uint64_t slice = line & (cfg_.slices - 1);
  const uint64_t set = (line >> slice_bits_) & (sets_ - 1);
  Way* const w = ways_.data() + (slice * sets_ + set) * cfg_.ways;
  return std::min_element(w, w + cfg_.ways,
                          [](const Way& a, const Way& b) { return a.stamp < b.stamp; });
}

void L2Cache::prefetch(uint64_t line, uint64_t issue, int unit) {
  if (find(line) != nullptr) return;
  Slice& s = slices_[line & (cfg_.slices - 1)];
  uint64_t free_at = 0;
  const size_t m = take_mshr(s, issue, free_at);
  if (free_at > issue) return;  // no MSHR free now: a prefetch never waits
  Way* const v = victim(line);
  if (v->stamp == clock_) return;  // would evict the demand line just allocated (one way)
  const uint64_t fill = next_->read_line(issue, line << line_shift_, cfg_.line_bytes, unit);
  s.mshr_release[m] = fill;
  *v = Way{line, ++clock_, fill, true};
  ++stats_.prefetches_issued;
  stats_.fill_bytes += cfg_.line_bytes;
}

uint64_t L2Cache::read_line(uint64_t now, uint64_t addr, uint32_t bytes, int unit) {
  if (bytes == 0 || !std::has_single_bit(bytes) || bytes > cfg_.line_bytes || addr % bytes != 0) {
    validate(bytes);
    throw std::invalid_argument("l2: line address " + std::to_string(addr) +
                                " is not a multiple of its size " + std::to_string(bytes));
  }
  const uint64_t line = addr >> line_shift_;
  const uint32_t slice_index = static_cast<uint32_t>(line & (cfg_.slices - 1));
  Slice& s = slices_[slice_index];
  ++stats_.accesses;
  ++stats_.slice_accesses[slice_index];
  const uint64_t accepted = accept(s, now);
  if (accepted > now) {
    ++stats_.bank_conflicts;
    stats_.bank_conflict_cycles += accepted - now;
  }
  const uint64_t checked = accepted + cfg_.hit_latency;
  if (Way* w = find(line)) {
    w->stamp = ++clock_;
    if (w->prefetched) {
      ++stats_.prefetches_useful;
      w->prefetched = false;
    }
    if (w->fill_ready > accepted) {
      ++stats_.mshr_merges;
      return std::max(checked, w->fill_ready);
    }
    ++stats_.hits;
    return checked;
  }
  ++stats_.misses;
  uint64_t issue = 0;
  const size_t m = take_mshr(s, checked, issue);
  if (issue > checked) {
    ++stats_.mshr_stalls;
    stats_.mshr_stall_cycles += issue - checked;
  }
  const uint64_t fill = next_->read_line(issue, line << line_shift_, cfg_.line_bytes, unit);
  s.mshr_release[m] = fill;
  *victim(line) = Way{line, ++clock_, fill, false};
  stats_.fill_bytes += cfg_.line_bytes;
  if (cfg_.prefetch == Prefetch::NextLine) prefetch(line + 1, issue, unit);
  return fill;
}

TimingSpec L2Cache::timing(const TechTable& tech) const {
  return derive_timing(tech, OpCounts{}, static_cast<double>(cfg_.hit_latency), Datapath::Spatial,
                       cfg_.slices * cfg_.ports);
}

}  // namespace texsim
