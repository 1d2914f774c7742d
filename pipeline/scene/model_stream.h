#pragma once
// What the child process of a model import (model_loader.cc, isolated_child.h) sends texsim:
// the files Assimp opened, then the converted model or the import's error message. Binary, in
// native byte order (both ends are the same program):
//   u32 magic "TXMI", u32 version 1
//   u32 opened files, each a string
//   u8 0: a model — u8 has_uvs; u32 materials, each name and texture (strings);
//         u32 vertices, each 3 f64; u32 triangles, each 3 i32 vertex, 6 f64 uv, i32 material
//   u8 1: an error — the InputError's message (a string)
//   u32 end mark "END."
// A string is u32 length and its bytes. The reader trusts nothing: every count is checked
// against model_loader.h's limits before anything is allocated, every vertex index, material
// index and number as the conversion checks them, and the stream ends at its end mark.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "pipeline/scene/isolated_child.h"
#include "pipeline/scene/model_loader.h"

namespace texsim {

inline constexpr uint32_t kMaxModelOpenedFiles = 1024;
inline constexpr uint32_t kMaxModelMessageBytes = 64 * 1024;

struct ModelMessage {
  std::vector<std::string> opened;  // files Assimp opened for the model (texsim's inputs)
  bool failed = false;
  std::string error;  // when failed: the import's InputError message
  Model model;        // otherwise
};

void write_model_message(ByteSink& out, const ModelMessage& m);
// Throws ChildFailure (Kind::Malformed) "FILE: WHO sent malformed data: what, at byte N", or the
// InputError of check_model_counts for counts over the limits or `budget`.
ModelMessage read_model_message(ByteSource& in, const std::string& file, const std::string& who,
                                const MeshBudget& budget);

// In memory: the fuzz harness and the tests.
class StringSink final : public ByteSink {
 public:
  void write(const void* buf, size_t n) override { bytes.append(static_cast<const char*>(buf), n); }
  std::string bytes;
};
class StringSource final : public ByteSource {
 public:
  explicit StringSource(std::string_view bytes) : bytes_(bytes) {}
  size_t read_some(void* buf, size_t n) override {
    n = std::min(n, bytes_.size() - pos_);
    if (n > 0) std::memcpy(buf, bytes_.data() + pos_, n);
    pos_ += n;
    return n;
  }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

}  // namespace texsim
