#pragma once
// `texsim trace info|convert` back ends (traces/FORMAT.md): a one-pass streaming summary of a
// trace and a streaming conversion between the binary and CSV forms.
#include <cstdint>
#include <map>
#include <ostream>
#include <string>

#include "traces/trace_csv.h"
#include "traces/trace_file.h"

namespace texsim {

struct TraceRange {
  double lo = 0, hi = 0;
  bool empty = true;
  void add(double v) {
    if (empty) {
      lo = hi = v;
      empty = false;
    } else {
      lo = v < lo ? v : lo;
      hi = v > hi ? v : hi;
    }
  }
};

// Everything trace_info prints, gathered in one streaming pass.
struct TraceSummary {
  TraceHeader header;
  uint64_t records = 0;
  uint64_t chunks = 0;
  uint64_t file_bytes = 0;
  // Fragments per frame, for at most kMaxFrames distinct frames, so the summary's memory stays
  // bounded whatever the trace holds; frames_overflow says that more frames were seen.
  static constexpr size_t kMaxFrames = 65536;
  std::map<uint32_t, uint64_t> frames;
  bool frames_overflow = false;
  uint32_t frame_min = 0, frame_max = 0;
  uint32_t prim_min = 0, prim_max = 0;
  std::map<uint32_t, uint64_t> per_texture;  // texture id -> fragments (ids come from the table)
  TraceRange x, y;                           // pixel bounding box
  TraceRange u, v, dudx, dvdx, dudy, dvdy, lod_bias;
};

// read_ahead: the chunks are read, checked and decoded on a thread of their own
// (PrefetchReader) while this one summarises them; the same summary and the same errors.
TraceSummary summarize_trace(const std::string& path, bool read_ahead = false);

// Prints the header, layout, texture table, counts, frames, pixel bbox and coordinate and
// derivative ranges. Returns 0; bad input throws InputError (the CLI prints it and exits 2).
int trace_info(const std::string& path, std::ostream& out);

// Opens the writer the extension of `path` asks for (".csv": CSV, anything else: binary),
// calls `fill(writer)` to write the records, closes it and returns the records written.
template <class Fill>
uint64_t write_trace(const std::string& path, const TraceHeader& header, Fill&& fill) {
  if (has_csv_extension(path)) {
    TraceCsvWriter w(path, header);
    fill(w);
    w.close();
    return w.records_written();
  }
  TraceWriter w(path, header);
  fill(w);
  w.close();
  return w.records_written();
}

// Converts .csv <-> binary by the extension of `out` (".csv" = CSV, anything else binary),
// streaming chunk by chunk. Fields the input has beyond the known ones are not carried over.
void trace_convert(const std::string& in, const std::string& out);

}  // namespace texsim
