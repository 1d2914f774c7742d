// libFuzzer harness: the streaming trace reader on arbitrary bytes, as a binary trace and as
// CSV, the draw-trace texture sources of its texture table and its sampler table. With
// TEXSIM_FUZZ_FIX_CRC=1 in the environment, the binary form first gets every CRC it can locate
// recomputed, so mutations reach the parser behind the checksums.
#include <zlib.h>

#include <cstring>
#include <vector>

#include "testbench/fuzz/fuzz_crc.h"
#include "testbench/fuzz/fuzz_input.h"
#include "traces/draw_trace.h"
#include "traces/trace_csv.h"
#include "traces/trace_file.h"

namespace {

using texsim::fuzz::get_u32;
using texsim::fuzz::put_crc;

// Recomputes the header, chunk and end-marker CRCs (traces/FORMAT.md) where the structure
// around them is intact enough to find them.
void fix_crcs(std::vector<uint8_t>& b) {
  if (b.size() < 32) return;
  const uint32_t header_size = get_u32(b, 12), record_size = get_u32(b, 16);
  if (header_size < 36 || header_size > b.size()) return;
  put_crc(b, header_size - 4, 0, header_size - 4);
  size_t at = header_size;
  while (at + 12 <= b.size() && std::memcmp(b.data() + at, "CHNK", 4) == 0) {
    const uint64_t payload = uint64_t{get_u32(b, at + 4)} * record_size;
    if (payload > b.size() - at - 12) return;
    put_crc(b, at + 8, at + 12, payload);
    at += 12 + payload;
  }
  if (at + 24 <= b.size() && std::memcmp(b.data() + at, "TEND", 4) == 0)
    put_crc(b, at + 4, at + 8, 16);
}

void read_all(const std::string& path) {
  texsim::TraceReader r(path);
  // A texture table source "draws:PATH#ID" (trace gen --draws) is parsed as a run of the trace
  // parses it; the draw trace it names has a harness of its own (fuzz_draw_trace).
  for (const texsim::TraceTexture& t : r.header().textures) {
    std::string draws;
    uint32_t id = 0;
    if (texsim::is_draws_source(t.source)) texsim::split_draws_source(t.source, draws, id);
  }
  // The sampler table (version 5) as `trace info` prints it: every code the reader let through
  // indexes its name table.
  for (const texsim::TraceSampler& s : r.header().samplers) (void)texsim::csv_sampler_directive(s);
  std::vector<texsim::Fragment> chunk;
  while (r.next_chunk(chunk) > 0) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bool fix = [] {
    const char* e = std::getenv("TEXSIM_FUZZ_FIX_CRC");
    return e && std::strcmp(e, "1") == 0;
  }();
  std::vector<uint8_t> bytes(data, data + size);
  if (fix) fix_crcs(bytes);
  const std::string trc = texsim::fuzz::write_input(bytes.data(), bytes.size(), ".trc");
  texsim::fuzz::expect_clean([&] { read_all(trc); });
  const std::string csv = texsim::fuzz::write_input(data, size, ".csv");
  texsim::fuzz::expect_clean([&] { read_all(csv); });
  return 0;
}
