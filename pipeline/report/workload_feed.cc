#include "pipeline/report/workload_feed.h"

#include <utility>

namespace texsim {

WorkloadFeed::WorkloadFeed(WorkloadStats& stats, bool async) : stats_(stats) {
  if (!async || stats_.empty()) return;  // no textures: add() only counts, at once
  batch_.reserve(kBatch);
  thread_ = std::thread([this] { work(); });
}

WorkloadFeed::~WorkloadFeed() {
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  filled_.notify_one();
  thread_.join();
}

void WorkloadFeed::hand_off() {
  std::vector<Item> next;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    emptied_.wait(lock, [this] { return ready_.size() < kDepth; });
    ready_.push_back(std::move(batch_));
    if (!spare_.empty()) {
      next = std::move(spare_.back());
      spare_.pop_back();
    }
  }
  filled_.notify_one();
  next.clear();
  next.reserve(kBatch);
  batch_ = std::move(next);
}

void WorkloadFeed::work() {
  for (;;) {
    std::vector<Item> b;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      filled_.wait(lock, [this] { return stop_ || done_ || !ready_.empty(); });
      if (stop_ || ready_.empty()) return;  // stopped, or finished with nothing left
      b = std::move(ready_.front());
      ready_.pop_front();
    }
    emptied_.notify_one();
    for (const Item& it : b) stats_.add(it.f, it.tex);
    b.clear();
    const std::lock_guard<std::mutex> lock(mutex_);
    spare_.push_back(std::move(b));
  }
}

void WorkloadFeed::finish() {
  if (thread_.joinable()) {
    if (!batch_.empty()) hand_off();
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    filled_.notify_one();
    thread_.join();
  }
  stats_.finish();
}

}  // namespace texsim
