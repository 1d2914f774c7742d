// libFuzzer harness: the draw trace reader (traces/DRAWS.md) on arbitrary bytes. With
// TEXSIM_FUZZ_FIX_CRC=1 in the environment, the header and record CRCs are first recomputed
// where the structure around them is intact, so mutations reach the checks behind them.
#include <zlib.h>

#include <cstring>
#include <vector>

#include "testbench/fuzz/fuzz_crc.h"
#include "testbench/fuzz/fuzz_input.h"
#include "traces/draw_trace.h"

namespace {

using texsim::fuzz::get_u32;
using texsim::fuzz::put_crc;

void fix_crcs(std::vector<uint8_t>& b) {
  if (b.size() < 20) return;
  const uint64_t source = get_u32(b, 12);
  if (16 + source + 4 > b.size()) return;
  put_crc(b, 16 + source, 0, 16 + source);
  size_t at = 16 + source + 4;
  while (at + 12 <= b.size()) {
    const uint64_t len = get_u32(b, at + 4);
    if (len > b.size() - at - 12) return;
    put_crc(b, at + 8, at + 12, len);
    at += 12 + len;
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
  const std::string path = texsim::fuzz::write_input(bytes.data(), bytes.size(), ".draws");
  texsim::fuzz::expect_clean([&] {
    texsim::DrawTraceReader r(path);
    while (r.next() != texsim::DrawRecordKind::End) {
    }
  });
  return 0;
}
