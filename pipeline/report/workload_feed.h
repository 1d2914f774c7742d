#pragma once
// Feeds a run's fragments to its WorkloadStats, on a thread of its own when the run has more
// than one: the characterisation (footprints, working sets, reuse distances) is a fifth of a
// trace run's serial work and depends on the fragment stream alone, so it runs a batch behind
// the simulation. One thread takes the batches in order: the figures are the same bits as the
// caller's own add() calls.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "blocks/base/fragment.h"
#include "pipeline/report/workload_stats.h"

namespace texsim {

class WorkloadFeed {
 public:
  // `stats` must outlive this object and be left alone until finish(). async false: add()
  // calls stats.add() at once.
  WorkloadFeed(WorkloadStats& stats, bool async);
  ~WorkloadFeed();  // stops the thread (what it had not taken is dropped)
  WorkloadFeed(const WorkloadFeed&) = delete;
  WorkloadFeed& operator=(const WorkloadFeed&) = delete;

  void add(const Fragment& f, uint32_t tex) {
    if (!thread_.joinable()) {
      stats_.add(f, tex);
      return;
    }
    batch_.push_back({f, tex});
    if (batch_.size() == kBatch) hand_off();
  }
  // Every fragment added is in the stats and their last frame closed (stats.finish()) once
  // this returns; the thread is stopped.
  void finish();

 private:
  struct Item {
    Fragment f;
    uint32_t tex;
  };
  static constexpr size_t kBatch = 4096, kDepth = 4;  // batches queued at most
  void hand_off();
  void work();

  WorkloadStats& stats_;
  std::vector<Item> batch_;  // being filled by the caller
  std::mutex mutex_;
  std::condition_variable filled_, emptied_;
  std::deque<std::vector<Item>> ready_;   // handed off, in order
  std::vector<std::vector<Item>> spare_;  // emptied buffers, for reuse
  bool done_ = false, stop_ = false;
  std::thread thread_;  // last: starts once every other member is set up
};

}  // namespace texsim
