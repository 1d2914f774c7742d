#pragma once
// A content-addressed cache of encoded levels (docs/compressed-files.md#the-encoded-level-cache):
// a scene that compresses its textures at load (`compress = { … }`) pays its encoder once per
// level image, encoder, quality and library version, not once per run. astcenc spends most of
// a compressed scene's run encoding (docs/performance.md#compressed-textures), and every job of
// a sweep, every tune candidate run in a process and every study run loads the same scene again.
//
// Two layers, as the truth cache (truth_cache.h): the process keeps levels in memory (up to
// 256 MiB), and the directory <cache root>/encoded (blocks/base/cache_dir.h) keeps them across
// processes, each level an entry `<key hex>.level`: a header (magic, version, key, format,
// sizes, CRC-64 of the rest) then the encoder's provenance text and the blocks. Entries are
// written to a temporary file and renamed into place; a damaged or foreign entry fails its
// checks, is reported on stderr naming the file, removed and encoded again. The directory is
// kept under TEXSIM_ENCODED_CACHE_MAX bytes (default 1G; 0 turns the disk layer off) by
// evicting the least recently used entries.
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "blocks/base/sha256.h"
#include "pipeline/image_io/encoder_input.h"

namespace texsim {

using EncodedLevelKey = Sha256::Digest;

// The key of `img` encoded by `encoder_identity` (the encoder, its options and the format, as
// the caller spells them): a SHA-256 of those, the encoders' library versions and texsim's
// version, and the image's size and texels.
EncodedLevelKey encoded_level_key(const std::string& encoder_identity, const Rgba8Image& img);

// The libraries' versions the key includes ("libsquish 1.15; NVIDIA Texture Tools 2.0.8; …;
// texsim encoders rN").
std::string encoder_library_versions();

// The revision of texsim's own encoders (etc_encoder.h, bc7_encoder.h), part of every key: raise
// it with any change that alters their blocks, so that no cache serves the old encoder's levels.
inline constexpr int kTexsimEncoderRevision = 1;

// The on-disk entry (format version kEncodedLevelEntryVersion, little-endian).
inline constexpr uint32_t kEncodedLevelEntryVersion = 1;
inline constexpr size_t kEncodedLevelHeaderBytes = 88;
std::string encode_level_entry(const EncodedLevelKey& key, const EncodedLevel& level);
// The level of an entry; throws InputError naming `path` and what is wrong (magic, version, a
// key other than *expected when given, an unknown format, sizes that disagree with each other
// or with the file's length, a provenance too long, a CRC that does not match).
EncodedLevel decode_level_entry(std::string_view bytes, const std::string& path,
                                const EncodedLevelKey* expected);

class EncodedLevelCache {
 public:
  // dir "" or max_bytes 0: memory only.
  EncodedLevelCache(std::string dir, uint64_t max_bytes);
  // The process's cache: <cache root>/encoded, TEXSIM_ENCODED_CACHE_MAX (a bad value is an
  // InputError naming the variable).
  static EncodedLevelCache& process();

  // The level stored under `key` (memory, then disk), or `encode()`'s, which is then stored;
  // *found_in (when given) says where it came from: "memory", "disk" or "" (encoded). Safe to
  // call from several threads.
  EncodedLevel get(const EncodedLevelKey& key, const std::function<EncodedLevel()>& encode,
                   const char** found_in = nullptr);
  std::string entry_path(const EncodedLevelKey& key) const;
  // Drops the memory layer (tests of the disk layer).
  static void forget_memory();

 private:
  void store_on_disk(const EncodedLevelKey& key, const EncodedLevel& level) const;
  std::string dir_;
  uint64_t max_bytes_;
};

}  // namespace texsim
