#pragma once
// Draw traces (traces/DRAWS.md): per frame, the draws of a fixed-function OpenGL frame with
// clip-space vertices, texture coordinates, colours, the bound textures' sampler state and the
// state deciding visibility and colour; textures are stored once and referenced by id. The
// writer streams record by record into a temporary file; the reader holds one record at a time
// and checks every size, count, index and enum against the file and the limits below.
#include <array>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "traces/trace_file.h"

namespace texsim {

inline constexpr char kDrawMagic[8] = {'T', 'E', 'X', 'S', 'I', 'M', 'D', 'R'};
inline constexpr uint32_t kDrawVersion = 1;

// Limits (DRAWS.md, "Limits"): anything beyond is corruption, so a damaged count can never
// make the reader allocate more than one record of at most kDrawMaxRecordBytes.
inline constexpr uint32_t kDrawMaxUnits = 2;  // texture units per draw
inline constexpr uint32_t kDrawMaxVertices = 1u << 20;
inline constexpr uint32_t kDrawMaxIndices = 3u << 20;
inline constexpr uint32_t kDrawMaxDrawsPerFrame = 1u << 16;
inline constexpr uint32_t kDrawMaxFrames = 1u << 20;
inline constexpr uint32_t kDrawMaxTextures = 65536;
inline constexpr uint32_t kDrawMaxTextureSize = 4096;
inline constexpr uint32_t kDrawMaxLevels = 13;  // 4096 .. 1
inline constexpr uint32_t kDrawMaxNameBytes = 256;
inline constexpr uint32_t kDrawMaxSourceBytes = 4096;
inline constexpr uint32_t kDrawMaxCallNames = 4096;  // uninterpreted call names per frame
inline constexpr uint32_t kDrawMaxRecordBytes = 96u << 20;
inline constexpr uint64_t kDrawMaxFileBytes = uint64_t{16} << 30;

// The one texel format of version 1: 4 bytes R, G, B, A per texel.
inline constexpr uint32_t kDrawFormatRgba8 = 1;

struct DrawTexture {
  uint32_t id = 0;
  uint32_t width = 0, height = 0;
  uint32_t format = kDrawFormatRgba8;
  std::string name;  // where it came from, e.g. "GL texture 42, upload 1"
  // levels[i]: max(1, width >> i) x max(1, height >> i) texels, rows in GL order (first row at
  // t = 0), 4 bytes each.
  std::vector<std::vector<uint8_t>> levels;
};

// Sampler and texture environment of one enabled texture unit. Filters, wraps and the mode
// are OpenGL enum values (DRAWS.md lists the accepted ones).
struct DrawUnit {
  uint32_t unit = 0;                                  // 0..kDrawMaxUnits-1
  uint32_t texture = 0;                               // id of a texture record before the draw
  uint32_t min_filter = 0x2703, mag_filter = 0x2601;  // LINEAR_MIPMAP_LINEAR, LINEAR
  uint32_t wrap_s = 0x2901, wrap_t = 0x2901;          // REPEAT
  float max_anisotropy = 1, lod_bias = 0;
  uint32_t env_mode = 0x2100;  // MODULATE
};

// Fixed-function state deciding visibility and colour (OpenGL enum values).
struct DrawState {
  int32_t viewport_x = 0, viewport_y = 0;
  uint32_t viewport_w = 1, viewport_h = 1;
  float depth_near = 0, depth_far = 1;
  bool depth_test = false, depth_write = true, cull = false, polygon_offset = false;
  bool alpha_test = false, blend = false;
  uint32_t depth_func = 0x0201;  // LESS
  uint32_t cull_face = 0x0405;   // BACK
  uint32_t front_face = 0x0901;  // CCW
  float offset_factor = 0, offset_units = 0;
  uint32_t alpha_func = 0x0207;  // ALWAYS
  float alpha_ref = 0;
  uint32_t blend_src = 1, blend_dst = 0;  // ONE, ZERO
};

// One draw: an indexed triangle list in clip space.
struct Draw {
  DrawState state;
  std::vector<DrawUnit> units;  // enabled units, increasing unit number
  uint32_t vertex_count = 0;
  std::vector<float> position;                       // x, y, z, w per vertex
  std::array<std::vector<float>, kDrawMaxUnits> st;  // s, t per vertex, for units[i]
  bool has_color = false;
  std::vector<uint8_t> color;     // r, g, b, a per vertex when has_color
  std::vector<uint32_t> indices;  // three per triangle, each < vertex_count
};

// Calls of a frame the importer did not interpret: name -> count.
using CallCounts = std::map<std::string, uint64_t>;

struct DrawFrame {
  uint32_t number = 0;  // frame number in the capture
  std::vector<Draw> draws;
  CallCounts uninterpreted;
};

// A whole draw trace in memory (tests, small traces).
struct DrawTrace {
  std::string source;
  std::vector<DrawTexture> textures;
  std::vector<DrawFrame> frames;
};

// Checks one draw against the limits and the enum sets; returns what is wrong or "".
// `known_texture(id)` says whether a texture id was defined.
std::string check_draw(const Draw& d, const std::vector<bool>& defined_textures);

class DrawTraceWriter {
 public:
  DrawTraceWriter(const std::string& path, const std::string& source);
  ~DrawTraceWriter();
  DrawTraceWriter(const DrawTraceWriter&) = delete;
  DrawTraceWriter& operator=(const DrawTraceWriter&) = delete;

