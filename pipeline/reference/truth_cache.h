#pragma once
// A content-addressed cache of ground truths (docs/truth-cache.md). A run's truth depends on
// its scene, textures and [reference] only, never on the texture unit's configuration, so
// runs that differ in the unit alone (tune candidates, sweep jobs, the ledger's variants)
// share it. Each fragment's truth is stored under its identity (TruthId) inside one entry per
// key (truth_key.h); a run takes what the entry has and computes the rest, so an entry serves
// any run whose fragments it covers, and a fragment it does not cover is computed, never
// guessed.
//
// Two layers: the process keeps recent tables in memory (a tune computes its truth once),
// and the directory (TEXSIM_CACHE_DIR, else $XDG_CACHE_HOME/texsim, else ~/.cache/texsim;
// entries under truth/) keeps them across processes. An entry is `<key hex>.truth`: a header
// (magic, format version, key, payload size, CRC-64 of the payload) and the records, exactly
// the doubles the truth computed. Entries are written to a temporary file in the directory
// and renamed into place, so readers never see a partial entry and processes writing the same
// key concurrently (sweep jobs on a shared file system) leave one whole entry; a damaged or
// foreign entry fails its checks, is reported on stderr naming the file, removed and
// recomputed. After a write the least recently used entries (mtime, touched on a hit) are
// removed until the directory fits its limit (TEXSIM_TRUTH_CACHE_MAX, default 2 GiB). A
// directory that cannot be used gives a warning and a run without the disk layer.
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/reference/truth_key.h"

namespace texsim {

// What identifies one fragment's truth under a key: its frame (a camera path's frames have
// their own maps), primitive, pixel, material and loaded texture.
struct TruthId {
  uint32_t frame = 0, prim = 0, x = 0, y = 0, material = 0, tex = 0;
  auto operator<=>(const TruthId&) const = default;
};

// One fragment's truth as the run computed it.
struct TruthRecord {
  TruthId id;
  double rgba[4] = {0, 0, 0, 0};
  int32_t samples = 0;  // points the integrator evaluated (the report's mean)
  uint32_t reach = 0;   // the finest tier whose value this also is (< TruthSampling::kTiers)
};

// An immutable set of records, in the order given, with a hash index over their ids built on
// the first look-up that needs it (thread-safe).
class TruthTable {
 public:
  explicit TruthTable(std::vector<TruthRecord> records) : records_(std::move(records)) {}
  // The record of `id` (if ids repeat, the first), or null. `hint`: where the record likely is;
  // a run whose fragments arrive in the order the table was written finds each at its
  // position, with no hash look-up and no index built.
  const TruthRecord* find(const TruthId& id, size_t hint = SIZE_MAX) const;
  const std::vector<TruthRecord>& records() const { return records_; }
  uint64_t bytes() const;  // with the index, built or not
  // This table's records and `more`, as a new table.
  std::shared_ptr<const TruthTable> merged(const std::vector<TruthRecord>& more) const;

 private:
  void build_index() const;
  std::vector<TruthRecord> records_;
  mutable std::once_flag indexed_;
  mutable std::vector<uint32_t> slots_;  // open addressing: record index + 1, 0 = empty
};

// The on-disk entry (format version kTruthEntryVersion, little-endian).
inline constexpr uint32_t kTruthEntryVersion = 2;
inline constexpr size_t kTruthHeaderBytes = 64;
std::string encode_truth_entry(const TruthKey& key, const std::vector<TruthRecord>& records);
// The records of an entry; throws InputError naming `path` and what is wrong (bad magic or
// version, a key other than *expected (when given), a size or checksum that does not match,
// a record whose reach is not a tier).
std::vector<TruthRecord> decode_truth_entry(std::string_view bytes, const std::string& path,
                                            const TruthKey* expected);
// The same from the file `path`, read straight into the records.
std::vector<TruthRecord> read_truth_entry(const std::string& path, const TruthKey& expected);
// Writes the entry to `path` in place (the cache writes a temporary file and renames it);
// false on failure.
bool write_truth_entry(const std::string& path, const TruthKey& key,
                       const std::vector<TruthRecord>& records);
// CRC-64/XZ of the payload (ISA-L's crc64_ecma_refl), as the header stores it.
uint64_t truth_payload_crc(const char* p, size_t n);

struct TruthCacheConfig {
  bool enabled = true;  // false: --no-truth-cache (neither layer)
  std::string dir;      // the entries' directory (".../truth"); "" = no disk layer
  uint64_t max_bytes = uint64_t{2} << 30;
  // From the environment: TEXSIM_CACHE_DIR, XDG_CACHE_HOME, HOME, TEXSIM_TRUTH_CACHE_MAX
  // (bytes, or with a K, M or G suffix; a bad value is an InputError naming the variable).
  static TruthCacheConfig from_env(bool enabled);
};

class TruthCache {
 public:
  explicit TruthCache(TruthCacheConfig c);
  // The table stored under `key` (memory first, then disk; a disk hit is touched), or null.
  std::shared_ptr<const TruthTable> find(const TruthKey& key);
  // Keeps `t` under `key` in memory and on disk, then evicts down to the limit.
  void store(const TruthKey& key, const std::shared_ptr<const TruthTable>& t);
  std::string entry_path(const TruthKey& key) const;
  bool enabled() const { return cfg_.enabled; }
  bool disk() const { return !cfg_.dir.empty(); }
  // Where the last find() found its table: "memory", "disk" or "" (a miss).
  const char* found_in() const { return found_in_; }
  // Drops the process's in-memory layer (tests of the disk layer).
  static void forget_memory();

 private:
  TruthCacheConfig cfg_;
  const char* found_in_ = "";
};

// Removes the least recently modified entries of `dir` until the entries' total is at most
// `max_bytes`; files that vanish meanwhile (another process evicting) are skipped.
void evict_truth_entries(const std::string& dir, uint64_t max_bytes);

}  // namespace texsim
