#include "traces/draw_trace.h"

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string_view>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "traces/byte_order.h"

namespace texsim {

namespace {

constexpr char kTexTag[4] = {'T', 'E', 'X', 'R'};
constexpr char kFrameTag[4] = {'F', 'R', 'A', 'M'};
constexpr char kDrawTag[4] = {'D', 'R', 'A', 'W'};
constexpr char kFrameEndTag[4] = {'F', 'E', 'N', 'D'};
constexpr char kEndTag[4] = {'T', 'E', 'N', 'D'};
constexpr uint32_t kRecordHeaderBytes = 12;
constexpr uint32_t kDrawStateBytes = 64;
constexpr uint32_t kDrawCountsBytes = 16;
constexpr uint32_t kUnitBytes = 36;
constexpr uint32_t kEndBytes = 32;

// Flag bits of a draw's state word.
constexpr uint32_t kDepthTest = 1, kDepthWrite = 2, kCull = 4, kPolygonOffset = 8, kAlphaTest = 16,
                   kBlend = 32, kAllFlags = 63;

bool one_of(uint32_t v, std::initializer_list<uint32_t> set) {
  return std::find(set.begin(), set.end(), v) != set.end();
}
bool is_filter(uint32_t v) { return v == 0x2600 || v == 0x2601; }
bool is_min_filter(uint32_t v) { return is_filter(v) || (v >= 0x2700 && v <= 0x2703); }
bool is_wrap(uint32_t v) { return one_of(v, {0x2900, 0x2901, 0x812F, 0x812D, 0x8370}); }
bool is_env(uint32_t v) { return one_of(v, {0x2100, 0x2101, 0x0BE2, 0x1E01, 0x0104, 0x8570}); }
bool is_func(uint32_t v) { return v >= 0x0200 && v <= 0x0207; }
bool is_blend_factor(uint32_t v) { return v <= 1 || (v >= 0x0300 && v <= 0x0308); }

std::string hex(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%04x", v);
  return b;
}

std::string tag_text(const unsigned char* t) {
  std::string s;
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>(t[i]);
    s += (c >= 0x21 && c <= 0x7e) ? c : '?';
  }
  return s;
}

bool has_control(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u < 0x20 || u == 0x7f;
  });
}

uint32_t vertex_bytes(uint32_t units, bool color) { return 16 + 8 * units + (color ? 4 : 0); }

uint32_t state_flags(const DrawState& s) {
  return (s.depth_test ? kDepthTest : 0) | (s.depth_write ? kDepthWrite : 0) |
         (s.cull ? kCull : 0) | (s.polygon_offset ? kPolygonOffset : 0) |
         (s.alpha_test ? kAlphaTest : 0) | (s.blend ? kBlend : 0);
}

// Checks a texture's header values; "" when they are valid.
std::string check_texture_header(uint32_t id, uint32_t w, uint32_t h, uint32_t format,
                                 uint32_t levels, const std::string& name) {
  if (id >= kDrawMaxTextures)
    return "texture id " + std::to_string(id) + " is outside 0.." +
           std::to_string(kDrawMaxTextures - 1);
  if (w < 1 || h < 1 || w > kDrawMaxTextureSize || h > kDrawMaxTextureSize)
    return "texture " + std::to_string(id) + ": size " + std::to_string(w) + "x" +
           std::to_string(h) + " is outside 1.." + std::to_string(kDrawMaxTextureSize);
  if (format != kDrawFormatRgba8)
    return "texture " + std::to_string(id) + ": unknown format " + std::to_string(format);
  const uint32_t most = std::bit_width(std::max(w, h));
  if (levels < 1 || levels > most)
    return "texture " + std::to_string(id) + ": " + std::to_string(levels) +
           " mip levels, outside 1.." + std::to_string(most) + " for " + std::to_string(w) + "x" +
           std::to_string(h);
  if (name.size() > kDrawMaxNameBytes || has_control(name))
    return "texture " + std::to_string(id) + ": name longer than " +
           std::to_string(kDrawMaxNameBytes) + " bytes or with a control character";
  return {};
}

}  // namespace

uint64_t draw_level_bytes(uint32_t width, uint32_t height, uint32_t level) {
  const uint64_t w = std::max<uint64_t>(1, width >> std::min(level, 31u));
  const uint64_t h = std::max<uint64_t>(1, height >> std::min(level, 31u));
  return w * h * 4;
}

