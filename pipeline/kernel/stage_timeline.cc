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

void StageTimeline::record(const ClockedPipeline& pipe) {
  const auto n = static_cast<size_t>(pipe.stage_count());
  if (names_.empty()) {
    for (size_t s = 0; s < n; ++s) names_.push_back(pipe.config(static_cast<int>(s)).name);
    starts_.resize(n);
    leaves_.resize(n);
  }
  for (size_t s = 0; s < n; ++s) {
    const ClockedPipeline::ItemTimes t = pipe.last_item(static_cast<int>(s));
    starts_[s].push_back(t.start);
    leaves_[s].push_back(t.leave);
  }
  ++recorded_;
}

void StageTimeline::write_vcd(const std::string& path) const {
  AtomicTextFile file(path);
  std::ostream& o = file.out();
  const size_t n = names_.size();
  o << "$version texsim run --timeline $end\n"
    << "$comment the clocked pipeline's stages: busy = an item in the stage, items = items "
       "issued to it, inflight = items in it; one time unit = one clock cycle; "
    << recorded_ << " of " << seen_ << " items recorded $end\n"
    << "$timescale 1ns $end\n"
    << "$scope module texsim_pipeline $end\n";
  for (size_t s = 0; s < n; ++s) {
    o << "$scope module " << vcd_name(names_[s]) << " $end\n"
      << "$var wire 1 " << vcd_id(3 * s) << " busy $end\n"
      << "$var wire " << kItemBits << " " << vcd_id(3 * s + 1) << " items [" << kItemBits - 1
      << ":0] $end\n"
      << "$var wire " << kInflightBits << " " << vcd_id(3 * s + 2) << " inflight ["
      << kInflightBits - 1 << ":0] $end\n"
      << "$upscope $end\n";
  }
  o << "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n";
  for (size_t s = 0; s < n; ++s) {
    o << "0" << vcd_id(3 * s) << "\nb0 " << vcd_id(3 * s + 1) << "\nb0 " << vcd_id(3 * s + 2)
      << "\n";
  }
  o << "$end\n";

  // Every cycle at which some stage's counts change, then per stage the counts at that cycle.
  std::vector<uint64_t> times;
  for (size_t s = 0; s < n; ++s) {
    times.insert(times.end(), starts_[s].begin(), starts_[s].end());
    times.insert(times.end(), leaves_[s].begin(), leaves_[s].end());
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::vector<size_t> started(n, 0), left(n, 0), shown_items(n, 0), shown_inflight(n, 0);
  for (const uint64_t t : times) {
    bool stamped = t == 0;  // #0 is already open after $dumpvars
    for (size_t s = 0; s < n; ++s) {
      while (started[s] < starts_[s].size() && starts_[s][started[s]] <= t) ++started[s];
      while (left[s] < leaves_[s].size() && leaves_[s][left[s]] <= t) ++left[s];
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
