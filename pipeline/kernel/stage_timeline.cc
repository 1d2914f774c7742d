#include "pipeline/kernel/stage_timeline.h"

#include <algorithm>
#include <ostream>

#include "blocks/base/atomic_file.h"

namespace texsim {

namespace {

// A VCD reference name: letters, digits and '_' only.
std::string vcd_name(const std::string& s) {
  std::string r;
  for (const char c : s) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    r += ok ? c : '_';
  }
  return r.empty() ? std::string("stage") : r;
}

// Identifier code of signal k: printable characters '!'..'~', several for large k.
std::string vcd_id(size_t k) {
  std::string id;
  do {
    id += static_cast<char>('!' + k % 94);
    k /= 94;
  } while (k > 0);
  return id;
}

std::string binary(uint64_t v) {
  std::string b;
  do {
    b += static_cast<char>('0' + (v & 1));
    v >>= 1;
  } while (v > 0);
  std::reverse(b.begin(), b.end());
  return b;
}

constexpr int kItemBits = 32, kInflightBits = 16;

}  // namespace

void StageTimeline::record(const ClockedPipeline& pipe, int unit) {
  const auto n = static_cast<size_t>(pipe.stage_count());
  const auto u = static_cast<size_t>(unit);
  if (u >= first_track_.size()) first_track_.resize(u + 1, -1);
  if (first_track_[u] < 0) {
    first_track_[u] = static_cast<int>(tracks_.size());
    for (size_t s = 0; s < n; ++s)
      tracks_.push_back({unit, pipe.config(static_cast<int>(s)).name, {}, {}});
  }
  for (size_t s = 0; s < n; ++s) {
    const ClockedPipeline::ItemTimes t = pipe.last_item(static_cast<int>(s));
    Track& k = tracks_[static_cast<size_t>(first_track_[u]) + s];
    k.starts.push_back(t.start);
    k.leaves.push_back(t.leave);
  }
  ++recorded_;
}

void StageTimeline::write_vcd(const std::string& path) const {
  AtomicTextFile file(path);
  std::ostream& o = file.out();
  // Tracks by unit, then stage (a unit's tracks were made together, in stage order), then the
  // memory levels' (their requests sorted: a level's answers do not come in order).
  std::vector<const Track*> order;
  for (const int first : first_track_) {
    if (first < 0) continue;
    for (size_t k = static_cast<size_t>(first);
         k < tracks_.size() && tracks_[k].unit == tracks_[static_cast<size_t>(first)].unit; ++k)
      order.push_back(&tracks_[k]);
  }
  std::vector<Track> memory;
  for (const Track& t : tracks_) {
    if (t.unit >= 0 || t.starts.empty()) continue;
    memory.push_back(t);
    std::sort(memory.back().starts.begin(), memory.back().starts.end());
    std::sort(memory.back().leaves.begin(), memory.back().leaves.end());
  }
  for (const Track& t : memory) order.push_back(&t);
  const size_t n = order.size();
  const bool units =
      std::count_if(first_track_.begin(), first_track_.end(), [](int f) { return f >= 0; }) > 1;
  o << "$version texsim run --timeline $end\n"
    << "$comment the clocked pipeline's stages: busy = an item in the stage, items = items "
       "issued to it, inflight = items in it; memory levels: requests made and outstanding; "
       "one time unit = one clock cycle; "
    << recorded_ << " of " << seen_ << " items recorded $end\n"
    << "$timescale 1ns $end\n"
    << "$scope module texsim_pipeline $end\n";
  // Each unit's stages in a scope unitN when there are several units; the levels in `memory`.
  auto group = [&](const Track* t) {
    return t->unit < 0 ? std::string("memory") : units ? "unit" + std::to_string(t->unit) : "";
  };
  for (size_t s = 0; s < n; ++s) {
    const std::string g = group(order[s]);
    if (s == 0 || g != group(order[s - 1])) {
      if (s > 0 && !group(order[s - 1]).empty()) o << "$upscope $end\n";
      if (!g.empty()) o << "$scope module " << g << " $end\n";
    }
    o << "$scope module " << vcd_name(order[s]->stage) << " $end\n"
      << "$var wire 1 " << vcd_id(3 * s) << " busy $end\n"
      << "$var wire " << kItemBits << " " << vcd_id(3 * s + 1) << " items [" << kItemBits - 1
      << ":0] $end\n"
      << "$var wire " << kInflightBits << " " << vcd_id(3 * s + 2) << " inflight ["
      << kInflightBits - 1 << ":0] $end\n"
      << "$upscope $end\n";
  }
  if (n > 0 && !group(order[n - 1]).empty()) o << "$upscope $end\n";
  o << "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n";
  for (size_t s = 0; s < n; ++s) {
    o << "0" << vcd_id(3 * s) << "\nb0 " << vcd_id(3 * s + 1) << "\nb0 " << vcd_id(3 * s + 2)
      << "\n";
  }
  o << "$end\n";

  // Every cycle at which some stage's counts change, then per stage the counts at that cycle.
  std::vector<uint64_t> times;
  for (size_t s = 0; s < n; ++s) {
    times.insert(times.end(), order[s]->starts.begin(), order[s]->starts.end());
    times.insert(times.end(), order[s]->leaves.begin(), order[s]->leaves.end());
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::vector<size_t> started(n, 0), left(n, 0), shown_items(n, 0), shown_inflight(n, 0);
  for (const uint64_t t : times) {
    bool stamped = t == 0;  // #0 is already open after $dumpvars
    for (size_t s = 0; s < n; ++s) {
      while (started[s] < order[s]->starts.size() && order[s]->starts[started[s]] <= t)
        ++started[s];
      while (left[s] < order[s]->leaves.size() && order[s]->leaves[left[s]] <= t) ++left[s];
      const size_t inflight = started[s] - left[s];
      if (started[s] == shown_items[s] && inflight == shown_inflight[s]) continue;
      if (!stamped) o << "#" << t << "\n";
      stamped = true;
      if ((inflight > 0) != (shown_inflight[s] > 0)) {
        o << (inflight > 0 ? "1" : "0") << vcd_id(3 * s) << "\n";
      }
      if (started[s] != shown_items[s])
        o << "b" << binary(started[s]) << " " << vcd_id(3 * s + 1) << "\n";
      if (inflight != shown_inflight[s])
        o << "b" << binary(inflight) << " " << vcd_id(3 * s + 2) << "\n";
      shown_items[s] = started[s];
      shown_inflight[s] = inflight;
    }
  }
  file.commit();
}

}  // namespace texsim