std::string check_draw(const Draw& d, const std::vector<bool>& defined) {
  const DrawState& s = d.state;
  if (s.viewport_w < 1 || s.viewport_h < 1 || s.viewport_w > 16384 || s.viewport_h > 16384)
    return "viewport size " + std::to_string(s.viewport_w) + "x" + std::to_string(s.viewport_h) +
           " is outside 1..16384";
  if (!(s.depth_near >= 0 && s.depth_near <= 1 && s.depth_far >= 0 && s.depth_far <= 1))
    return "depth range is not inside [0, 1]";
  if (!std::isfinite(s.offset_factor) || !std::isfinite(s.offset_units))
    return "polygon offset is not finite";
  if (!(s.alpha_ref >= 0 && s.alpha_ref <= 1)) return "alpha reference is not inside [0, 1]";
  if (!is_func(s.depth_func)) return "depth function " + hex(s.depth_func) + " is not known";
  if (!is_func(s.alpha_func)) return "alpha function " + hex(s.alpha_func) + " is not known";
  if (!one_of(s.cull_face, {0x0404, 0x0405, 0x0408}))
    return "cull face " + hex(s.cull_face) + " is not known";
  if (!one_of(s.front_face, {0x0900, 0x0901}))
    return "front face " + hex(s.front_face) + " is not known";
  if (!is_blend_factor(s.blend_src) || !is_blend_factor(s.blend_dst))
    return "blend factors " + hex(s.blend_src) + ", " + hex(s.blend_dst) + " are not known";
  if (d.units.size() > kDrawMaxUnits)
    return std::to_string(d.units.size()) + " texture units, more than " +
           std::to_string(kDrawMaxUnits);
  for (size_t i = 0; i < d.units.size(); ++i) {
    const DrawUnit& u = d.units[i];
    const std::string at = "unit entry " + std::to_string(i) + ": ";
    if (u.unit >= kDrawMaxUnits || (i > 0 && u.unit <= d.units[i - 1].unit))
      return at + "unit number " + std::to_string(u.unit) + " is out of order or above " +
             std::to_string(kDrawMaxUnits - 1);
    if (u.texture >= defined.size() || !defined[u.texture])
      return at + "texture id " + std::to_string(u.texture) +
             " has no texture record before the draw";
    if (!is_min_filter(u.min_filter) || !is_filter(u.mag_filter))
      return at + "filters " + hex(u.min_filter) + ", " + hex(u.mag_filter) + " are not known";
    if (!is_wrap(u.wrap_s) || !is_wrap(u.wrap_t))
      return at + "wrap modes " + hex(u.wrap_s) + ", " + hex(u.wrap_t) + " are not known";
    if (!(u.max_anisotropy >= 1 && u.max_anisotropy <= 16))
      return at + "max anisotropy is not inside [1, 16]";
    if (!(u.lod_bias >= -16 && u.lod_bias <= 16)) return at + "LOD bias is not inside [-16, 16]";
    if (!is_env(u.env_mode)) return at + "texture environment " + hex(u.env_mode) + " is not known";
  }
  const uint64_t n = d.vertex_count;
  if (n > kDrawMaxVertices)
    return std::to_string(n) + " vertices, more than " + std::to_string(kDrawMaxVertices);
  if (d.indices.size() > kDrawMaxIndices || d.indices.size() % 3 != 0)
    return std::to_string(d.indices.size()) + " indices: not a multiple of 3 up to " +
           std::to_string(kDrawMaxIndices);
  if (d.position.size() != 4 * n || (d.has_color ? d.color.size() != 4 * n : !d.color.empty()))
    return "vertex arrays do not match the vertex count " + std::to_string(n);
  for (size_t i = 0; i < kDrawMaxUnits; ++i) {
    const size_t want = i < d.units.size() ? 2 * n : 0;
    if (d.st[i].size() != want)
      return "texture coordinates of unit entry " + std::to_string(i) +
             " do not match the vertex count";
  }
  for (size_t v = 0; v < n; ++v) {
    for (int c = 0; c < 4; ++c) {
      if (!std::isfinite(d.position[4 * v + c]))
        return "vertex " + std::to_string(v) + ": clip-space position is " +
               (std::isnan(d.position[4 * v + c]) ? "NaN" : "infinite");
    }
    for (size_t i = 0; i < d.units.size(); ++i) {
      if (!std::isfinite(d.st[i][2 * v]) || !std::isfinite(d.st[i][2 * v + 1]))
        return "vertex " + std::to_string(v) + ": texture coordinate of unit entry " +
               std::to_string(i) + " is NaN or infinite";
    }
  }
  for (size_t i = 0; i < d.indices.size(); ++i) {
    if (d.indices[i] >= n)
      return "index " + std::to_string(i) + " is " + std::to_string(d.indices[i]) +
             ", not below the vertex count " + std::to_string(n);
  }
  return {};
}

// ---------------------------------------------------------------------------------------------
// Writer

DrawTraceWriter::DrawTraceWriter(const std::string& path, const std::string& source)
    : path_(path), temp_(temp_path_for(path)) {
  if (source.size() > kDrawMaxSourceBytes || has_control(source))
    throw InputError(path_, "source text longer than " + std::to_string(kDrawMaxSourceBytes) +
                                " bytes or with a control character");
  std::vector<unsigned char> h(kDrawMagic, kDrawMagic + sizeof kDrawMagic);
  append_le<uint32_t>(h, kDrawVersion);
  append_le<uint32_t>(h, static_cast<uint32_t>(source.size()));
  h.insert(h.end(), source.begin(), source.end());
  append_le<uint32_t>(h, trace_crc32(h.data(), h.size()));
  file_.reset(std::fopen(temp_.c_str(), "wb"));
  if (!file_)
    throw InputError(path_, std::string("cannot open for writing: ") + std::strerror(errno));
  put(h.data(), h.size());
}

