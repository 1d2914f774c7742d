#pragma once
// Splits [0, n) into one contiguous range per thread and runs `work(begin, end)` on each, the
// calling thread taking the first; returns when all are done. What each index computes must
// not depend on the split, so results are the same for every thread count.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace texsim {

// threads <= 0: one per hardware thread.
inline int resolve_threads(int threads) {
  return threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// The first error of a set of workers, by lowest position: rethrown on the calling thread after
// every worker has joined, so an exception in a task is the caller's, never std::terminate.
class FirstError {
 public:
  void record(size_t at) {
    const std::lock_guard<std::mutex> lock(m_);
    if (at < at_) {
      at_ = at;
      error_ = std::current_exception();
    }
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  std::mutex m_;
  size_t at_ = static_cast<size_t>(-1);
  std::exception_ptr error_;
};

template <class Work>
void parallel_range(size_t n, int threads, Work&& work) {
  const size_t t = std::min(n, static_cast<size_t>(resolve_threads(threads)));
  if (t <= 1) {
    if (n > 0) work(size_t{0}, n);
    return;
  }
  FirstError first;
  auto part = [&work, &first, n, t](size_t k) {
    try {
      work(n * k / t, n * (k + 1) / t);
    } catch (...) {
      first.record(k);
    }
  };
  {
    std::vector<std::jthread> helpers;
    helpers.reserve(t - 1);
    for (size_t k = 1; k < t; ++k) helpers.emplace_back(part, k);
    part(0);
  }  // the jthreads join here
  first.rethrow();
}

// Runs work(i) for every i in [0, n) on up to `threads` threads, each taking the next index as
// it finishes (tasks of uneven size balance themselves). work(i) must write only its own
// slot of any shared result, so the outcome is the same for every thread count. A task that
// throws stops the hand-out of new indices; the exception of the lowest failing index is
// rethrown here (indices are handed out in order, so it is the one a plain loop would meet).
template <class Work>
void parallel_tasks(size_t n, int threads, Work&& work) {
  const size_t t = std::min(n, static_cast<size_t>(resolve_threads(threads)));
  std::atomic<size_t> next{0};
  FirstError first;
  auto drain = [&work, &next, &first, n] {
    for (size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) {
      try {
        work(i);
      } catch (...) {
        first.record(i);
        next.store(n);
      }
    }
  };
  {
    std::vector<std::jthread> helpers;
    for (size_t k = 1; k < t; ++k) helpers.emplace_back(drain);
    drain();
  }  // the jthreads join here
  first.rethrow();
}

}  // namespace texsim
