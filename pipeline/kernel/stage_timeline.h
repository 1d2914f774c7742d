#pragma once
// The clocked pipeline's stage activity over a run, written as a VCD for GTKWave (`texsim run
// --timeline FILE.vcd`, docs/cli.md) or as Chrome trace events for Perfetto (`FILE.json`). After
// each item the caller hands the pipeline to observe(), which copies the item's start and leave
// cycle in every stage (nothing is recorded when no timeline is asked for: the caller holds no
// StageTimeline). Per stage the VCD has a wire `busy` (an item is in the stage: issued, in flight
// or waiting to leave), a vector `items` (items issued to the stage so far) and a vector `inflight`
// (items in it now); one time unit is one clock cycle.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/kernel/clocked_pipeline.h"

namespace texsim {

class StageTimeline {
 public:
  // Records at most `limit` items (the first ones); later items are counted, not recorded.
  explicit StageTimeline(uint64_t limit) : limit_(limit) {}

  // Call after each fragment of texture unit `unit` (0 for a run of one unit) with its
  // pipeline: records the pipeline's last item if it is new. With several units each unit's
  // stages are a scope `unitN` of their own.
  void observe(const ClockedPipeline& pipe, int unit = 0) {
    const auto u = static_cast<size_t>(unit);
    if (u >= seen_by_unit_.size()) seen_by_unit_.resize(u + 1, 0);
    if (pipe.items() == seen_by_unit_[u]) return;
    seen_ += pipe.items() - seen_by_unit_[u];
    seen_by_unit_[u] = pipe.items();
    if (recorded_ >= limit_) return;
    record(pipe, unit);
  }

  // A memory level's track ("l2", "dram"): in the VCD's scope `memory`, busy while a request
  // is outstanding, items = requests made, inflight = requests outstanding. Returns its index
  // for observe_request.
  int memory_track(const std::string& level) {
    tracks_.push_back({-1, level, {}, {}});
    return static_cast<int>(tracks_.size()) - 1;
  }
  // A request to the level made at `now`, its data there at `ready`; recorded while the
  // fragments are (the first `limit`).
  void observe_request(int track, uint64_t now, uint64_t ready) {
    if (recorded_ >= limit_) return;
    Track& t = tracks_[static_cast<size_t>(track)];
    t.starts.push_back(now);
    t.leaves.push_back(ready);
  }

  uint64_t recorded() const { return recorded_; }
  uint64_t seen() const { return seen_; }
  // " (R of N fragments)", for the run's log.
  std::string summary() const {
    return " (" + std::to_string(recorded_) + " of " + std::to_string(seen_) + " fragments)";
  }

  // Writes the VCD to `path` atomically (throws InputError naming it if it cannot).
  void write_vcd(const std::string& path) const;
  // Writes the same activity in the Chrome trace-event format (JSON; Perfetto's UI and
  // chrome://tracing open it): a process per unit and one for the memory levels, a thread per
  // stage or level with `busy` slices, and an in-flight counter per stage; 1 µs = 1 cycle.
  void write_trace_events(const std::string& path) const;
  // Writes the format the file name asks for: trace events for a name ending in `.json`, a VCD
  // otherwise.
  void write(const std::string& path) const;

 private:
  void record(const ClockedPipeline& pipe, int unit);

  // One stage of one unit: its recorded items' start and leave cycles (in order: a stage
  // takes its items in order); or a memory level's requests (unit -1; not in order).
  struct Track {
    int unit;
    std::string stage;
    std::vector<uint64_t> starts, leaves;
  };

  // The tracks in the order both writers list them; `memory` holds the levels' sorted copies.
  std::vector<const Track*> ordered_tracks(std::vector<Track>& memory) const;
  bool several_units() const;

  uint64_t limit_;
  uint64_t seen_ = 0, recorded_ = 0;
  std::vector<uint64_t> seen_by_unit_;
  std::vector<int> first_track_;  // by unit: its first track, -1 before its first item
  std::vector<Track> tracks_;
};

}  // namespace texsim
