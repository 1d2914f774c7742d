// libFuzzer harness: bytes as an entry of texsim's two disk caches, each decoded as read (the
// CRC rejects almost every mutation) and again with the CRC (and the truth entry's payload
// size) made to match, so mutations reach the checks behind it. Bad input must end in
// InputError.
// - A truth cache entry (pipeline/reference/truth_cache.h): an accepted entry must survive its
//   round trip through the table and the encoder byte for byte, and every record must be
//   found under its id, by position and by index.
// - An encoded-level entry (pipeline/image_io/encoded_level_cache.h): an accepted entry must
//   be re-encoded byte for byte.
#include <cstdlib>
#include <cstring>
#include <string>

#include "pipeline/image_io/encoded_level_cache.h"
#include "pipeline/reference/truth_cache.h"
#include "testbench/fuzz/fuzz_input.h"

namespace {

using namespace texsim;

void check(const std::string& bytes) {
  TruthKey key{};
  if (bytes.size() >= 48) std::memcpy(key.data(), bytes.data() + 16, key.size());
  const std::vector<TruthRecord> r = decode_truth_entry(bytes, "fuzz.truth", &key);
  const TruthTable t(r);
  for (size_t i = 0; i < r.size(); ++i) {
    // Found at its place, and through the index (with a repeated id: the first record's).
    const TruthRecord* at = t.find(r[i].id, i);
    const TruthRecord* indexed = t.find(r[i].id);
    if (at != &t.records()[i] || indexed == nullptr || indexed > at || !(indexed->id == r[i].id))
      std::abort();
  }
  if (encode_truth_entry(key, t.records()) != bytes) std::abort();
}

// The same bytes with the payload size and CRC rewritten to match the payload.
std::string with_fixed_crc(std::string b) {
  if (b.size() < kTruthHeaderBytes) return b;
  const uint64_t payload = b.size() - kTruthHeaderBytes;
  const uint64_t crc = truth_payload_crc(b.data() + kTruthHeaderBytes, payload);
  for (int i = 0; i < 8; ++i) {
    b[48 + i] = static_cast<char>(payload >> (8 * i));
    b[56 + i] = static_cast<char>(crc >> (8 * i));
  }
  return b;
}

void check_level(const std::string& bytes) {
  EncodedLevelKey key{};
  if (bytes.size() >= 48) std::memcpy(key.data(), bytes.data() + 16, key.size());
  const EncodedLevel l = decode_level_entry(bytes, "fuzz.level", &key);
  if (encode_level_entry(key, l) != bytes) std::abort();
}

// The same bytes with the CRC rewritten to match the rest.
std::string with_fixed_level_crc(std::string b) {
  if (b.size() < kEncodedLevelHeaderBytes) return b;
  const std::string body = b.substr(kEncodedLevelHeaderBytes);
  const uint64_t crc = truth_payload_crc(body.data(), body.size());  // the same CRC-64/XZ
  for (int i = 0; i < 8; ++i) b[72 + i] = static_cast<char>(crc >> (8 * i));
  return b;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  texsim::fuzz::expect_clean([&] { check(bytes); });
  texsim::fuzz::expect_clean([&] { check(with_fixed_crc(bytes)); });
  texsim::fuzz::expect_clean([&] { check_level(bytes); });
  texsim::fuzz::expect_clean([&] { check_level(with_fixed_level_crc(bytes)); });
  return 0;
}