DrawTraceWriter::~DrawTraceWriter() {
  if (!closed_) {
    file_.reset();
    discard_temp(temp_, path_);
  }
}

void DrawTraceWriter::fail(const std::string& what) {
  file_.reset();
  discard_temp(temp_, path_);
  closed_ = true;
  throw InputError(path_, what);
}

void DrawTraceWriter::put(const void* data, size_t n) {
  if (std::fwrite(data, 1, n, file_.get()) != n)
    fail(std::string("write failed: ") + std::strerror(errno));
  bytes_ += n;
}

void DrawTraceWriter::put_record(const char tag[4], const std::vector<uint8_t>& payload) {
  if (closed_) throw InputError(path_, "write after close");
  if (payload.size() > kDrawMaxRecordBytes)
    throw InputError(path_, "record of " + std::to_string(payload.size()) +
                                " bytes, more than the limit " +
                                std::to_string(kDrawMaxRecordBytes));
  if (bytes_ + kRecordHeaderBytes + payload.size() + kRecordHeaderBytes + kEndBytes >
      kDrawMaxFileBytes)
    fail("the trace would exceed " + std::to_string(kDrawMaxFileBytes) + " bytes");
  unsigned char h[kRecordHeaderBytes];
  std::memcpy(h, tag, 4);
  store_le<uint32_t>(h + 4, static_cast<uint32_t>(payload.size()));
  store_le<uint32_t>(h + 8, trace_crc32(payload.data(), payload.size()));
  put(h, sizeof h);
  put(payload.data(), payload.size());
  ++records_;
}

void DrawTraceWriter::add_texture(const DrawTexture& t) {
  const std::string bad =
      check_texture_header(t.id, t.width, t.height, t.format,
                           static_cast<uint32_t>(std::min<size_t>(t.levels.size(), 1000)), t.name);
  if (!bad.empty()) throw InputError(path_, bad);
  if (t.id < defined_.size() && defined_[t.id])
    throw InputError(path_, "texture id " + std::to_string(t.id) + " written twice");
  std::vector<uint8_t> p;
  append_le<uint32_t>(p, t.id);
  append_le<uint32_t>(p, t.width);
  append_le<uint32_t>(p, t.height);
  append_le<uint32_t>(p, t.format);
  append_le<uint32_t>(p, static_cast<uint32_t>(t.levels.size()));
  append_le<uint32_t>(p, static_cast<uint32_t>(t.name.size()));
  p.insert(p.end(), t.name.begin(), t.name.end());
  for (size_t l = 0; l < t.levels.size(); ++l) {
    if (t.levels[l].size() != draw_level_bytes(t.width, t.height, static_cast<uint32_t>(l)))
      throw InputError(
          path_, "texture " + std::to_string(t.id) + ", level " + std::to_string(l) + ": " +
                     std::to_string(t.levels[l].size()) + " bytes, expected " +
                     std::to_string(draw_level_bytes(t.width, t.height, static_cast<uint32_t>(l))));
    p.insert(p.end(), t.levels[l].begin(), t.levels[l].end());
  }
  put_record(kTexTag, p);
  if (defined_.size() <= t.id) defined_.resize(t.id + 1, false);
  defined_[t.id] = true;
  ++textures_;
}

void DrawTraceWriter::begin_frame(uint32_t number) {
  if (in_frame_)
    throw InputError(path_, "frame " + std::to_string(number) + " begun inside a frame");
  if (any_frame_ && number <= last_frame_)
    throw InputError(path_, "frame " + std::to_string(number) + " after frame " +
                                std::to_string(last_frame_) + ": numbers must increase");
  if (frames_ >= kDrawMaxFrames)
    throw InputError(path_, "more than " + std::to_string(kDrawMaxFrames) + " frames");
  std::vector<uint8_t> p;
  append_le<uint32_t>(p, number);
  put_record(kFrameTag, p);
  in_frame_ = any_frame_ = true;
  last_frame_ = number;
  frame_draws_ = 0;
  ++frames_;
}

