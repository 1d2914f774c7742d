#include "pipeline/reference/truth_cache.h"

#include <isa-l/crc64.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cerrno>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <list>
#include <mutex>
#include <set>
#include <sstream>
#include <system_error>
#include <type_traits>
#include <utility>

#include "blocks/base/cache_dir.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/reference/ground_truth.h"

namespace texsim {

namespace fs = std::filesystem;

// Records are stored as their bytes: no padding anywhere.
static_assert(sizeof(TruthId) == 24 && offsetof(TruthRecord, rgba) == 24 &&
                  offsetof(TruthRecord, samples) == 56 && sizeof(TruthRecord) == 64,
              "records are stored as their bytes: no padding");
static_assert(std::endian::native == std::endian::little, "entries are little-endian");

namespace {

constexpr char kMagic[8] = {'T', 'X', 'S', 'T', 'R', 'U', 'T', 'H'};
constexpr uint64_t kMemoryBytes = uint64_t{1} << 30;  // the in-memory layer's limit

uint64_t mix(uint64_t h) {  // a 64-bit finaliser (splitmix64's)
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  return h ^ (h >> 31);
}

uint64_t id_hash(const TruthId& id) {
  uint64_t h = mix((uint64_t{id.frame} << 32) | id.prim);
  h = mix(h ^ ((uint64_t{id.x} << 32) | id.y));
  return mix(h ^ ((uint64_t{id.material} << 32) | id.tex));
}

void put_u32(std::string& s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s += static_cast<char>(v >> (8 * i));
}
void put_u64(std::string& s, uint64_t v) {
  for (int i = 0; i < 8; ++i) s += static_cast<char>(v >> (8 * i));
}
uint64_t get_le(std::string_view b, size_t at, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t{static_cast<uint8_t>(b[at + i])} << (8 * i);
  return v;
}

// The in-memory layer: recent tables, least recently used first out.
struct MemoryLayer {
  std::mutex mu;
  std::list<std::pair<TruthKey, std::shared_ptr<const TruthTable>>> lru;  // most recent first
  uint64_t bytes = 0;
  std::set<std::string> warned;  // directories already reported unusable

