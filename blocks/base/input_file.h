#pragma once
// The one way every reader opens its input (scenes, sweeps, OBJ/MTL, DEM archives, merge and
// tune JSON, traces, textures): a regular file only, its size checked against the reader's
// limit before a byte is read, and opening never blocks. A directory, FIFO, device or socket
// gets an InputError naming the path and what it is. Every file opened here is remembered, so
// that an output about to replace it is refused (refuse_overwriting_input): a run never
// overwrites its own input.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>

namespace texsim {

// Limits of the readers (docs/cli.md#input-limits lists them).
inline constexpr uint64_t kMiB = uint64_t{1} << 20;
inline constexpr uint64_t kMaxTextInput = 16 * kMiB;  // scene, sweep, MTL files
inline constexpr uint64_t kMaxJsonInput = 64 * kMiB;  // report.json, job.json, tune shards
inline constexpr uint64_t kNoSizeLimit = UINT64_MAX;  // streamed readers (traces)

struct FileCloser {
  void operator()(std::FILE* f) const;
};
using InputFilePtr = std::unique_ptr<std::FILE, FileCloser>;

// Opens `path` for reading as described above; `what` names the input in errors ("scene
// file", "OBJ mesh", …). `size`, when given, receives the file's size in bytes.
InputFilePtr open_input_file(const std::string& path, std::string_view what, uint64_t max_bytes,
                             uint64_t* size = nullptr);
// The whole file (at most `max_bytes`), or an InputError naming the path and the reason.
std::string read_input_file(const std::string& path, std::string_view what, uint64_t max_bytes);
// The checks of open_input_file without reading, for readers that open the path themselves
// (OpenImageIO): returns the size.
uint64_t check_input_file(const std::string& path, std::string_view what, uint64_t max_bytes);

// Throws InputError naming `target` when it is a file this process opened as an input: the
// writers call it before they replace a file (OutputSet::commit, commit_temp).
void refuse_overwriting_input(const std::string& target);

}  // namespace texsim
