#pragma once
// `texsim import apitrace`: interprets the fixed-function OpenGL of an apitrace capture, read
// through the text of `apitrace dump --blobs` (traces/DRAWS.md, "Import from apitrace"), into
// a draw trace. What it does not interpret is counted per frame by call name, never guessed.
#include <cstdint>
#include <map>
#include <ostream>
#include <string>

#include "traces/draw_trace.h"

namespace texsim {

// Bounds of the importer's input (besides the draw trace's own limits).
inline constexpr size_t kImportMaxLineBytes = 1u << 20;         // one call of the dump
inline constexpr uint64_t kImportMaxBlobBytes = 96u << 20;      // one blob file
inline constexpr uint64_t kImportMaxTextureBytes = 1ull << 30;  // every texture level kept
inline constexpr uint32_t kImportMaxTextureNames = 65536;       // GL texture names alive

struct ImportFrameSummary {
  uint32_t frame = 0;
  uint64_t draws = 0, vertices = 0, triangles = 0;
  CallCounts uninterpreted;
};

struct ImportSummary {
  std::map<uint32_t, ImportFrameSummary> frames;
  uint64_t textures = 0, texture_bytes = 0, calls = 0, bytes = 0;
};

// Parses "A-B" or "A" (0-based frame numbers); throws InputError naming --frames.
void parse_frame_range(const std::string& text, uint32_t& first, uint32_t& last);

// Runs `apitrace dump --blobs ...` on `capture` (found on PATH, no shell) and writes frames
// first..last of it to `output`.
ImportSummary import_apitrace(const std::string& capture, uint32_t first, uint32_t last,
                              const std::string& output);

// The same from a dump's text already written to `dump_text`, its blob files in `blob_dir`
// (tests, and dumps made elsewhere). `name` names the capture in errors.
ImportSummary import_apitrace_dump(const std::string& dump_text, const std::string& blob_dir,
                                   uint32_t first, uint32_t last, const std::string& output,
                                   const std::string& name);

// The importer's report: per frame draws, vertices, triangles and uninterpreted calls.
void print_import_summary(const ImportSummary& s, const std::string& output, std::ostream& out);

}  // namespace texsim