void DrawTraceWriter::add_draw(const Draw& d) {
  const std::string where =
      path_ + ": frame " + std::to_string(last_frame_) + ", draw " + std::to_string(frame_draws_);
  if (!in_frame_) throw InputError(path_, "draw outside a frame");
  if (frame_draws_ >= kDrawMaxDrawsPerFrame)
    throw InputError(where,
                     "more than " + std::to_string(kDrawMaxDrawsPerFrame) + " draws in the frame");
  const std::string bad = check_draw(d, defined_);
  if (!bad.empty()) throw InputError(where, bad);
  const DrawState& s = d.state;
  const auto units = static_cast<uint32_t>(d.units.size());
  std::vector<uint8_t> p;
  p.reserve(kDrawStateBytes + kDrawCountsBytes + size_t{units} * kUnitBytes +
            size_t{d.vertex_count} * vertex_bytes(units, d.has_color) + 4 * d.indices.size());
  append_le<int32_t>(p, s.viewport_x);
  append_le<int32_t>(p, s.viewport_y);
  append_le<uint32_t>(p, s.viewport_w);
  append_le<uint32_t>(p, s.viewport_h);
  append_le<float>(p, s.depth_near);
  append_le<float>(p, s.depth_far);
  append_le<uint32_t>(p, state_flags(s));
  append_le<uint32_t>(p, s.depth_func);
  append_le<uint32_t>(p, s.cull_face);
  append_le<uint32_t>(p, s.front_face);
  append_le<float>(p, s.offset_factor);
  append_le<float>(p, s.offset_units);
  append_le<uint32_t>(p, s.alpha_func);
  append_le<float>(p, s.alpha_ref);
  append_le<uint32_t>(p, s.blend_src);
  append_le<uint32_t>(p, s.blend_dst);
  append_le<uint32_t>(p, units);
  append_le<uint32_t>(p, d.has_color ? 1 : 0);
  append_le<uint32_t>(p, d.vertex_count);
  append_le<uint32_t>(p, static_cast<uint32_t>(d.indices.size()));
  for (const DrawUnit& u : d.units) {
    append_le<uint32_t>(p, u.unit);
    append_le<uint32_t>(p, u.texture);
    append_le<uint32_t>(p, u.min_filter);
    append_le<uint32_t>(p, u.mag_filter);
    append_le<uint32_t>(p, u.wrap_s);
    append_le<uint32_t>(p, u.wrap_t);
    append_le<float>(p, u.max_anisotropy);
    append_le<float>(p, u.lod_bias);
    append_le<uint32_t>(p, u.env_mode);
  }
  for (size_t v = 0; v < d.vertex_count; ++v) {
    for (int c = 0; c < 4; ++c) append_le<float>(p, d.position[4 * v + c]);
    for (uint32_t i = 0; i < units; ++i) {
      append_le<float>(p, d.st[i][2 * v]);
      append_le<float>(p, d.st[i][2 * v + 1]);
    }
    if (d.has_color) {
      const auto off = static_cast<ptrdiff_t>(4 * v);
      p.insert(p.end(), d.color.begin() + off, d.color.begin() + off + 4);
    }
  }
  for (uint32_t i : d.indices) append_le<uint32_t>(p, i);
  put_record(kDrawTag, p);
  ++frame_draws_;
  ++draws_;
}

void DrawTraceWriter::end_frame(const CallCounts& uninterpreted) {
  if (!in_frame_) throw InputError(path_, "frame end outside a frame");
  if (uninterpreted.size() > kDrawMaxCallNames)
    throw InputError(path_, "frame " + std::to_string(last_frame_) + ": " +
                                std::to_string(uninterpreted.size()) +
                                " uninterpreted call names, more than " +
                                std::to_string(kDrawMaxCallNames));
  std::vector<uint8_t> p;
  append_le<uint32_t>(p, frame_draws_);
  append_le<uint32_t>(p, static_cast<uint32_t>(uninterpreted.size()));
  for (const auto& [name, count] : uninterpreted) {
    if (name.empty() || name.size() > kDrawMaxNameBytes || has_control(name))
      throw InputError(path_, "frame " + std::to_string(last_frame_) +
                                  ": uninterpreted call name of " + std::to_string(name.size()) +
                                  " bytes (1.." + std::to_string(kDrawMaxNameBytes) +
                                  ", no control characters)");
    append_le<uint32_t>(p, static_cast<uint32_t>(name.size()));
    p.insert(p.end(), name.begin(), name.end());
    append_le<uint64_t>(p, count);
  }
  put_record(kFrameEndTag, p);
  in_frame_ = false;
}

