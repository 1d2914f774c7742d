#pragma once
// Splits [0, n) into one contiguous range per thread and runs `work(begin, end)` on each, the
// calling thread taking the first; returns when all are done. What each index computes must
// not depend on the split, so results are the same for every thread count.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>
#include <vector>

namespace texsim {

// threads <= 0: one per hardware thread.
inline int resolve_threads(int threads) {
  return threads > 0 ? threads : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

template <class Work>
void parallel_range(size_t n, int threads, Work&& work) {
  const size_t t = std::min(n, static_cast<size_t>(resolve_threads(threads)));
  if (t <= 1) {
    if (n > 0) work(size_t{0}, n);
    return;
  }
  std::vector<std::jthread> helpers;
  helpers.reserve(t - 1);
  for (size_t k = 1; k < t; ++k) {
    helpers.emplace_back([&work, n, t, k] { work(n * k / t, n * (k + 1) / t); });
  }
  work(size_t{0}, n / t);
}  // the jthreads join here

// Runs work(i) for every i in [0, n) on up to `threads` threads, each taking the next index as
// it finishes (tasks of uneven size balance themselves). work(i) must write only its own
// slot of any shared result, so the outcome is the same for every thread count.
template <class Work>
void parallel_tasks(size_t n, int threads, Work&& work) {
  const size_t t = std::min(n, static_cast<size_t>(resolve_threads(threads)));
  std::atomic<size_t> next{0};
  auto drain = [&work, &next, n] {
    for (size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) work(i);
  };
  std::vector<std::jthread> helpers;
  for (size_t k = 1; k < t; ++k) helpers.emplace_back(drain);
  drain();
}  // the jthreads join here

}  // namespace texsim
