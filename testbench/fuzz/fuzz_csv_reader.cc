// libFuzzer harness: the CSV form of a trace (traces/FORMAT.md, "CSV form") on arbitrary text.
// Bad input must end in InputError. What the reader accepts must round-trip: written back as
// binary and as CSV, each reads to the same texture table and the same records, bit for bit.
#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "testbench/fuzz/fuzz_input.h"
#include "traces/trace_csv.h"
#include "traces/trace_file.h"

namespace {

// Enough records to cross several chunk boundaries, few enough that each input stays fast.
constexpr size_t kMaxRecords = 20000;

std::vector<texsim::Fragment> read_some(const std::string& path, texsim::TraceHeader& header) {
  texsim::TraceReader r(path);
  header = r.header();
  std::vector<texsim::Fragment> all, chunk;
  while (all.size() < kMaxRecords && r.next_chunk(chunk) > 0)
    all.insert(all.end(), chunk.begin(), chunk.end());
  if (all.size() > kMaxRecords) all.resize(kMaxRecords);
  return all;
}

// Bit for bit: -0.0 and 0.0 differ, a NaN payload would count.
bool same_bits(double a, double b) {
  return std::bit_cast<uint64_t>(a) == std::bit_cast<uint64_t>(b);
}

bool same(const texsim::Fragment& a, const texsim::Fragment& b) {
  return a.frame == b.frame && a.prim == b.prim && a.x == b.x && a.y == b.y && a.tex == b.tex &&
         same_bits(a.u, b.u) && same_bits(a.v, b.v) && same_bits(a.dudx, b.dudx) &&
         same_bits(a.dvdx, b.dvdx) && same_bits(a.dudy, b.dudy) && same_bits(a.dvdy, b.dvdy) &&
         std::bit_cast<uint32_t>(a.lod_bias) == std::bit_cast<uint32_t>(b.lod_bias) &&
         std::bit_cast<uint32_t>(a.view_x) == std::bit_cast<uint32_t>(b.view_x) &&
         std::bit_cast<uint32_t>(a.view_y) == std::bit_cast<uint32_t>(b.view_y) &&
         std::bit_cast<uint32_t>(a.view_z) == std::bit_cast<uint32_t>(b.view_z) &&
         same_bits(a.w, b.w) && same_bits(a.dwdx, b.dwdx) && same_bits(a.dwdy, b.dwdy) &&
         std::bit_cast<uint32_t>(a.layer) == std::bit_cast<uint32_t>(b.layer) &&
         std::bit_cast<uint32_t>(a.lod) == std::bit_cast<uint32_t>(b.lod) &&
         std::bit_cast<uint32_t>(a.compare_ref) == std::bit_cast<uint32_t>(b.compare_ref) &&
         a.sampler == b.sampler && a.op == b.op && a.gather_component == b.gather_component &&
         a.offset_u == b.offset_u && a.offset_v == b.offset_v && a.offset_w == b.offset_w;
}

bool same(const texsim::TraceHeader& a, const texsim::TraceHeader& b) {
  if (a.has_lod_bias != b.has_lod_bias || a.has_view != b.has_view || a.has_ops != b.has_ops ||
      a.textures.size() != b.textures.size())
    return false;
  for (size_t i = 0; i < a.textures.size(); ++i) {
    const texsim::TraceTexture &s = a.textures[i], &t = b.textures[i];
    if (s.id != t.id || s.name != t.name || s.source != t.source || s.width != t.width ||
        s.height != t.height || s.storage != t.storage)
      return false;
  }
  return a.samplers == b.samplers;  // the sampler table (version 5), entry by entry
}

// Writes what was read to `path` and checks that it reads back unchanged.
void check_round_trip(const texsim::TraceHeader& header, const std::vector<texsim::Fragment>& in,
                      const std::string& path) {
  texsim::write_trace(path, header, in);
  texsim::TraceHeader back_header;
  const std::vector<texsim::Fragment> back = read_some(path, back_header);
  bool ok = same(header, back_header) && back.size() == in.size();
  for (size_t i = 0; ok && i < in.size(); ++i) ok = same(in[i], back[i]);
  std::remove(path.c_str());
  if (!ok) {
    std::fprintf(stderr, "round trip through %s changed the trace\n", path.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string csv = texsim::fuzz::write_input(data, size, ".csv");
  texsim::fuzz::expect_clean([&] {
    texsim::TraceHeader header;
    const std::vector<texsim::Fragment> records = read_some(csv, header);
    // The round trips are the writers' business: an InputError there is a finding too.
    try {
      check_round_trip(header, records, csv + ".trc");
      check_round_trip(header, records, csv + ".back.csv");
    } catch (const texsim::InputError& e) {
      std::fprintf(stderr, "writing back an accepted trace failed: %s\n", e.what());
      std::abort();
    }
  });
  return 0;
}
