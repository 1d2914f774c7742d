#pragma once
// The clocked pipeline's stage activity over a run, written as a VCD for GTKWave (`texsim run
// --timeline FILE.vcd`, docs/cli.md). After each item the caller hands the pipeline to
// observe(), which copies the item's start and leave cycle in every stage (nothing is recorded
// when no timeline is asked for: the caller holds no StageTimeline). Per stage the VCD has a
// wire `busy` (an item is in the stage: issued, in flight or waiting to leave), a vector
// `items` (items issued to the stage so far) and a vector `inflight` (items in it now); one
// time unit is one clock cycle.
#include <cstdint>
#include <string>
#include <vector>

#include "pipeline/kernel/clocked_pipeline.h"

namespace texsim {

class StageTimeline {
 public:
  // Records at most `limit` items (the first ones); later items are counted, not recorded.
  explicit StageTimeline(uint64_t limit) : limit_(limit) {}

  // Call after each fragment: records the pipeline's last item if it is new.
  void observe(const ClockedPipeline& pipe) {
    if (pipe.items() == seen_) return;
    seen_ = pipe.items();
    if (recorded_ >= limit_) return;
    record(pipe);
  }

  uint64_t recorded() const { return recorded_; }
  uint64_t seen() const { return seen_; }
  // " (R of N fragments)", for the run's log.
  std::string summary() const {
    return " (" + std::to_string(recorded_) + " of " + std::to_string(seen_) + " fragments)";
  }

  // Writes the VCD to `path` atomically (throws InputError naming it if it cannot).
  void write_vcd(const std::string& path) const;

 private:
  void record(const ClockedPipeline& pipe);

  uint64_t limit_;
  uint64_t seen_ = 0, recorded_ = 0;
  std::vector<std::string> names_;  // stage names, from the first item's pipeline
  // Per stage, the recorded items' start and leave cycles (in order: stages are in order).
  std::vector<std::vector<uint64_t>> starts_, leaves_;
};

}  // namespace texsim
