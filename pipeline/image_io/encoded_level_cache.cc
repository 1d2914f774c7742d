#include "pipeline/image_io/encoded_level_cache.h"

#include <isa-l/crc64.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <system_error>

#include "blocks/base/cache_dir.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "blocks/base/version.h"

#ifndef TEXSIM_SQUISH_VERSION
#define TEXSIM_SQUISH_VERSION "unknown"
#endif
#ifndef TEXSIM_NVTT_VERSION
#define TEXSIM_NVTT_VERSION "unknown"
#endif
#ifndef TEXSIM_ASTCENC_VERSION
#define TEXSIM_ASTCENC_VERSION "unknown"
#endif

namespace texsim {

namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'T', 'X', 'S', 'E', 'N', 'C', 'L', 'V'};
constexpr uint32_t kMaxProvenance = 4096;
constexpr uint64_t kMemoryLimit = uint64_t{256} << 20;

void put_u32(std::string& s, uint32_t v) {
  for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
}
void put_u64(std::string& s, uint64_t v) {
  for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>(v >> (8 * i)));
}
uint64_t get_le(std::string_view b, size_t at, int n) {
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t{static_cast<uint8_t>(b[at + i])} << (8 * i);
  return v;
}

uint64_t crc_of(std::string_view b) {
  return crc64_ecma_refl(0, reinterpret_cast<const unsigned char*>(b.data()), b.size());
}

void warn(const std::string& what) {
  std::ostringstream s;  // one write: lines of concurrent runs do not interleave
  s << "texsim: warning: encoded-level cache: " << what << "\n";
  std::cerr << s.str() << std::flush;
}

// The process's levels in memory, and the directories already warned about.
struct MemoryLayer {
  std::mutex mu;
  std::map<EncodedLevelKey, EncodedLevel> levels;
  uint64_t bytes = 0;
  std::set<std::string> warned;
};

MemoryLayer& memory() {
  static MemoryLayer m;
  return m;
}

}  // namespace

std::string encoder_library_versions() {
  return std::string("libsquish ") + TEXSIM_SQUISH_VERSION + "; NVIDIA Texture Tools " +
         TEXSIM_NVTT_VERSION + "; libastcenc " + TEXSIM_ASTCENC_VERSION + "; texsim " +
         TEXSIM_VERSION + "; texsim encoders r" + std::to_string(kTexsimEncoderRevision);
}

EncodedLevelKey encoded_level_key(const std::string& encoder_identity, const Rgba8Image& img) {
  Sha256 h;
  std::string head =
      "texsim encoded level 1\n" + encoder_identity + "\n" + encoder_library_versions() + "\n";
  put_u32(head, static_cast<uint32_t>(img.width));
  put_u32(head, static_cast<uint32_t>(img.height));
  h.update(head.data(), head.size());
  h.update(img.rgba.data(), img.rgba.size());
  return h.finish();
}

std::string encode_level_entry(const EncodedLevelKey& key, const EncodedLevel& level) {
  std::string s(kMagic, sizeof kMagic);
  put_u32(s, kEncodedLevelEntryVersion);
  put_u32(s, static_cast<uint32_t>(level.format));
  s.append(reinterpret_cast<const char*>(key.data()), key.size());
  for (const int v : {level.width, level.height, level.block_w, level.block_h})
    put_u32(s, static_cast<uint32_t>(v));
  put_u64(s, level.bytes.size());
  std::string body = level.provenance;
  body.append(reinterpret_cast<const char*>(level.bytes.data()), level.bytes.size());
  put_u64(s, crc_of(body));
  put_u32(s, static_cast<uint32_t>(level.provenance.size()));
  put_u32(s, 0);
  return s + body;
}

