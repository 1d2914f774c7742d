#include "traces/prefetch_reader.h"

#include <algorithm>
#include <utility>

namespace texsim {

PrefetchReader::PrefetchReader(TraceReader& reader, size_t depth)
    : reader_(reader), spare_(std::max<size_t>(depth, 1)) {
  thread_ = std::thread([this] { read_ahead(); });
}

PrefetchReader::~PrefetchReader() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  emptied_.notify_one();
  thread_.join();
}

void PrefetchReader::read_ahead() {
  for (;;) {
    std::vector<Fragment> buf;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      emptied_.wait(lock, [this] { return stop_ || !spare_.empty(); });
      if (stop_) return;
      buf = std::move(spare_.back());
      spare_.pop_back();
    }
    // Read outside the lock: this is the work that overlaps with the consumer.
    size_t n = 0;
    std::exception_ptr error;
    try {
      n = reader_.next_chunk(buf);
    } catch (...) {
      error = std::current_exception();
    }
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (error) {
        error_ = error;
      } else if (n == 0) {
        end_ = true;
      } else {
        ready_.push_back(std::move(buf));
      }
    }
    filled_.notify_one();
    if (error || n == 0) return;
  }
}

size_t PrefetchReader::next_chunk(std::vector<Fragment>& out) {
  std::unique_lock<std::mutex> lock(mutex_);
  filled_.wait(lock, [this] { return !ready_.empty() || end_ || error_; });
  if (ready_.empty()) {
    out.clear();
    if (error_) std::rethrow_exception(error_);
    return 0;
  }
  std::vector<Fragment> next = std::move(ready_.front());
  ready_.pop_front();
  out.swap(next);
  // The consumer's previous buffer, with its capacity, is read into next.
  spare_.push_back(std::move(next));
  lock.unlock();
  emptied_.notify_one();
  return out.size();
}

}  // namespace texsim
