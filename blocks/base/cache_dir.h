#pragma once
// The directory texsim's on-disk caches live under (docs/truth-cache.md#where): the ground
// truths (truth/) and the encoded levels of compressed textures (encoded/), and what the two
// share — the size limits' syntax and the least-recently-used eviction.
#include <cstdint>
#include <string>

namespace texsim {

// TEXSIM_CACHE_DIR, else $XDG_CACHE_HOME/texsim (absolute values only, as the XDG base
// directory specification says), else $HOME/.cache/texsim; "" when none is set.
std::string cache_root_from_env();

// A size in bytes, optionally with a K, M or G suffix ("2G"); anything else is an InputError
// naming `variable=text`.
uint64_t parse_cache_max_bytes(const std::string& text, const std::string& variable);

// Removes the least recently modified files of `dir` whose names end in `suffix` until their
// total is at most `max_bytes`; files that vanish meanwhile (another process evicting) are
// skipped, and temporary files (".NAME.tmp.…") older than a day — left by a process that died
// while writing — are removed.
void evict_cache_entries(const std::string& dir, uint64_t max_bytes, const std::string& suffix);

// A temporary file name in `dir` for the entry `name`, unique to this process and call: write
// it, then rename it onto the entry so readers never see a partial one.
std::string cache_temp_path(const std::string& dir, const std::string& name);

}  // namespace texsim
