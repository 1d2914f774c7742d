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

std::vector<const StageTimeline::Track*> StageTimeline::ordered_tracks(
    std::vector<Track>& memory) const {
  // Tracks by unit, then stage (a unit's tracks were made together, in stage order), then the
  // memory levels' (their requests sorted: a level's answers do not come in order).
  std::vector<const Track*> order;
  for (const int first : first_track_) {
    if (first < 0) continue;
    for (size_t k = static_cast<size_t>(first);
         k < tracks_.size() && tracks_[k].unit == tracks_[static_cast<size_t>(first)].unit; ++k)
      order.push_back(&tracks_[k]);
  }
  memory.clear();
  for (const Track& t : tracks_) {
    if (t.unit >= 0 || t.starts.empty()) continue;
    memory.push_back(t);
    std::sort(memory.back().starts.begin(), memory.back().starts.end());
    std::sort(memory.back().leaves.begin(), memory.back().leaves.end());
  }
  for (const Track& t : memory) order.push_back(&t);
  return order;
}

bool StageTimeline::several_units() const {
  return std::count_if(first_track_.begin(), first_track_.end(), [](int f) { return f >= 0; }) > 1;
}

void StageTimeline::write_vcd(const std::string& path) const {
  AtomicTextFile file(path);
  std::ostream& o = file.out();
  std::vector<Track> memory;
  const std::vector<const Track*> order = ordered_tracks(memory);
  const size_t n = order.size();
  const bool units = several_units();
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

namespace {

// A JSON string literal of `s` (stage and level names are plain words; escaped to be safe).
std::string json_string(const std::string& s) {
  std::string r = "\"";
  for (const char c : s) {
    if (c == '"' || c == '\\') {
      r += '\\';
      r += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      r += ' ';
    } else {
      r += c;
    }
  }
  return r + "\"";
}

}  // namespace

void StageTimeline::write_trace_events(const std::string& path) const {
  AtomicTextFile file(path);
  std::ostream& o = file.out();
  std::vector<Track> memory;
  const std::vector<const Track*> order = ordered_tracks(memory);
  // One process per unit (pid = unit) and one for the memory levels (pid = the last unit + 1);
  // one thread per stage or level. 1 µs on the viewer's time axis is one clock cycle.
  int memory_pid = 0;
  for (const Track* t : order) memory_pid = std::max(memory_pid, t->unit + 1);
  const bool units = several_units();
  o << "{\"displayTimeUnit\":\"ns\",\"otherData\":{\"generator\":\"texsim run --timeline\","
    << "\"time_unit\":\"1 us = 1 clock cycle\",\"items_recorded\":" << recorded_
    << ",\"items_seen\":" << seen_ << "},\"traceEvents\":[\n";
  bool first_event = true;
  auto event = [&](const std::string& body) {
    o << (first_event ? "" : ",\n") << "{" << body << "}";
    first_event = false;
  };
  int previous_pid = -1;
  for (size_t s = 0; s < order.size(); ++s) {
    const Track& t = *order[s];
    const int pid = t.unit < 0 ? memory_pid : t.unit;
    const std::string ids = "\"pid\":" + std::to_string(pid) + ",\"tid\":" + std::to_string(s);
    if (pid != previous_pid) {
      const std::string name = t.unit < 0 ? std::string("memory")
                               : units    ? "unit " + std::to_string(t.unit)
                                          : std::string("texture unit");
      event("\"ph\":\"M\",\"name\":\"process_name\",\"pid\":" + std::to_string(pid) +
            ",\"args\":{\"name\":" + json_string(name) + "}");
      event("\"ph\":\"M\",\"name\":\"process_sort_index\",\"pid\":" + std::to_string(pid) +
            ",\"args\":{\"sort_index\":" + std::to_string(pid) + "}");
      previous_pid = pid;
    }
    event("\"ph\":\"M\",\"name\":\"thread_name\"," + ids +
          ",\"args\":{\"name\":" + json_string(t.stage) + "}");
    event("\"ph\":\"M\",\"name\":\"thread_sort_index\"," + ids +
          ",\"args\":{\"sort_index\":" + std::to_string(s) + "}");
    // Sweep the track's starts and leaves (both sorted): a busy slice while items are in it,
    // with the items that started in it; a counter sample where the in-flight count changes.
    size_t started = 0, left = 0, slice_items = 0;
    uint64_t slice_start = 0;
    while (started < t.starts.size() || left < t.leaves.size()) {
      const uint64_t now = left < t.leaves.size() && (started == t.starts.size() ||
                                                      t.leaves[left] <= t.starts[started])
                               ? t.leaves[left]
                               : t.starts[started];
      const size_t before = started - left;
      for (; started < t.starts.size() && t.starts[started] <= now; ++started) ++slice_items;
      while (left < t.leaves.size() && t.leaves[left] <= now) ++left;
      const size_t inflight = started - left;
      if (before == 0 && inflight > 0) slice_start = now;
      if (before > 0 && inflight == 0) {
        event("\"ph\":\"X\",\"name\":\"busy\",\"cat\":\"stage\"," + ids + ",\"ts\":" +
              std::to_string(slice_start) + ",\"dur\":" + std::to_string(now - slice_start) +
              ",\"args\":{\"items\":" + std::to_string(slice_items) + "}");
        slice_items = 0;
      }
      if (inflight != before) {
        event("\"ph\":\"C\",\"name\":" + json_string(t.stage + " in flight") +
              ",\"pid\":" + std::to_string(pid) + ",\"ts\":" + std::to_string(now) +
              ",\"args\":{\"items\":" + std::to_string(inflight) + "}");
      }
    }
  }
  o << "\n]}\n";
  file.commit();
}

void StageTimeline::write(const std::string& path) const {
  const bool json = path.size() >= 5 && path.compare(path.size() - 5, 5, ".json") == 0;
  if (json) {
    write_trace_events(path);
  } else {
    write_vcd(path);
  }
}

}  // namespace texsim
