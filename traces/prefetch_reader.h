#pragma once
// Reads a trace one thread ahead of its consumer: a reader thread fills a few chunks in advance
// (reading, CRC check and decoding), so that work overlaps with whatever the consumer does with
// the chunks before. Chunks come out in file order with TraceReader::next_chunk's contract; an
// error of the input reaches the consumer with its own type and message after every good chunk
// before it, exactly where the serial reader would have raised it.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

#include "blocks/base/fragment.h"
#include "traces/trace_file.h"

namespace texsim {

class PrefetchReader {
 public:
  // `reader` (its header already read) must outlive this object; nobody else may read from it
  // meanwhile. `depth`: chunks read ahead at most (at least 1); memory stays depth + 2 chunks.
  explicit PrefetchReader(TraceReader& reader, size_t depth = 3);
  // Stops the reader thread (after the chunk it is reading, if any) and waits for it.
  ~PrefetchReader();
  PrefetchReader(const PrefetchReader&) = delete;
  PrefetchReader& operator=(const PrefetchReader&) = delete;

  // Replaces `out` with the next chunk's fragments and returns their count; 0 at the end. Throws
  // the reader's exception once every chunk before it has been handed out (again on each call).
  size_t next_chunk(std::vector<Fragment>& out);

 private:
  void read_ahead();

  TraceReader& reader_;
  std::mutex mutex_;
  std::condition_variable filled_;            // a chunk, the end or an error is ready
  std::condition_variable emptied_;           // a buffer came back, or stop
  std::deque<std::vector<Fragment>> ready_;   // read, not yet handed out, in file order
  std::vector<std::vector<Fragment>> spare_;  // buffers to read into (recycled from `out`)
  bool end_ = false;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;  // last: starts once every other member is set up
};

}  // namespace texsim