  void add_texture(const DrawTexture& t);  // ids unique; before any draw using them
  void begin_frame(uint32_t number);       // increasing numbers
  void add_draw(const Draw& d);            // inside a frame
  void end_frame(const CallCounts& uninterpreted);
  void close();
  uint64_t bytes_written() const { return bytes_; }

 private:
  void put_record(const char tag[4], const std::vector<uint8_t>& payload);
  void put(const void* data, size_t n);
  [[noreturn]] void fail(const std::string& what);

  std::string path_, temp_;
  TraceFilePtr file_;
  std::vector<bool> defined_;
  bool in_frame_ = false, any_frame_ = false, closed_ = false;
  uint32_t last_frame_ = 0, frame_draws_ = 0;
  uint64_t frames_ = 0, draws_ = 0, textures_ = 0, records_ = 0, bytes_ = 0;
};

enum class DrawRecordKind { Texture, Frame, Draw, FrameEnd, End };

class DrawTraceReader {
 public:
  explicit DrawTraceReader(const std::string& path);
  ~DrawTraceReader();
  DrawTraceReader(const DrawTraceReader&) = delete;
  DrawTraceReader& operator=(const DrawTraceReader&) = delete;

  const std::string& source() const { return source_; }
  // Reads the next record; End once, after the end marker was checked (then End again).
  DrawRecordKind next();
  const DrawTexture& texture() const { return texture_; }     // after Texture
  uint32_t frame() const { return frame_; }                   // after Frame, Draw, FrameEnd
  const Draw& draw() const { return draw_; }                  // after Draw
  const CallCounts& uninterpreted() const { return calls_; }  // after FrameEnd

 private:
  void read_exact(void* dst, size_t n, const std::string& where, const char* what);
  std::string where() const;
  // One per record kind: p is the CRC-checked payload, at names it in errors.
  void read_texture(const std::vector<uint8_t>& p, const std::string& at);
  void read_frame_start(const std::vector<uint8_t>& p, const std::string& at);
  void read_draw(const std::vector<uint8_t>& p, std::string at);
  void read_frame_end(const std::vector<uint8_t>& p, const std::string& at);
  void read_end(const std::vector<uint8_t>& p, const std::string& at) const;

  std::string path_, source_;
  TraceFilePtr file_;
  uint64_t size_ = 0, pos_ = 0, record_pos_ = 0;
  bool done_ = false, in_frame_ = false, any_frame_ = false;
  uint32_t frame_ = 0, frame_draws_ = 0;
  uint64_t frames_ = 0, draws_ = 0, textures_ = 0, records_ = 0;
  std::vector<bool> defined_;
  DrawTexture texture_;
  Draw draw_;
  CallCounts calls_;
};

void write_draw_trace(const std::string& path, const DrawTrace& trace);
DrawTrace read_draw_trace(const std::string& path);

// True when the file at `path` starts with the draw trace magic (false if it cannot be read).
bool is_draw_trace(const std::string& path);

// A fragment trace's texture source naming texture ID of the draw trace PATH: "draws:PATH#ID"
// (written by `texsim trace gen --draws`, traces/FORMAT.md's table stores it verbatim).
std::string draws_source(const std::string& path, uint32_t id);
bool is_draws_source(const std::string& source);
// Its PATH and ID; an InputError naming the source when it is not of that form.
void split_draws_source(const std::string& source, std::string& path, uint32_t& id);
// `texsim trace info` for a draw trace, in one streaming pass: the frames with their draws,
// vertices, triangles and uninterpreted calls, and the textures with their sizes; returns 0.
int draw_trace_info(const std::string& path, std::ostream& out);

// Bytes of level `level` of a width x height RGBA8 texture.
uint64_t draw_level_bytes(uint32_t width, uint32_t height, uint32_t level);

}  // namespace texsim