EncodedLevel decode_level_entry(std::string_view b, const std::string& path,
                                const EncodedLevelKey* expected) {
  if (b.size() < kEncodedLevelHeaderBytes)
    throw InputError(path, "shorter than an entry's " + std::to_string(kEncodedLevelHeaderBytes) +
                               "-byte header");
  if (std::memcmp(b.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(path, "not an encoded-level entry (bad magic)");
  if (get_le(b, 8, 4) != kEncodedLevelEntryVersion)
    throw InputError(path, "entry version " + std::to_string(get_le(b, 8, 4)) + ", expected " +
                               std::to_string(kEncodedLevelEntryVersion));
  const uint64_t format = get_le(b, 12, 4);
  if (format > static_cast<uint64_t>(kLastFileBlockFormat))
    throw InputError(path, "unknown block format " + std::to_string(format));
  EncodedLevelKey key{};
  std::memcpy(key.data(), b.data() + 16, key.size());
  if (expected != nullptr && key != *expected)
    throw InputError(path, "the entry's key is not the one its name asks for");
  EncodedLevel l;
  l.format = static_cast<FileBlockFormat>(format);
  const uint64_t w = get_le(b, 48, 4), h = get_le(b, 52, 4);
  const uint64_t bw = get_le(b, 56, 4), bh = get_le(b, 60, 4);
  const uint64_t payload = get_le(b, 64, 8), crc = get_le(b, 72, 8);
  const uint64_t prov = get_le(b, 80, 4);
  const bool astc = is_astc(l.format);
  if (w == 0 || h == 0 || w > 65536 || h > 65536 || bw < 4 || bh < 4 || bw > 12 || bh > 12 ||
      (!astc && (bw != 4 || bh != 4)))
    throw InputError(path, "level of " + std::to_string(w) + " x " + std::to_string(h) +
                               " in blocks of " + std::to_string(bw) + " x " + std::to_string(bh) +
                               " is not a level this cache stores");
  const uint64_t blocks = ((w + bw - 1) / bw) * ((h + bh - 1) / bh);
  if (payload != blocks * static_cast<uint64_t>(format_block_bytes(l.format)))
    throw InputError(path, "holds " + std::to_string(payload) + " bytes of blocks, not the " +
                               std::to_string(blocks) + " blocks its size needs");
  if (prov > kMaxProvenance || get_le(b, 84, 4) != 0)
    throw InputError(path, "bad provenance length or padding");
  if (b.size() != kEncodedLevelHeaderBytes + prov + payload)
    throw InputError(path, "is " + std::to_string(b.size()) + " bytes, its header says " +
                               std::to_string(kEncodedLevelHeaderBytes + prov + payload));
  const std::string_view body = b.substr(kEncodedLevelHeaderBytes);
  if (crc_of(body) != crc) throw InputError(path, "CRC-64 does not match its contents (damaged)");
  l.width = static_cast<int>(w);
  l.height = static_cast<int>(h);
  l.block_w = static_cast<int>(bw);
  l.block_h = static_cast<int>(bh);
  l.provenance.assign(body.substr(0, prov));
  l.bytes.assign(body.begin() + static_cast<std::ptrdiff_t>(prov), body.end());
  return l;
}

EncodedLevelCache::EncodedLevelCache(std::string dir, uint64_t max_bytes)
    : dir_(std::move(dir)), max_bytes_(max_bytes) {}

EncodedLevelCache& EncodedLevelCache::process() {
  static EncodedLevelCache cache = [] {
    const std::string root = cache_root_from_env();
    uint64_t max = uint64_t{1} << 30;
    if (const char* m = std::getenv("TEXSIM_ENCODED_CACHE_MAX"); m && *m)
      max = parse_cache_max_bytes(m, "TEXSIM_ENCODED_CACHE_MAX");
    return EncodedLevelCache(root.empty() ? std::string() : root + "/encoded", max);
  }();
  return cache;
}

std::string EncodedLevelCache::entry_path(const EncodedLevelKey& key) const {
  return dir_ + "/" + Sha256::hex(key) + ".level";
}

void EncodedLevelCache::forget_memory() {
  MemoryLayer& m = memory();
  const std::lock_guard<std::mutex> lock(m.mu);
  m.levels.clear();
  m.bytes = 0;
}

EncodedLevel EncodedLevelCache::get(const EncodedLevelKey& key,
                                    const std::function<EncodedLevel()>& encode,
                                    const char** found_in) {
  const char* dummy = nullptr;
  const char*& where = found_in != nullptr ? *found_in : dummy;
  MemoryLayer& m = memory();
  {
    const std::lock_guard<std::mutex> lock(m.mu);
    if (const auto it = m.levels.find(key); it != m.levels.end()) {
      where = "memory";
      return it->second;
    }
  }
  std::optional<EncodedLevel> level;
  const bool disk = !dir_.empty() && max_bytes_ > 0;
  const std::string path = disk ? entry_path(key) : std::string();
  std::error_code ec;
  if (disk && fs::exists(path, ec)) {
    try {
      // The common opener: a regular file, at most the cache's limit; errors are InputErrors.
      const std::string bytes = read_input_file(path, "encoded-level cache entry", max_bytes_);
      level = decode_level_entry(bytes, path, &key);
      fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // recently used
      where = "disk";
    } catch (const InputError& e) {
      warn(std::string(e.what()) + "; removed, the level is encoded again");
      fs::remove(path, ec);
    }
  }
  if (!level) {
    level = encode();
    where = "";
    if (disk) store_on_disk(key, *level);
  }
  const std::lock_guard<std::mutex> lock(m.mu);
  if (m.bytes + level->bytes.size() <= kMemoryLimit && m.levels.emplace(key, *level).second)
    m.bytes += level->bytes.size();
  return *level;
}

void EncodedLevelCache::store_on_disk(const EncodedLevelKey& key, const EncodedLevel& level) const {
  const std::string entry = encode_level_entry(key, level);
  if (entry.size() > max_bytes_) return;  // larger than the whole cache may be
  std::error_code ec;
  fs::create_directories(dir_, ec);
  const std::string temp = cache_temp_path(dir_, Sha256::hex(key));
  bool ok = !ec;
  if (ok) {
    std::ofstream out(temp, std::ios::binary);
    out.write(entry.data(), static_cast<std::streamsize>(entry.size()));
    ok = static_cast<bool>(out.flush());
  }
  if (ok) fs::rename(temp, entry_path(key), ec);  // atomic: readers see a whole entry
  if (!ok || ec) {
    const std::string why = ec ? ec.message() : std::string(std::strerror(errno));
    fs::remove(temp, ec);
    MemoryLayer& m = memory();
    const std::lock_guard<std::mutex> lock(m.mu);
    if (m.warned.insert(dir_).second)
      warn("cannot write entries in " + dir_ + " (" + why + "); levels are encoded every run");
    return;
  }
  evict_cache_entries(dir_, max_bytes_, ".level");
}

}  // namespace texsim