  std::shared_ptr<const TruthTable> find(const TruthKey& key) {
    std::lock_guard<std::mutex> lock(mu);
    for (auto it = lru.begin(); it != lru.end(); ++it) {
      if (it->first != key) continue;
      lru.splice(lru.begin(), lru, it);
      return it->second;
    }
    return nullptr;
  }
  void put(const TruthKey& key, const std::shared_ptr<const TruthTable>& t) {
    std::lock_guard<std::mutex> lock(mu);
    for (auto it = lru.begin(); it != lru.end(); ++it) {
      if (it->first != key) continue;
      bytes -= it->second->bytes();
      lru.erase(it);
      break;
    }
    lru.emplace_front(key, t);
    bytes += t->bytes();
    while (bytes > kMemoryBytes && lru.size() > 1) {
      bytes -= lru.back().second->bytes();
      lru.pop_back();
    }
  }
  // True the first time `dir` is reported.
  bool first_warning(const std::string& dir) {
    std::lock_guard<std::mutex> lock(mu);
    return warned.insert(dir).second;
  }
};

MemoryLayer& memory() {
  static MemoryLayer m;
  return m;
}

void warn(const std::string& what) {
  std::ostringstream s;  // one write: lines of concurrent runs do not interleave
  s << "texsim: warning: truth cache: " << what << "\n";
  std::cerr << s.str() << std::flush;
}

}  // namespace

void TruthTable::build_index() const {
  size_t n = 16;
  while (n < 2 * records_.size()) n *= 2;
  slots_.assign(n, 0);
  for (size_t i = 0; i < records_.size(); ++i) {
    size_t s = id_hash(records_[i].id) & (n - 1);
    while (slots_[s] != 0 && records_[slots_[s] - 1].id != records_[i].id) s = (s + 1) & (n - 1);
    if (slots_[s] == 0) slots_[s] = static_cast<uint32_t>(i + 1);  // a repeat: the first stands
  }
}

const TruthRecord* TruthTable::find(const TruthId& id, size_t hint) const {
  if (hint < records_.size() && records_[hint].id == id) return &records_[hint];
  std::call_once(indexed_, [this] { build_index(); });
  const size_t mask = slots_.size() - 1;
  for (size_t s = id_hash(id) & mask; slots_[s] != 0; s = (s + 1) & mask) {
    const TruthRecord& r = records_[slots_[s] - 1];
    if (r.id == id) return &r;
  }
  return nullptr;
}

uint64_t TruthTable::bytes() const {
  return records_.size() * (sizeof(TruthRecord) + 4 * sizeof(uint32_t));  // slots: under 4n
}

std::shared_ptr<const TruthTable> TruthTable::merged(const std::vector<TruthRecord>& more) const {
  std::vector<TruthRecord> all;
  all.reserve(records_.size() + more.size());
  all = records_;
  all.insert(all.end(), more.begin(), more.end());
  return std::make_shared<const TruthTable>(std::move(all));
}

uint64_t truth_payload_crc(const char* p, size_t n) {
  return crc64_ecma_refl(0, reinterpret_cast<const unsigned char*>(p), n);
}

namespace {

std::string entry_header(const TruthKey& key, const std::vector<TruthRecord>& records) {
  const size_t payload = records.size() * sizeof(TruthRecord);
  std::string s(kMagic, sizeof kMagic);
  put_u32(s, kTruthEntryVersion);
  put_u32(s, sizeof(TruthRecord));
  s.append(reinterpret_cast<const char*>(key.data()), key.size());
  put_u64(s, payload);
  put_u64(s, truth_payload_crc(reinterpret_cast<const char*>(records.data()), payload));
  return s;
}

// Checks a header (kTruthHeaderBytes of `h`) against the file's size; returns the payload
// size and its CRC.
std::pair<uint64_t, uint64_t> check_header(std::string_view h, uint64_t file_bytes,
                                           const std::string& path, const TruthKey* expected) {
  if (file_bytes < kTruthHeaderBytes) {
    throw InputError(path, "truncated: " + std::to_string(file_bytes) + " bytes, less than the " +
                               std::to_string(kTruthHeaderBytes) + "-byte header");
  }
  if (std::memcmp(h.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(path, "not a truth cache entry (bad magic)");
  if (const uint64_t v = get_le(h, 8, 4); v != kTruthEntryVersion) {
    throw InputError(path, "entry format version " + std::to_string(v) + ", expected " +
                               std::to_string(kTruthEntryVersion));
  }
  if (get_le(h, 12, 4) != sizeof(TruthRecord))
    throw InputError(path, "record size " + std::to_string(get_le(h, 12, 4)) + ", expected 64");
  TruthKey key;
  std::memcpy(key.data(), h.data() + 16, key.size());
  if (expected && key != *expected) {
    throw InputError(path, "header key " + Sha256::hex(key) + " is not the file's key " +
                               Sha256::hex(*expected));
  }
  const uint64_t payload = get_le(h, 48, 8), have = file_bytes - kTruthHeaderBytes;
  if (payload != have) {
    throw InputError(path, "truncated or extended: the header says " + std::to_string(payload) +
                               " payload bytes, the file has " + std::to_string(have));
  }
  if (payload % sizeof(TruthRecord) != 0)
    throw InputError(path, "payload of " + std::to_string(payload) + " bytes is not whole records");
  return {payload, get_le(h, 56, 8)};
}

// The records' checksum and reaches.
void check_records(const std::vector<TruthRecord>& r, uint64_t crc, const std::string& path) {
  if (truth_payload_crc(reinterpret_cast<const char*>(r.data()), r.size() * sizeof(TruthRecord)) !=
      crc)
    throw InputError(path, "payload checksum (CRC-64) does not match: the entry is corrupted");
  for (size_t i = 0; i < r.size(); ++i) {
    if (r[i].reach >= TruthSampling::kTiers) {
      throw InputError(path, "record " + std::to_string(i) + ": reach " +
                                 std::to_string(r[i].reach) + " is not a tier (0 to " +
                                 std::to_string(TruthSampling::kTiers - 1) + ")");
    }
  }
}

}  // namespace

std::string encode_truth_entry(const TruthKey& key, const std::vector<TruthRecord>& records) {
  std::string s = entry_header(key, records);
  s.append(reinterpret_cast<const char*>(records.data()), records.size() * sizeof(TruthRecord));
  return s;
}

std::vector<TruthRecord> decode_truth_entry(std::string_view b, const std::string& path,
                                            const TruthKey* expected) {
  const auto [payload, crc] = check_header(b, b.size(), path, expected);
  std::vector<TruthRecord> r(payload / sizeof(TruthRecord));
  if (payload > 0) std::memcpy(r.data(), b.data() + kTruthHeaderBytes, payload);
  check_records(r, crc, path);
  return r;
}

std::vector<TruthRecord> read_truth_entry(const std::string& path, const TruthKey& expected) {
  // The common opener: a regular file only, opened without blocking.
  uint64_t size = 0;
  const InputFilePtr in = open_input_file(path, "truth cache entry", kNoSizeLimit, &size);
  std::string h(static_cast<size_t>(std::min<uint64_t>(size, kTruthHeaderBytes)), '\0');
  if (std::fread(h.data(), 1, h.size(), in.get()) != h.size())
    throw InputError(path, "truncated while it was read");
  h.resize(kTruthHeaderBytes, '\0');
  const auto [payload, crc] = check_header(h, size, path, &expected);
  std::vector<TruthRecord> r(payload / sizeof(TruthRecord));  // read in place: no copy
  if (std::fread(r.data(), 1, payload, in.get()) != payload)
    throw InputError(path, "truncated while it was read");
  check_records(r, crc, path);
  return r;
}

bool write_truth_entry(const std::string& path, const TruthKey& key,
                       const std::vector<TruthRecord>& records) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  const std::string h = entry_header(key, records);
  out.write(h.data(), static_cast<std::streamsize>(h.size()));
  out.write(reinterpret_cast<const char*>(records.data()),
            static_cast<std::streamsize>(records.size() * sizeof(TruthRecord)));
  return out.flush().good();
}

TruthCacheConfig TruthCacheConfig::from_env(bool enabled) {
  TruthCacheConfig c;
  c.enabled = enabled;
  if (!enabled) return c;
  if (const std::string root = cache_root_from_env(); !root.empty()) c.dir = root + "/truth";
  if (const char* m = std::getenv("TEXSIM_TRUTH_CACHE_MAX"); m && *m)
    c.max_bytes = parse_cache_max_bytes(m, "TEXSIM_TRUTH_CACHE_MAX");
  return c;
}

TruthCache::TruthCache(TruthCacheConfig c) : cfg_(std::move(c)) {}

std::string TruthCache::entry_path(const TruthKey& key) const {
  return cfg_.dir + "/" + Sha256::hex(key) + ".truth";
}

void TruthCache::forget_memory() {
  MemoryLayer& m = memory();
  std::lock_guard<std::mutex> lock(m.mu);
  m.lru.clear();
  m.bytes = 0;
}

std::shared_ptr<const TruthTable> TruthCache::find(const TruthKey& key) {
  found_in_ = "";
  if (!cfg_.enabled) return nullptr;
  if (auto t = memory().find(key)) {
    found_in_ = "memory";
    return t;
  }
  if (!disk()) return nullptr;
  const std::string path = entry_path(key);
  std::error_code ec;
  if (!fs::exists(path, ec)) return nullptr;
  std::shared_ptr<const TruthTable> t;
  try {
    t = std::make_shared<const TruthTable>(read_truth_entry(path, key));
  } catch (const InputError& e) {
    warn(std::string(e.what()) + "; entry removed, the truth is recomputed");
    fs::remove(path, ec);
    return nullptr;
  }
  // A hit is recent use: the eviction keeps it longer.
  fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
  memory().put(key, t);
  found_in_ = "disk";
  return t;
}

void TruthCache::store(const TruthKey& key, const std::shared_ptr<const TruthTable>& t) {
  if (!cfg_.enabled) return;
  memory().put(key, t);
  if (!disk()) return;
  const uint64_t size = kTruthHeaderBytes + t->records().size() * sizeof(TruthRecord);
  if (size > cfg_.max_bytes) return;  // larger than the whole cache may be
  std::error_code ec;
  fs::create_directories(cfg_.dir, ec);
  const std::string path = entry_path(key);
  const std::string temp = cache_temp_path(cfg_.dir, Sha256::hex(key));
  bool ok = !ec;
  if (ok) ok = write_truth_entry(temp, key, t->records());
  if (ok) fs::rename(temp, path, ec);  // atomic: readers see the old entry or the new one
  if (!ok || ec) {
    const std::string why = ec ? ec.message() : std::string(std::strerror(errno));
    fs::remove(temp, ec);
    if (memory().first_warning(cfg_.dir)) {
      warn("cannot write entries in " + cfg_.dir + " (" + why +
           "); runs go on without the disk cache");
    }
    return;
  }
  evict_truth_entries(cfg_.dir, cfg_.max_bytes);
}

void evict_truth_entries(const std::string& dir, uint64_t max_bytes) {
  evict_cache_entries(dir, max_bytes, ".truth");
}

}  // namespace texsim