void DrawTraceWriter::close() {
  if (closed_) return;
  if (in_frame_) throw InputError(path_, "close inside frame " + std::to_string(last_frame_));
  std::vector<uint8_t> p;
  append_le<uint64_t>(p, frames_);
  append_le<uint64_t>(p, draws_);
  append_le<uint64_t>(p, textures_);
  append_le<uint64_t>(p, records_);
  put_record(kEndTag, p);
  if (std::fflush(file_.get()) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  std::FILE* f = file_.release();
  if (std::fclose(f) != 0) fail(std::string("write failed: ") + std::strerror(errno));
  closed_ = true;
  commit_temp(temp_, path_);
}

// ---------------------------------------------------------------------------------------------
// Reader

DrawTraceReader::DrawTraceReader(const std::string& path) : path_(path) {
  file_ = TraceFilePtr(open_input_file(path_, "draw trace", kDrawMaxFileBytes, &size_).release());
  const std::string where = path_ + ": header";
  unsigned char h[16];
  read_exact(h, sizeof h, where, "fixed header");
  if (std::memcmp(h, kDrawMagic, sizeof kDrawMagic) != 0)
    throw InputError(where, "bad magic: not a texsim draw trace (expected \"TEXSIMDR\")");
  const auto version = load_le<uint32_t>(h + 8);
  const auto source_len = load_le<uint32_t>(h + 12);
  if (version != kDrawVersion)
    throw InputError(where, "unknown version " + std::to_string(version) +
                                " (this reader reads version " + std::to_string(kDrawVersion) +
                                ")");
  if (source_len > kDrawMaxSourceBytes)
    throw InputError(where, "source length " + std::to_string(source_len) + " exceeds " +
                                std::to_string(kDrawMaxSourceBytes));
  std::vector<unsigned char> all(h, h + sizeof h);
  all.resize(sizeof h + source_len + 4);
  read_exact(all.data() + sizeof h, source_len + 4, where, "source and header CRC");
  const auto stored = load_le<uint32_t>(all.data() + sizeof h + source_len);
  const uint32_t crc = trace_crc32(all.data(), sizeof h + source_len);
  if (stored != crc) throw InputError(where, "header CRC mismatch");
  source_.assign(reinterpret_cast<const char*>(all.data()) + sizeof h, source_len);
  if (has_control(source_)) throw InputError(where, "source text has a control character");
}

DrawTraceReader::~DrawTraceReader() = default;

void DrawTraceReader::read_exact(void* dst, size_t n, const std::string& where, const char* what) {
  if (n > size_ - pos_)
    throw InputError(where, std::string("truncated file: ") + what + " needs " + std::to_string(n) +
                                " bytes, only " + std::to_string(size_ - pos_) + " remain");
  if (std::fread(dst, 1, n, file_.get()) != n)
    throw InputError(where, std::string("cannot read ") + what);
  pos_ += n;
}

std::string DrawTraceReader::where() const {
  return path_ + ": record " + std::to_string(records_) + " at byte " + std::to_string(record_pos_);
}

namespace {

// Bounds-checked little-endian cursor over one record's payload.
struct Cursor {
  const std::vector<uint8_t>& p;
  size_t at = 0;
  const std::string& where;
  void need(uint64_t n) const {
    if (n > p.size() - at)
      throw InputError(where, "record ends early: needs " + std::to_string(n) +
                                  " more bytes at payload byte " + std::to_string(at) + " of " +
                                  std::to_string(p.size()));
  }
  template <class T>
  T get() {
    need(sizeof(T));
    const T v = load_le<T>(p.data() + at);
    at += sizeof(T);
    return v;
  }
  std::string text(uint32_t n) {
    need(n);
    std::string s(reinterpret_cast<const char*>(p.data()) + at, n);
    at += n;
    return s;
  }
  void done() const {
    if (at != p.size())
      throw InputError(where, std::to_string(p.size() - at) + " unexplained bytes at the end");
  }
};

// The fixed-size render state at the start of a DRAW payload.
void read_draw_state(Cursor& c, DrawState& s) {
  s.viewport_x = c.get<int32_t>();
  s.viewport_y = c.get<int32_t>();
  s.viewport_w = c.get<uint32_t>();
  s.viewport_h = c.get<uint32_t>();
  s.depth_near = c.get<float>();
  s.depth_far = c.get<float>();
  const auto flags = c.get<uint32_t>();
  if (flags & ~kAllFlags) throw InputError(c.where, "unknown state flag bits " + hex(flags));
  s.depth_test = flags & kDepthTest;
  s.depth_write = flags & kDepthWrite;
  s.cull = flags & kCull;
  s.polygon_offset = flags & kPolygonOffset;
  s.alpha_test = flags & kAlphaTest;
  s.blend = flags & kBlend;
  s.depth_func = c.get<uint32_t>();
  s.cull_face = c.get<uint32_t>();
  s.front_face = c.get<uint32_t>();
  s.offset_factor = c.get<float>();
  s.offset_units = c.get<float>();
  s.alpha_func = c.get<uint32_t>();
  s.alpha_ref = c.get<float>();
  s.blend_src = c.get<uint32_t>();
  s.blend_dst = c.get<uint32_t>();
}

}  // namespace

DrawRecordKind DrawTraceReader::next() {
  if (done_) return DrawRecordKind::End;
  record_pos_ = pos_;
  std::string at = where();
  if (pos_ == size_) throw InputError(at, "truncated file: ends without the end marker (TEND)");
  unsigned char h[kRecordHeaderBytes];
  read_exact(h, sizeof h, at, "record header");
  const auto len = load_le<uint32_t>(h + 4);
  const auto stored = load_le<uint32_t>(h + 8);
  const std::string tag = tag_text(h);
  at += " (" + tag + ")";
  if (len > kDrawMaxRecordBytes)
    throw InputError(at, "record length " + std::to_string(len) + " exceeds the limit " +
                             std::to_string(kDrawMaxRecordBytes));
  if (len > size_ - pos_)  // checked before allocating
    throw InputError(at, "truncated record: needs " + std::to_string(len) + " bytes, only " +
                             std::to_string(size_ - pos_) + " remain");
  std::vector<uint8_t> p(len);
  read_exact(p.data(), len, at, "record payload");
  if (trace_crc32(p.data(), len) != stored) throw InputError(at, "CRC mismatch");
  if (in_frame_) at += ", frame " + std::to_string(frame_);
  DrawRecordKind kind;
  if (std::memcmp(h, kTexTag, 4) == 0) {
    read_texture(p, at);
    kind = DrawRecordKind::Texture;
  } else if (std::memcmp(h, kFrameTag, 4) == 0) {
    read_frame_start(p, at);
    kind = DrawRecordKind::Frame;
  } else if (std::memcmp(h, kDrawTag, 4) == 0) {
    read_draw(p, at);
    kind = DrawRecordKind::Draw;
  } else if (std::memcmp(h, kFrameEndTag, 4) == 0) {
    read_frame_end(p, at);
    kind = DrawRecordKind::FrameEnd;
  } else if (std::memcmp(h, kEndTag, 4) == 0) {
    read_end(p, at);
    done_ = true;
    return DrawRecordKind::End;
  } else {
    throw InputError(at, "unknown record tag (expected TEXR, FRAM, DRAW, FEND or TEND)");
  }
  ++records_;
  return kind;
}

// A TEXR payload: header, name and every level; the id must be new.
void DrawTraceReader::read_texture(const std::vector<uint8_t>& p, const std::string& at) {
  Cursor c{p, 0, at};
  texture_ = DrawTexture{};
  texture_.id = c.get<uint32_t>();
  texture_.width = c.get<uint32_t>();
  texture_.height = c.get<uint32_t>();
  texture_.format = c.get<uint32_t>();
  const auto levels = c.get<uint32_t>();
  const auto name_len = c.get<uint32_t>();
  if (name_len > kDrawMaxNameBytes)
    throw InputError(at, "texture name length " + std::to_string(name_len) + " exceeds " +
                             std::to_string(kDrawMaxNameBytes));
  texture_.name = c.text(name_len);
  const std::string bad = check_texture_header(texture_.id, texture_.width, texture_.height,
                                               texture_.format, levels, texture_.name);
  if (!bad.empty()) throw InputError(at, bad);
  if (texture_.id < defined_.size() && defined_[texture_.id])
    throw InputError(at, "texture id " + std::to_string(texture_.id) + " defined twice");
  for (uint32_t l = 0; l < levels; ++l) {
    const uint64_t n = draw_level_bytes(texture_.width, texture_.height, l);
    c.need(n);
    texture_.levels.emplace_back(p.begin() + static_cast<ptrdiff_t>(c.at),
                                 p.begin() + static_cast<ptrdiff_t>(c.at + n));
    c.at += n;
  }
  c.done();
  if (defined_.size() <= texture_.id) defined_.resize(texture_.id + 1, false);
  defined_[texture_.id] = true;
  ++textures_;
}

// A FRAM payload: the frame number, which must increase.
void DrawTraceReader::read_frame_start(const std::vector<uint8_t>& p, const std::string& at) {
  Cursor c{p, 0, at};
  const auto number = c.get<uint32_t>();
  c.done();
  if (in_frame_) throw InputError(at, "frame begins inside frame " + std::to_string(frame_));
  if (any_frame_ && number <= frame_)
    throw InputError(at, "frame " + std::to_string(number) + " after frame " +
                             std::to_string(frame_) + ": numbers must increase");
  if (frames_ >= kDrawMaxFrames)
    throw InputError(at, "more than " + std::to_string(kDrawMaxFrames) + " frames");
  frame_ = number;
  in_frame_ = any_frame_ = true;
  frame_draws_ = 0;
  ++frames_;
}

// A DRAW payload: state, counts (checked against the length before filling), units,
// vertices and indices, then the whole draw is validated.
void DrawTraceReader::read_draw(const std::vector<uint8_t>& p, std::string at) {
  if (!in_frame_) throw InputError(at, "draw outside a frame");
  at += ", draw " + std::to_string(frame_draws_);
  if (frame_draws_ >= kDrawMaxDrawsPerFrame)
    throw InputError(at,
                     "more than " + std::to_string(kDrawMaxDrawsPerFrame) + " draws in the frame");
  Cursor c{p, 0, at};
  Draw& d = draw_;
  read_draw_state(c, d.state);
  const auto units = c.get<uint32_t>();
  const auto color = c.get<uint32_t>();
  const auto verts = c.get<uint32_t>();
  const auto nidx = c.get<uint32_t>();
  if (units > kDrawMaxUnits)
    throw InputError(
        at, std::to_string(units) + " texture units, more than " + std::to_string(kDrawMaxUnits));
  if (color > 1) throw InputError(at, "colour flag " + std::to_string(color) + " is not 0 or 1");
  if (verts > kDrawMaxVertices)
    throw InputError(
        at, std::to_string(verts) + " vertices, more than " + std::to_string(kDrawMaxVertices));
  if (nidx > kDrawMaxIndices || nidx % 3 != 0)
    throw InputError(at, std::to_string(nidx) + " indices: not a multiple of 3 up to " +
                             std::to_string(kDrawMaxIndices));
  const uint64_t want = uint64_t{kDrawStateBytes} + kDrawCountsBytes +
                        uint64_t{units} * kUnitBytes +
                        uint64_t{verts} * vertex_bytes(units, color) + uint64_t{nidx} * 4;
  if (want != p.size())
    throw InputError(at, "record is " + std::to_string(p.size()) + " bytes, its counts (" +
                             std::to_string(verts) + " vertices, " + std::to_string(nidx) +
                             " indices, " + std::to_string(units) + " units) need " +
                             std::to_string(want));
  d.units.assign(units, DrawUnit{});
  for (DrawUnit& u : d.units) {
    u.unit = c.get<uint32_t>();
    u.texture = c.get<uint32_t>();
    u.min_filter = c.get<uint32_t>();
    u.mag_filter = c.get<uint32_t>();
    u.wrap_s = c.get<uint32_t>();
    u.wrap_t = c.get<uint32_t>();
    u.max_anisotropy = c.get<float>();
    u.lod_bias = c.get<float>();
    u.env_mode = c.get<uint32_t>();
  }
  d.vertex_count = verts;
  d.has_color = color != 0;
  d.position.resize(size_t{4} * verts);
  for (uint32_t i = 0; i < kDrawMaxUnits; ++i) d.st[i].resize(i < units ? size_t{2} * verts : 0);
  d.color.resize(d.has_color ? size_t{4} * verts : 0);
  for (size_t v = 0; v < verts; ++v) {
    for (int k = 0; k < 4; ++k) d.position[4 * v + k] = c.get<float>();
    for (uint32_t i = 0; i < units; ++i) {
      d.st[i][2 * v] = c.get<float>();
      d.st[i][2 * v + 1] = c.get<float>();
    }
    if (d.has_color) {
      c.need(4);
      std::memcpy(&d.color[4 * v], p.data() + c.at, 4);
      c.at += 4;
    }
  }
  d.indices.resize(nidx);
  for (uint32_t i = 0; i < nidx; ++i) d.indices[i] = c.get<uint32_t>();
  c.done();
  const std::string bad = check_draw(d, defined_);
  if (!bad.empty()) throw InputError(at, bad);
  ++frame_draws_;
  ++draws_;
}

// A FEND payload: the frame's draw count and its uninterpreted call names.
void DrawTraceReader::read_frame_end(const std::vector<uint8_t>& p, const std::string& at) {
  if (!in_frame_) throw InputError(at, "frame end outside a frame");
  Cursor c{p, 0, at};
  const auto draws = c.get<uint32_t>();
  const auto names = c.get<uint32_t>();
  if (draws != frame_draws_)
    throw InputError(at, "frame end counts " + std::to_string(draws) + " draws, the frame has " +
                             std::to_string(frame_draws_));
  if (names > kDrawMaxCallNames)
    throw InputError(at, std::to_string(names) + " uninterpreted call names, more than " +
                             std::to_string(kDrawMaxCallNames));
  calls_.clear();
  for (uint32_t i = 0; i < names; ++i) {
    const auto n = c.get<uint32_t>();
    if (n < 1 || n > kDrawMaxNameBytes)
      throw InputError(at, "call name " + std::to_string(i) + ": length " + std::to_string(n) +
                               " is outside 1.." + std::to_string(kDrawMaxNameBytes));
    std::string name = c.text(n);
    if (has_control(name))
      throw InputError(at, "call name " + std::to_string(i) + " has a control character");
    const auto count = c.get<uint64_t>();
    if (!calls_.emplace(std::move(name), count).second)
      throw InputError(at, "call name " + std::to_string(i) + " appears twice");
  }
  c.done();
  in_frame_ = false;
}

// A TEND payload: its totals must match what was read, and nothing may follow it.
void DrawTraceReader::read_end(const std::vector<uint8_t>& p, const std::string& at) const {
  if (in_frame_) throw InputError(at, "end marker inside frame " + std::to_string(frame_));
  Cursor c{p, 0, at};
  const auto frames = c.get<uint64_t>();
  const auto draws = c.get<uint64_t>();
  const auto textures = c.get<uint64_t>();
  const auto records = c.get<uint64_t>();
  c.done();
  if (frames != frames_ || draws != draws_ || textures != textures_ || records != records_)
    throw InputError(at, "end marker counts " + std::to_string(frames) + " frames, " +
                             std::to_string(draws) + " draws, " + std::to_string(textures) +
                             " textures, " + std::to_string(records) + " records; the file holds " +
                             std::to_string(frames_) + ", " + std::to_string(draws_) + ", " +
                             std::to_string(textures_) + ", " + std::to_string(records_) +
                             " (records lost)");
  if (pos_ != size_)
    throw InputError(at, std::to_string(size_ - pos_) + " unexpected bytes after the end marker");
}

namespace {
constexpr std::string_view kDrawsPrefix = "draws:";
}  // namespace

std::string draws_source(const std::string& path, uint32_t id) {
  return std::string(kDrawsPrefix) + path + "#" + std::to_string(id);
}

bool is_draws_source(const std::string& source) { return source.starts_with(kDrawsPrefix); }

void split_draws_source(const std::string& source, std::string& path, uint32_t& id) {
  const size_t hash = source.rfind('#');
  const std::string digits = hash == std::string::npos ? "" : source.substr(hash + 1);
  if (!is_draws_source(source) || hash <= kDrawsPrefix.size() || digits.empty() ||
      digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string::npos) {
    throw InputError(source, "not a draw-trace texture source \"draws:PATH#ID\"");
  }
  path = source.substr(kDrawsPrefix.size(), hash - kDrawsPrefix.size());
  id = static_cast<uint32_t>(std::stoul(digits));
}

bool is_draw_trace(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  char magic[sizeof kDrawMagic] = {};
  const bool yes = std::fread(magic, 1, sizeof magic, f) == sizeof magic &&
                   std::memcmp(magic, kDrawMagic, sizeof magic) == 0;
  std::fclose(f);
  return yes;
}

int draw_trace_info(const std::string& path, std::ostream& out) {
  DrawTraceReader r(path);
  struct Frame {
    uint32_t number;
    uint64_t draws = 0, vertices = 0, triangles = 0, units = 0;
    CallCounts calls;
  };
  std::vector<Frame> frames;
  std::vector<std::string> textures;  // one line each; the texture table of a draw trace
  uint64_t texture_bytes = 0;
  for (DrawRecordKind k; (k = r.next()) != DrawRecordKind::End;) {
    if (k == DrawRecordKind::Texture) {
      const DrawTexture& t = r.texture();
      uint64_t bytes = 0;
      for (const auto& l : t.levels) bytes += l.size();
      texture_bytes += bytes;
      textures.push_back("  id " + std::to_string(t.id) + "  " + std::to_string(t.width) + "x" +
                         std::to_string(t.height) + "  " + std::to_string(t.levels.size()) +
                         " levels  " + std::to_string(bytes) + " bytes  " + t.name);
    } else if (k == DrawRecordKind::Frame) {
      frames.push_back(Frame{r.frame(), 0, 0, 0, 0, {}});
    } else if (k == DrawRecordKind::Draw) {
      Frame& f = frames.back();
      ++f.draws;
      f.vertices += r.draw().vertex_count;
      f.triangles += r.draw().indices.size() / 3;
      f.units += r.draw().units.size();
    } else {
      frames.back().calls = r.uninterpreted();
    }
  }
  out << "draw trace: " << path << "\n";
  out << "format:     draw trace, version " << kDrawVersion << "\n";
  out << "source:     " << r.source() << "\n";
  out << "frames:     " << frames.size() << "\n";
  for (const Frame& f : frames) {
    uint64_t calls = 0;
    for (const auto& [n, c] : f.calls) calls += c;
    out << "  frame " << f.number << ": " << f.draws << " draws, " << f.vertices << " vertices, "
        << f.triangles << " triangles, " << f.units << " texture bindings; " << calls
        << " calls not interpreted";
    const char* sep = ": ";
    for (const auto& [n, c] : f.calls) {
      out << sep << n << " " << c;
      sep = ", ";
    }
    out << "\n";
  }
  out << "textures:   " << textures.size() << " (" << texture_bytes << " bytes of texels)\n";
  for (const std::string& t : textures) out << t << "\n";
  return 0;
}

void write_draw_trace(const std::string& path, const DrawTrace& trace) {
  DrawTraceWriter w(path, trace.source);
  for (const DrawTexture& t : trace.textures) w.add_texture(t);
  for (const DrawFrame& f : trace.frames) {
    w.begin_frame(f.number);
    for (const Draw& d : f.draws) w.add_draw(d);
    w.end_frame(f.uninterpreted);
  }
  w.close();
}

DrawTrace read_draw_trace(const std::string& path) {
  DrawTraceReader r(path);
  DrawTrace t;
  t.source = r.source();
  for (;;) {
    switch (r.next()) {
      case DrawRecordKind::Texture:
        t.textures.push_back(r.texture());
        break;
      case DrawRecordKind::Frame:
        t.frames.push_back(DrawFrame{r.frame(), {}, {}});
        break;
      case DrawRecordKind::Draw:
        t.frames.back().draws.push_back(r.draw());
        break;
      case DrawRecordKind::FrameEnd:
        t.frames.back().uninterpreted = r.uninterpreted();
        break;
      case DrawRecordKind::End:
        return t;
    }
  }
}

}  // namespace texsim
