// libFuzzer harness: bytes as a tune_shard.json through the reader `texsim tune --merge` uses
// (read_tune_shard): JSON depth, every field's type and range, `chosen` within the points. What
// it accepts is then used as the merge uses it, so an index it let through out of range is an
// ASan finding.
#include <cstdio>

#include "pipeline/app/tuner.h"
#include "testbench/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = texsim::fuzz::write_input(data, size, "-tune_shard.json");
  texsim::fuzz::expect_clean([&] {
    const texsim::TuneShard s = texsim::read_tune_shard(path);
    if (s.indices.size() != s.materials.size()) std::abort();
    double sum = 0;
    for (const texsim::TuneMaterial& m : s.materials) {
      const texsim::TunePoint& c = m.points.at(static_cast<size_t>(m.chosen));
      sum += c.cycles + c.area + c.psnr_db + c.nmse + static_cast<double>(c.label.size());
    }
    if (sum != sum) std::abort();  // every number read is finite
  });
  return 0;
}
