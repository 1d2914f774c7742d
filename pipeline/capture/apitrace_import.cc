#include "pipeline/capture/apitrace_import.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"

namespace texsim {

namespace {

constexpr uint32_t kUnknown = 0xFFFFFFFFu;  // state set to a value the format cannot hold
constexpr int kUnitsTracked = 8;            // GL_TEXTURE0..7; draws may use 0..1

// OpenGL enum names the importer reads, with their values.
const std::unordered_map<std::string_view, uint32_t>& gl_enums() {
  static const std::unordered_map<std::string_view, uint32_t> m = {
      {"GL_FALSE", 0},
      {"GL_TRUE", 1},
      {"GL_ZERO", 0},
      {"GL_ONE", 1},
      {"GL_POINTS", 0},
      {"GL_LINES", 1},
      {"GL_LINE_LOOP", 2},
      {"GL_LINE_STRIP", 3},
      {"GL_TRIANGLES", 4},
      {"GL_TRIANGLE_STRIP", 5},
      {"GL_TRIANGLE_FAN", 6},
      {"GL_QUADS", 7},
      {"GL_QUAD_STRIP", 8},
      {"GL_POLYGON", 9},
      {"GL_NEVER", 0x0200},
      {"GL_LESS", 0x0201},
      {"GL_EQUAL", 0x0202},
      {"GL_LEQUAL", 0x0203},
      {"GL_GREATER", 0x0204},
      {"GL_NOTEQUAL", 0x0205},
      {"GL_GEQUAL", 0x0206},
      {"GL_ALWAYS", 0x0207},
      {"GL_SRC_COLOR", 0x0300},
      {"GL_ONE_MINUS_SRC_COLOR", 0x0301},
      {"GL_SRC_ALPHA", 0x0302},
      {"GL_ONE_MINUS_SRC_ALPHA", 0x0303},
      {"GL_DST_ALPHA", 0x0304},
      {"GL_ONE_MINUS_DST_ALPHA", 0x0305},
      {"GL_DST_COLOR", 0x0306},
      {"GL_ONE_MINUS_DST_COLOR", 0x0307},
      {"GL_SRC_ALPHA_SATURATE", 0x0308},
      {"GL_FRONT", 0x0404},
      {"GL_BACK", 0x0405},
      {"GL_FRONT_AND_BACK", 0x0408},
      {"GL_CW", 0x0900},
      {"GL_CCW", 0x0901},
      {"GL_NEAREST", 0x2600},
      {"GL_LINEAR", 0x2601},
      {"GL_NEAREST_MIPMAP_NEAREST", 0x2700},
      {"GL_LINEAR_MIPMAP_NEAREST", 0x2701},
      {"GL_NEAREST_MIPMAP_LINEAR", 0x2702},
      {"GL_LINEAR_MIPMAP_LINEAR", 0x2703},
      {"GL_CLAMP", 0x2900},
      {"GL_REPEAT", 0x2901},
      {"GL_CLAMP_TO_EDGE", 0x812F},
      {"GL_CLAMP_TO_BORDER", 0x812D},
      {"GL_MIRRORED_REPEAT", 0x8370},
      {"GL_MODULATE", 0x2100},
      {"GL_DECAL", 0x2101},
      {"GL_BLEND", 0x0BE2},
      {"GL_REPLACE", 0x1E01},
      {"GL_ADD", 0x0104},
      {"GL_COMBINE", 0x8570},
      {"GL_BYTE", 0x1400},
      {"GL_UNSIGNED_BYTE", 0x1401},
      {"GL_SHORT", 0x1402},
      {"GL_UNSIGNED_SHORT", 0x1403},
      {"GL_INT", 0x1404},
      {"GL_UNSIGNED_INT", 0x1405},
      {"GL_FLOAT", 0x1406},
      {"GL_DOUBLE", 0x140A},
  };
  return m;
}

uint32_t type_bytes(uint32_t type) {
  switch (type) {
    case 0x1400:
    case 0x1401:
      return 1;
    case 0x1402:
    case 0x1403:
      return 2;
    case 0x1404:
    case 0x1405:
    case 0x1406:
      return 4;
    case 0x140A:
      return 8;
  }
  return 0;
}

using Mat = std::array<double, 16>;  // column-major, as glLoadMatrix takes it

Mat identity() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
Mat mul(const Mat& a, const Mat& b) {
  Mat r{};
  for (int c = 0; c < 4; ++c)
    for (int row = 0; row < 4; ++row) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + row] * b[c * 4 + k];
      r[c * 4 + row] = s;
    }
  return r;
}

struct Stack {
  std::vector<Mat> m{identity()};
  size_t max_depth;
};

// One GL texture object: its levels as uploaded (RGBA8) and its sampler parameters.
struct GlTexture {
  struct Level {
    uint32_t w = 0, h = 0;
    bool defined = false;
    std::vector<uint8_t> rgba;
  };
  std::vector<Level> levels;
  std::string bad;  // why its contents are not interpreted, "" when they are
  uint32_t min_filter = 0x2702, mag_filter = 0x2601, wrap_s = 0x2901, wrap_t = 0x2901;
  float aniso = 1, lod_bias = 0;
  int64_t trace_id = -1;  // id of the record of the current contents, -1 if none yet
  uint32_t upload = 0;
};

struct ClientArray {
  bool enabled = false;
  uint32_t size = 4, type = 0x1406, stride = 0;
  // In a buffer object: the buffer bound to GL_ARRAY_BUFFER when the pointer was set (0: an
  // offset with no buffer bound, which the capture cannot resolve) and the byte offset in it.
  bool buffer = false;
  uint32_t buffer_id = 0;
  uint64_t offset = 0;
  std::vector<uint8_t> data;  // client memory, as captured
};

// One GL buffer object: its contents as uploaded by glBufferData / glBufferSubData. Mapped
// (glMapBuffer*) its contents are written through memory the dump does not show: unknown.
struct GlBuffer {
  std::vector<uint8_t> data;
  bool unknown = false;
};

struct Unit {
  uint32_t bound = 0;
  bool tex2d = false;
  uint32_t env = 0x2100;
  float s = 0, t = 0;  // current texture coordinate
  Stack texture{{identity()}, 32};
  ClientArray coords;
};

// Splits the argument text of a call at its top-level commas.
std::vector<std::string_view> split_args(std::string_view s) {
  std::vector<std::string_view> out;
  int depth = 0;
  bool quote = false;
  size_t start = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        quote = false;
      continue;
    }
    if (c == '"')
      quote = true;
    else if (c == '(' || c == '{' || c == '[')
      ++depth;
    else if (c == ')' || c == '}' || c == ']')
      --depth;
    else if (c == ',' && depth == 0) {
      out.push_back(s.substr(start, i - start));
      start = i + 1;
    }
  }
  if (!s.empty()) out.push_back(s.substr(start));
  for (auto& a : out) {
    while (!a.empty() && a.front() == ' ') a.remove_prefix(1);
    while (!a.empty() && a.back() == ' ') a.remove_suffix(1);
  }
  return out;
}

// The triangle list of primitive `mode` over idx, in the application's winding; false for the
// modes it does not turn into triangles (points and lines).
bool triangle_list(uint32_t mode, const std::vector<uint32_t>& idx, std::vector<uint32_t>& tri) {
  const size_t n = idx.size();
  switch (mode) {
    case 4:
      for (size_t k = 0; k + 2 < n; k += 3) tri.insert(tri.end(), {idx[k], idx[k + 1], idx[k + 2]});
      break;
    case 5:
      for (size_t k = 0; k + 2 < n; ++k) {
        if (k % 2 == 0)
          tri.insert(tri.end(), {idx[k], idx[k + 1], idx[k + 2]});
        else
          tri.insert(tri.end(), {idx[k + 1], idx[k], idx[k + 2]});
      }
      break;
    case 6:
    case 9:
      for (size_t k = 1; k + 1 < n; ++k) tri.insert(tri.end(), {idx[0], idx[k], idx[k + 1]});
      break;
    case 7:
      for (size_t k = 0; k + 3 < n; k += 4)
        tri.insert(tri.end(), {idx[k], idx[k + 1], idx[k + 2], idx[k], idx[k + 2], idx[k + 3]});
      break;
    case 8:
      for (size_t k = 0; k + 3 < n; k += 2)
        tri.insert(tri.end(), {idx[k], idx[k + 1], idx[k + 3], idx[k], idx[k + 3], idx[k + 2]});
      break;
    default:
      return false;
  }
  return true;
}

// State the format cannot hold (an enum it does not know) leaves the draw out.
bool state_interpreted(const Draw& d) {
  const DrawState& s = d.state;
  bool unknown = s.depth_func == kUnknown || s.cull_face == kUnknown || s.front_face == kUnknown ||
                 s.alpha_func == kUnknown || s.blend_src == kUnknown || s.blend_dst == kUnknown ||
                 s.viewport_w == 0 || s.viewport_h == 0;
  for (const DrawUnit& u : d.units)
    unknown = unknown || u.min_filter == kUnknown || u.mag_filter == kUnknown ||
              u.wrap_s == kUnknown || u.wrap_t == kUnknown || u.env_mode == kUnknown ||
              u.env_mode == 0x8570;
  return !unknown;
}

// An array of a type this importer can read (float or double; bytes where allowed).
bool usable_array(const ClientArray& a, bool bytes_ok) {
  return a.size >= 1 && a.size <= 4 && a.stride < 65536 &&
         (a.type == 0x1406 || a.type == 0x140A || (bytes_ok && a.type == 0x1401));
}

class Interpreter {
 public:
  Interpreter(std::string name, std::string blob_dir, bool remove_blobs, uint32_t first,
              uint32_t last, DrawTraceWriter& w, ImportSummary& s)
      : name_(std::move(name)),
        blob_dir_(std::move(blob_dir)),
        remove_blobs_(remove_blobs),
        first_(first),
        last_(last),
        w_(w),
        s_(s) {
    for (Unit& u : units_) u.texture.max_depth = 32;
    if (first_ == 0) begin_frame();
  }

  // Interprets one line of the dump; false once frame `last` has ended.
  bool line(std::string_view text) {
    if (text.empty() || text.starts_with("//")) return true;
    size_t i = 0;
    while (i < text.size() && text[i] >= '0' && text[i] <= '9') ++i;
    if (i == 0 || i >= text.size() || text[i] != ' ' || i > 19)
      throw InputError(name_ + ": dump line \"" + std::string(text.substr(0, 60)) + "\"",
                       "not a call (expected \"NUMBER name(arguments)\")");
    call_no_ = std::strtoull(std::string(text.substr(0, i)).c_str(), nullptr, 10);
    const size_t open = text.find('(', i);
    if (open == std::string_view::npos)
      throw InputError(where(), "no argument list in \"" + std::string(text.substr(0, 80)) + "\"");
    call_ = std::string(text.substr(i + 1, open - i - 1));
    int depth = 0;
    bool quote = false;
    size_t close = std::string_view::npos;
    for (size_t k = open; k < text.size(); ++k) {
      const char c = text[k];
      if (quote) {
        if (c == '\\')
          ++k;
        else if (c == '"')
          quote = false;
      } else if (c == '"') {
        quote = true;
      } else if (c == '(' || c == '{' || c == '[') {
        ++depth;
      } else if (c == ')' || c == '}' || c == ']') {
        if (--depth == 0) {
          close = k;
          break;
        }
      }
    }
    if (close == std::string_view::npos) throw InputError(where(), "unbalanced argument list");
    args_ = split_args(text.substr(open + 1, close - open - 1));
    ++s_.calls;
    const bool go_on = dispatch();
    if (remove_blobs_) {
      std::error_code ec;
      std::filesystem::remove(blob_dir_ + "/blob_call" + std::to_string(call_no_) + ".bin", ec);
    }
    return go_on;
  }

  void finish() {
    if (s_.calls == 0)
      throw InputError(name_, "the dump holds no calls (not an apitrace capture, or empty)");
    if (frame_ <= last_)
      throw InputError(name_, "the capture ends in frame " + std::to_string(frame_) +
                                  ": it has no frames " + std::to_string(std::max(frame_, first_)) +
                                  "-" + std::to_string(last_) + " (frames are counted from 0)");
  }

 private:
  std::string where() const {
    return name_ + ": call " + std::to_string(call_no_) + " (" + call_ + "), frame " +
           std::to_string(frame_);
  }
  bool in_range() const { return frame_ >= first_ && frame_ <= last_; }
  void count(const std::string& what) {
    if (in_range()) ++s_.frames[frame_].uninterpreted[what];
  }
  void need_args(size_t n) {
    if (args_.size() != n)
      throw InputError(where(),
                       std::to_string(args_.size()) + " arguments, expected " + std::to_string(n));
  }
  double num(size_t i) {
    const std::string a(args_.at(i));
    if (a == "GL_TRUE") return 1;
    if (a == "GL_FALSE") return 0;
    char* end = nullptr;
    const double v = std::strtod(a.c_str(), &end);
    if (a.empty() || *end != '\0')
      throw InputError(where(), "argument " + std::to_string(i) + " '" + a + "' is not a number");
    if (!std::isfinite(v))
      throw InputError(where(), "argument " + std::to_string(i) + " '" + a + "' is not finite");
    return v;
  }
  // A whole-number argument in [lo, hi], or an error (never an out-of-range conversion).
  int64_t whole(size_t i, int64_t lo, int64_t hi) {
    const double v = num(i);
    if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)) || v != std::floor(v))
      throw InputError(where(), "argument " + std::to_string(i) + " '" + std::string(args_[i]) +
                                    "' is not a whole number in " + std::to_string(lo) + ".." +
                                    std::to_string(hi));
    return static_cast<int64_t>(v);
  }
  uint32_t u32(size_t i, uint32_t hi) { return static_cast<uint32_t>(whole(i, 0, hi)); }
  float f32(size_t i) { return to_f32(num(i), "argument " + std::to_string(i)); }
  float to_f32(double v, const std::string& what) {
    if (!(std::fabs(v) <= std::numeric_limits<float>::max()))
      throw InputError(where(), what + " is not a finite single-precision value");
    return static_cast<float>(v);
  }
  // GL_TEXTURE0..7 -> 0..7, else -1.
  static int unit_of(std::string_view a) {
    if (a.size() != 11 || !a.starts_with("GL_TEXTURE") || a[10] < '0' || a[10] > '7') return -1;
    return a[10] - '0';
  }
  // The value of an enum argument, or kUnknown for a name the importer does not know.
  uint32_t gl_enum(size_t i) {
    const std::string_view a = args_.at(i);
    const auto& m = gl_enums();
    if (const auto it = m.find(a); it != m.end()) return it->second;
    if (!a.empty() && a[0] >= '0' && a[0] <= '9') return u32(i, 0xFFFFFFFEu);
    return kUnknown;
  }
  std::vector<double> numbers(size_t i) {
    std::string_view a = args_.at(i);
    if (a.size() < 2 || a.front() != '{' || a.back() != '}')
      throw InputError(where(), "argument " + std::to_string(i) + " is not an array {…}");
    std::vector<double> out;
    for (std::string_view v : split_args(a.substr(1, a.size() - 2))) {
      char* end = nullptr;
      const std::string t(v);
      out.push_back(std::strtod(t.c_str(), &end));
      if (t.empty() || *end != '\0')
        throw InputError(where(), "array value '" + t + "' is not a number");
    }
    return out;
  }
  // The object names of argument i, a glDelete* list as the dump prints it: "&5" or "{3, 4}".
  std::vector<uint32_t> names(size_t i) {
    std::string_view a = args_.at(i);
    if (a.starts_with("&")) a.remove_prefix(1);
    std::string list(a);
    if (list.starts_with("{") && list.size() >= 2) list = list.substr(1, list.size() - 2);
    std::vector<uint32_t> out;
    for (std::string_view v : split_args(list))
      out.push_back(static_cast<uint32_t>(std::strtoul(std::string(v).c_str(), nullptr, 10)));
    return out;
  }
  // The blob of argument i: its bytes; nullopt for NULL or a buffer offset (a number).
  std::optional<std::vector<uint8_t>> blob(size_t i, bool* is_offset = nullptr) {
    const std::string_view a = args_.at(i);
    if (is_offset) *is_offset = false;
    if (a == "NULL" || a == "0") return std::nullopt;
    if (!a.starts_with("blob(")) {
      if (!a.empty() && a[0] >= '0' && a[0] <= '9') {
        if (is_offset) *is_offset = true;
        return std::nullopt;
      }
      throw InputError(where(), "argument " + std::to_string(i) + " '" +
                                    std::string(a.substr(0, 40)) + "' is not a blob");
    }
    if (!a.starts_with("blob(\""))
      throw InputError(where(), "blob without its data: the dump must be made with --blobs");
    const std::string file(a.substr(6, a.size() - 8));
    const std::string want = "blob_call" + std::to_string(call_no_) + ".bin";
    if (file != want || !a.ends_with("\")"))
      throw InputError(where(), "blob file '" + file + "' is not the call's (" + want + ")");
    // Read directly, not through open_input_file: these scratch files are removed at once and
    // must not enter the registry of the run's inputs.
    const std::string path = blob_dir_ + "/" + file;
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(where(), "cannot open blob " + path + ": " + std::strerror(errno));
    std::vector<uint8_t> data;
    uint8_t buf[65536];
    size_t n;
    while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
      if (data.size() + n > kImportMaxBlobBytes) {
        std::fclose(f);
        throw InputError(where(),
                         "blob larger than " + std::to_string(kImportMaxBlobBytes) + " bytes");
      }
      data.insert(data.end(), buf, buf + n);
    }
    std::fclose(f);
    return data;
  }

  Stack& stack() {
    if (matrix_mode_ == 0x1701) return projection_;
    if (matrix_mode_ == 0x1702) return units_[active_].texture;
    return modelview_;
  }
  void apply(const Mat& m) { stack().m.back() = mul(stack().m.back(), m); }

  void begin_frame() {
    if (!in_range()) return;
    w_.begin_frame(frame_);
    s_.frames[frame_].frame = frame_;
  }

  bool dispatch();
  bool texture_object_call(const std::string& c);
  bool texture_unit_call(const std::string& c);
  bool matrix_call(const std::string& c);
  bool client_array_call(const std::string& c);
  bool buffer_call(const std::string& c);
  uint32_t& buffer_binding(std::string_view target);
  GlBuffer& bound_buffer(uint32_t id);
  // The bytes an array reads (client memory, or its buffer's contents) and where it starts in
  // them; null when a buffer's contents are unknown or the buffer is gone.
  const std::vector<uint8_t>* array_bytes(const ClientArray& a, uint64_t& base) const;
  bool element_indices(const std::string& c, size_t n, uint32_t tb, size_t arg,
                       std::vector<uint32_t>& idx);
  bool state_call(const std::string& c);
  bool draw_call(const std::string& c);
  void tex_image();
  void tex_parameter();
  void set_pointer(ClientArray& a, size_t size_arg);
  ClientArray* client_array(std::string_view which);
  void draw(uint32_t mode, const std::vector<uint32_t>& idx);
  bool write_units(const std::string& c, Draw& d);
  bool arrays_usable(const std::string& c, const Draw& d);
  double fetch(const ClientArray& a, const char* what, uint32_t v, uint32_t k);
  bool gather_vertices(const std::string& c, uint32_t lo, uint32_t nv, Draw& d);
  void transform_vertex(const Mat& mvp, uint32_t src, float* out);
  void vertex_colour(uint32_t src, uint8_t* out);
  bool set_cap(std::string_view cap, bool on);
  std::optional<uint32_t> write_texture(GlTexture& t, uint32_t gl_name, std::string& why);

  std::string name_, blob_dir_;
  bool remove_blobs_;
  uint32_t first_, last_;
  DrawTraceWriter& w_;
  ImportSummary& s_;
  uint64_t call_no_ = 0;
  std::string call_;
  std::vector<std::string_view> args_;
  uint32_t frame_ = 0;

  std::unordered_map<uint32_t, GlTexture> textures_{{0, GlTexture{}}};
  std::unordered_map<uint32_t, GlBuffer> buffers_;
  uint64_t buffer_bytes_ = 0;
  uint32_t array_buffer_ = 0, element_buffer_ = 0;  // GL_ARRAY_BUFFER, GL_ELEMENT_ARRAY_BUFFER
  uint64_t texture_bytes_ = 0;
  uint32_t next_trace_id_ = 0;
  std::array<Unit, kUnitsTracked> units_;
  uint32_t active_ = 0, client_active_ = 0;
  uint32_t matrix_mode_ = 0x1700;
  Stack modelview_{{identity()}, 32}, projection_{{identity()}, 4};
  ClientArray vertex_, color_;
  DrawState st_;
  std::array<uint8_t, 4> color_now_{255, 255, 255, 255};
  uint32_t unpack_alignment_ = 4;
  bool viewport_set_ = false;
};

bool Interpreter::set_cap(std::string_view cap, bool on) {
  if (cap == "GL_TEXTURE_2D")
    units_[active_].tex2d = on;
  else if (cap == "GL_DEPTH_TEST")
    st_.depth_test = on;
  else if (cap == "GL_CULL_FACE")
    st_.cull = on;
  else if (cap == "GL_POLYGON_OFFSET_FILL")
    st_.polygon_offset = on;
  else if (cap == "GL_ALPHA_TEST")
    st_.alpha_test = on;
  else if (cap == "GL_BLEND")
    st_.blend = on;
  else
    return false;
  return true;
}

ClientArray* Interpreter::client_array(std::string_view which) {
  if (which == "GL_VERTEX_ARRAY") return &vertex_;
  if (which == "GL_COLOR_ARRAY") return &color_;
  if (which == "GL_TEXTURE_COORD_ARRAY") return &units_[client_active_].coords;
  return nullptr;
}

void Interpreter::set_pointer(ClientArray& a, size_t n) {
  need_args(n);
  a.size = u32(0, 4);
  a.type = gl_enum(1);
  a.stride = u32(2, 65535);
  a.data.clear();
  a.buffer_id = 0;
  a.offset = 0;
  if (array_buffer_ != 0) {  // the pointer is an offset into the bound buffer
    a.buffer = true;
    a.buffer_id = array_buffer_;
    if (args_[3] != "NULL") a.offset = static_cast<uint64_t>(whole(3, 0, int64_t{1} << 40));
    return;
  }
  bool offset = false;
  auto data = blob(3, &offset);
  a.buffer = offset;
  if (data) a.data = std::move(*data);
}

uint32_t& Interpreter::buffer_binding(std::string_view target) {
  return target == "GL_ELEMENT_ARRAY_BUFFER" ? element_buffer_ : array_buffer_;
}

GlBuffer& Interpreter::bound_buffer(uint32_t id) {
  if (id == 0) throw InputError(where(), "no buffer object is bound to the target");
  return buffers_[id];
}

const std::vector<uint8_t>* Interpreter::array_bytes(const ClientArray& a, uint64_t& base) const {
  base = 0;
  if (!a.buffer) return &a.data;
  const auto it = buffers_.find(a.buffer_id);
  if (a.buffer_id == 0 || it == buffers_.end() || it->second.unknown) return nullptr;
  base = a.offset;
  return &it->second.data;
}

// Buffer objects: names, bindings, contents (glBufferData, glBufferSubData), mapping (contents
// then unknown). False when the call is not one of them.
bool Interpreter::buffer_call(const std::string& c) {
  std::string n = c;
  if (n.ends_with("ARB")) n.resize(n.size() - 3);
  if (n == "glGenBuffers") return true;
  const auto known_target = [&](size_t i) {
    if (args_[i] == "GL_ARRAY_BUFFER" || args_[i] == "GL_ELEMENT_ARRAY_BUFFER") return true;
    count(c + "(" + std::string(args_[i]) + ")");
    return false;
  };
  if (n == "glBindBuffer") {
    need_args(2);
    if (!known_target(0)) return true;
    const uint32_t id = u32(1, 0xFFFFFFFFu);
    if (id != 0 && !buffers_.contains(id) && buffers_.size() >= kImportMaxTextureNames)
      throw InputError(
          where(), "more than " + std::to_string(kImportMaxTextureNames) + " buffer objects alive");
    if (id != 0) buffers_.try_emplace(id);
    buffer_binding(args_[0]) = id;
  } else if (n == "glBufferData") {
    need_args(4);
    if (!known_target(0)) return true;
    GlBuffer& b = bound_buffer(buffer_binding(args_[0]));
    const auto size = static_cast<size_t>(whole(1, 0, static_cast<int64_t>(kImportMaxBlobBytes)));
    std::optional<std::vector<uint8_t>> data = blob(2);
    if (data && data->size() < size)
      throw InputError(where(), "data blob of " + std::to_string(data->size()) + " bytes for a " +
                                    std::to_string(size) + "-byte buffer");
    buffer_bytes_ = buffer_bytes_ - b.data.size() + size;
    if (buffer_bytes_ > kImportMaxTextureBytes)
      throw InputError(where(), "buffer objects hold more than " +
                                    std::to_string(kImportMaxTextureBytes) + " bytes");
    b.data.assign(size, 0);
    if (data) std::copy_n(data->begin(), size, b.data.begin());
    b.unknown = false;
  } else if (n == "glBufferSubData") {
    need_args(4);
    if (!known_target(0)) return true;
    GlBuffer& b = bound_buffer(buffer_binding(args_[0]));
    const auto off = static_cast<uint64_t>(whole(1, 0, int64_t{1} << 40));
    const auto size = static_cast<uint64_t>(whole(2, 0, int64_t{1} << 40));
    std::optional<std::vector<uint8_t>> data = blob(3);
    if (off + size > b.data.size() || !data || data->size() < size)
      throw InputError(where(), "bytes " + std::to_string(off) + ".." + std::to_string(off + size) +
                                    " are not inside the " + std::to_string(b.data.size()) +
                                    "-byte buffer, or the blob is short");
    std::copy_n(data->begin(), size, b.data.begin() + static_cast<std::ptrdiff_t>(off));
  } else if (n == "glMapBuffer" || n == "glMapBufferRange") {
    if (args_.empty()) throw InputError(where(), "no arguments");
    if (known_target(0)) bound_buffer(buffer_binding(args_[0])).unknown = true;
    count(c);
  } else if (n == "glUnmapBuffer") {
    return true;
  } else if (n == "glDeleteBuffers") {
    need_args(2);
    for (const uint32_t id : names(1)) {
      if (auto it = buffers_.find(id); it != buffers_.end()) {
        buffer_bytes_ -= it->second.data.size();
        buffers_.erase(it);
      }
      if (array_buffer_ == id) array_buffer_ = 0;
      if (element_buffer_ == id) element_buffer_ = 0;
    }
  } else {
    return false;
  }
  return true;
}

bool Interpreter::dispatch() {
  const std::string& c = call_;
  if (c == "glXSwapBuffers" || c == "eglSwapBuffers" || c == "wglSwapBuffers") {
    if (in_range()) w_.end_frame(s_.frames[frame_].uninterpreted);
    ++frame_;
    if (frame_ > last_) return false;
    begin_frame();
    return true;
  }
  static const char* const kNoEffect[] = {"glGetIntegerv",
                                          "glGetFloatv",
                                          "glGetBooleanv",
                                          "glGetString",
                                          "glGetStringi",
                                          "glGetError",
                                          "glIsEnabled",
                                          "glFinish",
                                          "glFlush",
                                          "glGenTextures",
                                          "glLockArraysEXT",
                                          "glUnlockArraysEXT",
                                          "glXChooseVisual",
                                          "glXChooseFBConfig",
                                          "glXGetVisualFromFBConfig",
                                          "glXCreateContext",
                                          "glXCreateNewContext",
                                          "glXDestroyContext",
                                          "glXMakeCurrent",
                                          "glXMakeContextCurrent",
                                          "glXQueryExtensionsString",
                                          "glXGetProcAddress",
                                          "glXGetProcAddressARB",
                                          "glGetFramebufferAttachmentParameteriv",
                                          "glGetTexLevelParameteriv"};
  for (const char* n : kNoEffect)
    if (c == n) return true;
  if (texture_object_call(c) || texture_unit_call(c) || matrix_call(c) || client_array_call(c) ||
      buffer_call(c) || state_call(c) || draw_call(c))
    return true;
  count(c);
  return true;
}

// Texture names, uploads, parameters and unpacking. False when the call is not one of them.
bool Interpreter::texture_object_call(const std::string& c) {
  if (c == "glBindTexture") {
    need_args(2);
    if (args_[0] != "GL_TEXTURE_2D") return count(c + "(" + std::string(args_[0]) + ")"), true;
    const auto t = u32(1, 0xFFFFFFFFu);
    if (!textures_.contains(t)) {
      if (textures_.size() >= kImportMaxTextureNames)
        throw InputError(where(),
                         "more than " + std::to_string(kImportMaxTextureNames) + " textures alive");
      textures_[t] = GlTexture{};
    }
    units_[active_].bound = t;
  } else if (c == "glDeleteTextures") {
    need_args(2);
    for (const uint32_t t : names(1)) {
      if (t == 0) continue;
      if (auto it = textures_.find(t); it != textures_.end()) {
        for (auto& l : it->second.levels) texture_bytes_ -= l.rgba.size();
        textures_.erase(it);
      }
      for (Unit& u : units_)
        if (u.bound == t) u.bound = 0;
    }
  } else if (c == "glTexImage2D") {
    tex_image();
  } else if (c == "glTexParameterf" || c == "glTexParameteri") {
    tex_parameter();
  } else if (c == "glPixelStorei") {
    need_args(2);
    const double v = num(1);
    if (args_[0] == "GL_UNPACK_ALIGNMENT" && (v == 1 || v == 2 || v == 4 || v == 8))
      unpack_alignment_ = static_cast<uint32_t>(v);
    else
      count(c + "(" + std::string(args_[0]) + ")");
  } else {
    return false;
  }
  return true;
}

// The active units, their environment and current coordinates. False when the call is not one of
// them.
bool Interpreter::texture_unit_call(const std::string& c) {
  if (c == "glActiveTexture" || c == "glActiveTextureARB" || c == "glClientActiveTexture" ||
      c == "glClientActiveTextureARB") {
    need_args(1);
    const std::string_view a = args_[0];
    const int u = unit_of(a);
    if (u < 0)
      throw InputError(where(), "texture unit '" + std::string(a) + "' is not GL_TEXTURE0..7");
    (c.find("Client") != std::string::npos ? client_active_ : active_) = static_cast<uint32_t>(u);
  } else if (c == "glTexEnvf" || c == "glTexEnvi") {
    need_args(3);
    if (args_[0] == "GL_TEXTURE_ENV" && args_[1] == "GL_TEXTURE_ENV_MODE") {
      units_[active_].env = gl_enum(2);
      if (units_[active_].env == kUnknown || units_[active_].env == 0x8570)
        count(c + "(" + std::string(args_[2]) + ")");
    } else {
      count(c + "(" + std::string(args_[1]) + ")");
    }
  } else if (c == "glTexCoord2f") {
    need_args(2);
    units_[0].s = f32(0);
    units_[0].t = f32(1);
    count(c);  // immediate mode: the current value is kept, the vertex it feeds is not
  } else if (c == "glMultiTexCoord2f" || c == "glMultiTexCoord2fARB") {
    need_args(3);
    const std::string_view a = args_[0];
    const int u = unit_of(a);
    if (u < 0) throw InputError(where(), "bad texture unit " + std::string(a));
    units_[u].s = f32(1);
    units_[u].t = f32(2);
  } else {
    return false;
  }
  return true;
}

// The matrix stacks. False when the call is not one of them.
bool Interpreter::matrix_call(const std::string& c) {
  if (c == "glMatrixMode") {
    need_args(1);
    if (args_[0] == "GL_MODELVIEW")
      matrix_mode_ = 0x1700;
    else if (args_[0] == "GL_PROJECTION")
      matrix_mode_ = 0x1701;
    else if (args_[0] == "GL_TEXTURE")
      matrix_mode_ = 0x1702;
    else
      throw InputError(where(), "unknown matrix mode " + std::string(args_[0]));
  } else if (c == "glLoadIdentity") {
    stack().m.back() = identity();
  } else if (c == "glLoadMatrixf" || c == "glLoadMatrixd" || c == "glMultMatrixf" ||
             c == "glMultMatrixd") {
    need_args(1);
    const std::vector<double> v = numbers(0);
    if (v.size() != 16)
      throw InputError(where(), "matrix of " + std::to_string(v.size()) + " values, expected 16");
    Mat m;
    std::copy(v.begin(), v.end(), m.begin());
    if (c.starts_with("glLoad"))
      stack().m.back() = m;
    else
      apply(m);
  } else if (c == "glOrtho" || c == "glFrustum") {
    need_args(6);
    const double l = num(0), r = num(1), b = num(2), t = num(3), n = num(4), f = num(5);
    if (l == r || b == t || n == f || (c == "glFrustum" && (n <= 0 || f <= 0)))
      throw InputError(where(), "degenerate volume");
    Mat m{};
    if (c == "glOrtho") {
      m = identity();
      m[0] = 2 / (r - l);
      m[5] = 2 / (t - b);
      m[10] = -2 / (f - n);
      m[12] = -(r + l) / (r - l);
      m[13] = -(t + b) / (t - b);
      m[14] = -(f + n) / (f - n);
    } else {
      m[0] = 2 * n / (r - l);
      m[5] = 2 * n / (t - b);
      m[8] = (r + l) / (r - l);
      m[9] = (t + b) / (t - b);
      m[10] = -(f + n) / (f - n);
      m[11] = -1;
      m[14] = -2 * f * n / (f - n);
    }
    apply(m);
  } else if (c == "glTranslatef" || c == "glTranslated" || c == "glScalef" || c == "glScaled") {
    need_args(3);
    Mat m = identity();
    if (c.starts_with("glTranslate")) {
      m[12] = num(0), m[13] = num(1), m[14] = num(2);
    } else {
      m[0] = num(0), m[5] = num(1), m[10] = num(2);
    }
    apply(m);
  } else if (c == "glRotatef" || c == "glRotated") {
    need_args(4);
    const double a = num(0) * M_PI / 180;
    double x = num(1), y = num(2), z = num(3);
    const double len = std::sqrt(x * x + y * y + z * z);
    if (len == 0) throw InputError(where(), "rotation about the zero vector");
    x /= len, y /= len, z /= len;
    const double co = std::cos(a), si = std::sin(a), k = 1 - co;
    Mat m = identity();
    m[0] = x * x * k + co, m[4] = x * y * k - z * si, m[8] = x * z * k + y * si;
    m[1] = y * x * k + z * si, m[5] = y * y * k + co, m[9] = y * z * k - x * si;
    m[2] = x * z * k - y * si, m[6] = y * z * k + x * si, m[10] = z * z * k + co;
    apply(m);
  } else if (c == "glPushMatrix") {
    Stack& s = stack();
    if (s.m.size() >= s.max_depth) throw InputError(where(), "matrix stack overflow");
    s.m.push_back(s.m.back());
  } else if (c == "glPopMatrix") {
    Stack& s = stack();
    if (s.m.size() <= 1) throw InputError(where(), "matrix stack underflow");
    s.m.pop_back();
  } else {
    return false;
  }
  return true;
}

// The client-side vertex, colour and texture coordinate arrays. False when the call is not one of
// them.
bool Interpreter::client_array_call(const std::string& c) {
  if (c == "glVertexPointer") {
    set_pointer(vertex_, 4);
  } else if (c == "glColorPointer") {
    set_pointer(color_, 4);
  } else if (c == "glTexCoordPointer") {
    set_pointer(units_[client_active_].coords, 4);
  } else if (c == "glEnableClientState" || c == "glDisableClientState") {
    need_args(1);
    if (ClientArray* a = client_array(args_[0]))
      a->enabled = c == "glEnableClientState";
    else
      count(c + "(" + std::string(args_[0]) + ")");
  } else {
    return false;
  }
  return true;
}

// Fixed-function state: capabilities, depth, culling, offset, alpha, blend, viewport, colour. False
// when the call is not one of them.
bool Interpreter::state_call(const std::string& c) {
  if (c == "glEnable" || c == "glDisable") {
    need_args(1);
    if (!set_cap(args_[0], c == "glEnable")) count(c + "(" + std::string(args_[0]) + ")");
  } else if (c == "glDepthFunc") {
    need_args(1);
    st_.depth_func = gl_enum(0);
  } else if (c == "glDepthMask") {
    need_args(1);
    st_.depth_write = num(0) != 0;
  } else if (c == "glDepthRange" || c == "glDepthRangef") {
    need_args(2);
    st_.depth_near = f32(0);
    st_.depth_far = f32(1);
  } else if (c == "glCullFace") {
    need_args(1);
    st_.cull_face = gl_enum(0);
  } else if (c == "glFrontFace") {
    need_args(1);
    st_.front_face = gl_enum(0);
  } else if (c == "glPolygonOffset") {
    need_args(2);
    st_.offset_factor = f32(0);
    st_.offset_units = f32(1);
  } else if (c == "glAlphaFunc") {
    need_args(2);
    st_.alpha_func = gl_enum(0);
    st_.alpha_ref = std::clamp(f32(1), 0.0f, 1.0f);
  } else if (c == "glBlendFunc") {
    need_args(2);
    st_.blend_src = gl_enum(0);
    st_.blend_dst = gl_enum(1);
  } else if (c == "glViewport") {
    need_args(4);
    st_.viewport_x = static_cast<int32_t>(whole(0, INT32_MIN, INT32_MAX));
    st_.viewport_y = static_cast<int32_t>(whole(1, INT32_MIN, INT32_MAX));
    const double vw = num(2), vh = num(3);
    st_.viewport_w = vw >= 1 && vw <= 16384 ? static_cast<uint32_t>(vw) : 0;
    st_.viewport_h = vh >= 1 && vh <= 16384 ? static_cast<uint32_t>(vh) : 0;
    viewport_set_ = true;
  } else if (c == "glColor4f" || c == "glColor3f" || c == "glColor4ub" || c == "glColor3ub") {
    const bool ub = c.ends_with("ub");
    need_args(c[7] == '4' ? 4 : 3);
    for (size_t k = 0; k < 4; ++k) {
      const double v = k < args_.size() ? num(k) : (ub ? 255 : 1);
      color_now_[k] = static_cast<uint8_t>(ub ? std::lround(std::clamp(v, 0.0, 255.0))
                                              : std::lround(std::clamp(v, 0.0, 1.0) * 255));
    }
  } else {
    return false;
  }
  return true;
}

// Draw calls: their indices, then draw(). False when the call is not one of them.
bool Interpreter::draw_call(const std::string& c) {
  if (c == "glDrawElements" || c == "glDrawRangeElements") {
    const bool range = c == "glDrawRangeElements";
    need_args(range ? 6 : 4);
    const size_t base = range ? 2 : 0;
    const uint32_t mode = gl_enum(0);
    const double n = num(base + 1);
    const uint32_t type = gl_enum(base + 2);
    const uint32_t tb = type_bytes(type);
    if (!(n >= 0 && n <= kDrawMaxIndices)) throw InputError(where(), "index count out of range");
    if (tb == 0 || type == 0x1406 || type == 0x140A || type == 0x1400 || type == 0x1402 ||
        type == 0x1404)
      throw InputError(where(), "index type " + std::string(args_[base + 2]) +
                                    " is not an unsigned integer type");
    std::vector<uint32_t> idx;
    if (element_indices(c, static_cast<size_t>(n), tb, base + 3, idx)) draw(mode, idx);
  } else if (c == "glDrawArrays") {
    need_args(3);
    const double f = num(1), n = num(2);
    if (!(f >= 0 && n >= 0 && n <= kDrawMaxIndices && f + n <= 4294967295.0))
      throw InputError(where(), "first or count out of range");
    std::vector<uint32_t> idx(static_cast<size_t>(n));
    for (size_t k = 0; k < idx.size(); ++k)
      idx[k] = static_cast<uint32_t>(f) + static_cast<uint32_t>(k);
    draw(gl_enum(0), idx);
  } else {
    return false;
  }
  return true;
}
// The n indices of tb bytes each of a glDrawElements: from the blob of argument `arg`, or with a
// buffer bound to GL_ELEMENT_ARRAY_BUFFER at the offset it gives; false (and counted) when they
// cannot be read.
bool Interpreter::element_indices(const std::string& c, size_t n, uint32_t tb, size_t arg,
                                  std::vector<uint32_t>& idx) {
  std::optional<std::vector<uint8_t>> blob_data;
  const std::vector<uint8_t>* bytes = nullptr;
  uint64_t base = 0;
  if (element_buffer_ != 0) {
    const GlBuffer& b = buffers_[element_buffer_];
    if (b.unknown) return count(c + "[index buffer contents unknown]"), false;
    if (args_[arg] != "NULL") base = static_cast<uint64_t>(whole(arg, 0, int64_t{1} << 40));
    bytes = &b.data;
  } else {
    bool offset = false;
    blob_data = blob(arg, &offset);
    if (!blob_data) return count(c + (offset ? "[buffer object]" : "[no indices]")), false;
    bytes = &*blob_data;
  }
  if (bytes->size() < base || bytes->size() - base < n * tb)
    throw InputError(
        where(), "indices of " +
                     std::to_string(bytes->size() - std::min<uint64_t>(base, bytes->size())) +
                     " bytes, " + std::to_string(n) + " indices need " + std::to_string(n * tb));
  idx.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const uint8_t* p = bytes->data() + base + k * tb;
    idx[k] = tb == 1   ? p[0]
             : tb == 2 ? uint32_t(p[0] | p[1] << 8)
                       : uint32_t(p[0] | p[1] << 8 | p[2] << 16 | uint32_t(p[3]) << 24);
  }
  return true;
}

void Interpreter::tex_parameter() {
  need_args(3);
  if (args_[0] != "GL_TEXTURE_2D") return count(call_ + "(" + std::string(args_[0]) + ")");
  GlTexture& t = textures_[units_[active_].bound];
  const std::string_view p = args_[1];
  if (p == "GL_TEXTURE_MIN_FILTER")
    t.min_filter = gl_enum(2);
  else if (p == "GL_TEXTURE_MAG_FILTER")
    t.mag_filter = gl_enum(2);
  else if (p == "GL_TEXTURE_WRAP_S")
    t.wrap_s = gl_enum(2);
  else if (p == "GL_TEXTURE_WRAP_T")
    t.wrap_t = gl_enum(2);
  else if (p == "GL_TEXTURE_MAX_ANISOTROPY_EXT" || p == "GL_TEXTURE_MAX_ANISOTROPY")
    t.aniso = std::clamp(f32(2), 1.0f, 16.0f);
  else if (p == "GL_TEXTURE_LOD_BIAS")
    t.lod_bias = f32(2);
  else
    count(call_ + "(" + std::string(p) + ")");
}

void Interpreter::tex_image() {
  need_args(9);
  if (args_[0] != "GL_TEXTURE_2D") return count(call_ + "(" + std::string(args_[0]) + ")");
  const double level = num(1), w = num(3), h = num(4), border = num(5);
  const uint32_t bound = units_[active_].bound;
  GlTexture& t = textures_[bound];
  t.trace_id = -1;
  if (num(1) == 0) ++t.upload;  // counts the uploads of the base level
  if (!(level >= 0 && level < kDrawMaxLevels)) {
    t.bad = "level out of range";
    return count(call_ + "[level]");
  }
  const auto l = static_cast<size_t>(level);
  if (t.levels.size() <= l) t.levels.resize(l + 1);
  GlTexture::Level& lv = t.levels[l];
  texture_bytes_ -= lv.rgba.size();
  lv = GlTexture::Level{};
  if (!(w >= 1 && h >= 1 && w <= kDrawMaxTextureSize && h <= kDrawMaxTextureSize) || border != 0) {
    t.bad = "size or border";
    return count(call_ + "[size or border]");
  }
  lv.w = static_cast<uint32_t>(w);
  lv.h = static_cast<uint32_t>(h);
  const std::string_view fmt = args_[6];
  uint32_t comps = 0;
  if (fmt == "GL_RGBA")
    comps = 4;
  else if (fmt == "GL_RGB")
    comps = 3;
  else if (fmt == "GL_LUMINANCE_ALPHA")
    comps = 2;
  else if (fmt == "GL_LUMINANCE" || fmt == "GL_ALPHA")
    comps = 1;
  if (comps == 0 || args_[7] != "GL_UNSIGNED_BYTE") {
    t.bad = "format " + std::string(fmt) + "/" + std::string(args_[7]);
    return count(call_ + "(" + std::string(fmt) + ", " + std::string(args_[7]) + ")");
  }
  bool offset = false;
  auto data = blob(8, &offset);
  if (offset) {
    t.bad = "pixel buffer object";
    return count(call_ + "[pixel buffer object]");
  }
  if (!data) return;  // storage without contents: the level stays undefined
  const uint64_t row =
      (uint64_t{lv.w} * comps + unpack_alignment_ - 1) / unpack_alignment_ * unpack_alignment_;
  const uint64_t need = row * (lv.h - 1) + uint64_t{lv.w} * comps;
  if (data->size() < need)
    throw InputError(where(), "pixel blob of " + std::to_string(data->size()) + " bytes, a " +
                                  std::to_string(lv.w) + "x" + std::to_string(lv.h) + " " +
                                  std::string(fmt) + " image needs " + std::to_string(need));
  if (texture_bytes_ + uint64_t{lv.w} * lv.h * 4 > kImportMaxTextureBytes)
    throw InputError(
        where(), "the textures alive exceed " + std::to_string(kImportMaxTextureBytes) + " bytes");
  lv.rgba.resize(size_t{lv.w} * lv.h * 4);
  for (uint32_t y = 0; y < lv.h; ++y) {
    const uint8_t* src = data->data() + y * row;
    uint8_t* dst = lv.rgba.data() + size_t{y} * lv.w * 4;
    for (uint32_t x = 0; x < lv.w; ++x, src += comps, dst += 4) {
      if (comps == 4)
        std::memcpy(dst, src, 4);
      else if (comps == 3)
        dst[0] = src[0], dst[1] = src[1], dst[2] = src[2], dst[3] = 255;
      else if (comps == 2)
        dst[0] = dst[1] = dst[2] = src[0], dst[3] = src[1];
      else if (fmt == "GL_ALPHA")
        dst[0] = dst[1] = dst[2] = 0, dst[3] = src[0];
      else
        dst[0] = dst[1] = dst[2] = src[0], dst[3] = 255;
    }
  }
  texture_bytes_ += lv.rgba.size();
  lv.defined = true;
  if (l == 0) t.bad.clear();
}

// The trace id of texture `t`'s current contents, writing its record first if needed; nullopt
// with `why` when it cannot be written faithfully.
std::optional<uint32_t> Interpreter::write_texture(GlTexture& t, uint32_t gl_name,
                                                   std::string& why) {
  if (!t.bad.empty()) return why = "texture not interpreted", std::nullopt;
  if (t.levels.empty() || !t.levels[0].defined) return why = "texture incomplete", std::nullopt;
  const uint32_t w0 = t.levels[0].w, h0 = t.levels[0].h;
  uint32_t n = 1;
  while (n < t.levels.size() && t.levels[n].defined && t.levels[n].w == std::max(1u, w0 >> n) &&
         t.levels[n].h == std::max(1u, h0 >> n))
    ++n;
  const bool mipmapped = t.min_filter >= 0x2700 && t.min_filter <= 0x2703;
  if (mipmapped && n < static_cast<uint32_t>(std::bit_width(std::max(w0, h0))))
    return why = "texture incomplete", std::nullopt;
  if (!mipmapped) n = 1;  // only the base level is sampled
  if (t.trace_id >= 0) return static_cast<uint32_t>(t.trace_id);
  if (next_trace_id_ >= kDrawMaxTextures) return why = "too many textures", std::nullopt;
  DrawTexture d;
  d.id = next_trace_id_++;
  d.width = w0;
  d.height = h0;
  d.name = "GL texture " + std::to_string(gl_name) + ", upload " + std::to_string(t.upload);
  for (uint32_t l = 0; l < n; ++l) d.levels.push_back(t.levels[l].rgba);
  w_.add_texture(d);
  ++s_.textures;
  for (const auto& l : d.levels) s_.texture_bytes += l.size();
  t.trace_id = d.id;
  return d.id;
}

void Interpreter::draw(uint32_t mode, const std::vector<uint32_t>& idx) {
  if (!in_range()) return;
  const std::string c = call_;
  std::vector<uint32_t> tri;
  if (!triangle_list(mode, idx, tri)) return count(c + "[points or lines]");
  if (tri.empty()) return;
  if (tri.size() > kDrawMaxIndices) return count(c + "[too many indices]");
  const auto [lo_it, hi_it] = std::minmax_element(tri.begin(), tri.end());
  const uint32_t lo = *lo_it, hi = *hi_it;
  if (hi - lo >= kDrawMaxVertices) return count(c + "[too many vertices]");
  if (!vertex_.enabled) return count(c + "[no vertex array]");

  Draw d;
  d.state = st_;
  if (!viewport_set_) return count(c + "[viewport not set]");
  if (!write_units(c, d)) return;
  if (!state_interpreted(d)) return count(c + "[state not interpreted]");
  if (!arrays_usable(c, d)) return;

  const uint32_t nv = hi - lo + 1;
  if (!gather_vertices(c, lo, nv, d)) return;
  d.indices.resize(tri.size());
  for (size_t k = 0; k < tri.size(); ++k) d.indices[k] = tri[k] - lo;
  w_.add_draw(d);
  ImportFrameSummary& fs = s_.frames[frame_];
  ++fs.draws;
  fs.vertices += nv;
  fs.triangles += tri.size() / 3;
}

// The enabled texture units of the draw, writing each one's texture on first use; false (and
// counted) when a unit cannot be expressed.
bool Interpreter::write_units(const std::string& c, Draw& d) {
  for (uint32_t u = 0; u < kUnitsTracked; ++u) {
    Unit& unit = units_[u];
    if (!unit.tex2d) continue;
    if (u >= kDrawMaxUnits) return count(c + "[more than 2 units]"), false;
    GlTexture& t = textures_[unit.bound];
    std::string why;
    const auto id = write_texture(t, unit.bound, why);
    if (!id) {
      std::string what = c;
      what.append("[").append(why).append("]");
      count(what);
      return false;
    }
    DrawUnit du;
    du.unit = u;
    du.texture = *id;
    du.min_filter = t.min_filter;
    du.mag_filter = t.mag_filter;
    du.wrap_s = t.wrap_s;
    du.wrap_t = t.wrap_t;
    du.max_anisotropy = t.aniso;
    du.lod_bias = t.lod_bias;
    du.env_mode = unit.env;
    d.units.push_back(du);
  }
  return true;
}

// Whether the arrays the draw reads hold client data of a readable type; counted when not.
bool Interpreter::arrays_usable(const std::string& c, const Draw& d) {
  uint64_t base = 0;
  const auto readable = [&](const ClientArray& a) { return array_bytes(a, base) != nullptr; };
  if (!readable(vertex_) || (color_.enabled && !readable(color_)))
    return count(c + "[buffer object contents unknown]"), false;
  if (!usable_array(vertex_, false) || vertex_.size < 2)
    return count(c + "[vertex array type]"), false;
  if (color_.enabled && (!usable_array(color_, true) || color_.size < 3))
    return count(c + "[colour array type]"), false;
  for (const DrawUnit& u : d.units) {
    const ClientArray& a = units_[u.unit].coords;
    if (a.enabled && !readable(a)) return count(c + "[buffer object contents unknown]"), false;
    if (a.enabled && !usable_array(a, false))
      return count(c + "[texture coordinate array type]"), false;
  }
  return true;
}

// Component k (of `size`) of element v of an array, as a double.
double Interpreter::fetch(const ClientArray& a, const char* what, uint32_t v, uint32_t k) {
  const uint32_t tb = type_bytes(a.type);
  const uint64_t stride = a.stride ? a.stride : uint64_t{a.size} * tb;
  uint64_t base = 0;
  const std::vector<uint8_t>& bytes = *array_bytes(a, base);  // arrays_usable checked it
  const uint64_t at = base + uint64_t{v} * stride + uint64_t{k} * tb;
  if (at + tb > bytes.size())
    throw InputError(where(), std::string(what) + " array of " + std::to_string(bytes.size()) +
                                  " bytes ends before vertex " + std::to_string(v));
  const uint8_t* p = bytes.data() + at;
  if (a.type == 0x1406) {
    float f;
    std::memcpy(&f, p, 4);
    return f;
  }
  if (a.type == 0x140A) {
    double f;
    std::memcpy(&f, p, 8);
    return f;
  }
  return p[0];  // GL_UNSIGNED_BYTE (colours)
}

// Vertices lo..lo+nv-1 of the draw: clip-space positions, texture coordinates and colours; false
// (and counted) for projective texture coordinates.
bool Interpreter::gather_vertices(const std::string& c, uint32_t lo, uint32_t nv, Draw& d) {
  const Mat mvp = mul(projection_.m.back(), modelview_.m.back());
  d.vertex_count = nv;
  d.position.resize(size_t{4} * nv);
  d.has_color = true;
  d.color.resize(size_t{4} * nv);
  for (size_t i = 0; i < d.units.size(); ++i) d.st[i].resize(size_t{2} * nv);
  for (size_t v = 0; v < nv; ++v) {
    const uint32_t src = lo + static_cast<uint32_t>(v);
    transform_vertex(mvp, src, &d.position[4 * v]);
    for (size_t i = 0; i < d.units.size(); ++i) {
      const Unit& unit = units_[d.units[i].unit];
      const ClientArray& a = unit.coords;
      // (s, t, r, q) through the unit's texture matrix; the format holds s and t, so a q other
      // than 1 (projective coordinates) leaves the draw out.
      // An array's missing components are t = r = 0, q = 1; without one, the current values.
      double tc[4] = {unit.s, unit.t, 0, 1};
      if (a.enabled) {
        tc[1] = 0;
        for (uint32_t k = 0; k < a.size; ++k) tc[k] = fetch(a, "texture coordinate", src, k);
      }
      if (const Mat& m = unit.texture.m.back(); m != identity()) {
        const double in[4] = {tc[0], tc[1], tc[2], tc[3]};
        for (int row = 0; row < 4; ++row)
          tc[row] = m[row] * in[0] + m[4 + row] * in[1] + m[8 + row] * in[2] + m[12 + row] * in[3];
      }
      if (tc[3] != 1) return count(c + "[projective texture coordinates]"), false;
      const double cs = tc[0], ct = tc[1];
      d.st[i][2 * v] = to_f32(cs, "vertex " + std::to_string(src) + ": texture coordinate");
      d.st[i][2 * v + 1] = to_f32(ct, "vertex " + std::to_string(src) + ": texture coordinate");
    }
    vertex_colour(src, &d.color[4 * v]);
  }
  return true;
}

// The clip-space position of vertex src under mvp.
void Interpreter::transform_vertex(const Mat& mvp, uint32_t src, float* out) {
  double p[4] = {0, 0, 0, 1};
  for (uint32_t k = 0; k < vertex_.size; ++k) p[k] = fetch(vertex_, "vertex", src, k);
  for (int row = 0; row < 4; ++row) {
    const double x =
        mvp[row] * p[0] + mvp[4 + row] * p[1] + mvp[8 + row] * p[2] + mvp[12 + row] * p[3];
    out[row] = to_f32(x, "vertex " + std::to_string(src) + ": clip-space position");
  }
}

// The RGBA colour of vertex src: the colour array where enabled (missing components 255), else
// the current colour.
void Interpreter::vertex_colour(uint32_t src, uint8_t* out) {
  for (uint32_t k = 0; k < 4; ++k) {
    uint8_t col = color_now_[k];
    if (color_.enabled) {
      if (k < color_.size) {
        const double x = fetch(color_, "colour", src, k);
        if (!std::isfinite(x))
          throw InputError(where(), "vertex " + std::to_string(src) + ": colour is not finite");
        col = color_.type == 0x1401
                  ? static_cast<uint8_t>(x)
                  : static_cast<uint8_t>(std::lround(std::clamp(x, 0.0, 1.0) * 255));
      } else {
        col = 255;
      }
    }
    out[k] = col;
  }
}

// Bounded line reader over a file descriptor.
class LineReader {
 public:
  LineReader(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  // The next line without its end; false at the end of input.
  bool next(std::string& line) {
    line.clear();
    for (;;) {
      if (pos_ == len_) {
        const ssize_t n = ::read(fd_, buf_, sizeof buf_);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0)
          throw InputError(name_, std::string("cannot read the dump: ") + std::strerror(errno));
        if (n == 0) return !line.empty();
        pos_ = 0;
        len_ = static_cast<size_t>(n);
      }
      const char* start = buf_ + pos_;
      const void* nl = std::memchr(start, '\n', len_ - pos_);
      const size_t take =
          nl ? static_cast<size_t>(static_cast<const char*>(nl) - start) : len_ - pos_;
      if (line.size() + take > kImportMaxLineBytes)
        throw InputError(name_, "a dump line after call " + line.substr(0, line.find(' ')) +
                                    " is longer than " + std::to_string(kImportMaxLineBytes) +
                                    " bytes");
      line.append(start, take);
      pos_ += take;
      if (nl) {
        ++pos_;
        return true;
      }
    }
  }

 private:
  int fd_;
  std::string name_;
  char buf_[65536];
  size_t pos_ = 0, len_ = 0;
};

ImportSummary run_interpreter(int fd, const std::string& name, const std::string& blob_dir,
                              bool remove_blobs, uint32_t first, uint32_t last,
                              const std::string& output) {
  ImportSummary s;
  DrawTraceWriter w(output, "apitrace capture " + std::filesystem::path(name).filename().string() +
                                ", frames " + std::to_string(first) + "-" + std::to_string(last));
  Interpreter in(name, blob_dir, remove_blobs, first, last, w, s);
  LineReader r(fd, name);
  std::string line;
  bool more = true;
  while (more && r.next(line)) more = in.line(line);
  if (more) in.finish();
  w.close();
  s.bytes = w.bytes_written();
  return s;
}

}  // namespace

void parse_frame_range(const std::string& text, uint32_t& first, uint32_t& last) {
  const size_t dash = text.find('-');
  auto parse = [&](const std::string& t) {
    if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos)
      throw InputError("--frames", "'" + text + "' is not a frame range A-B (0-based)");
    return static_cast<uint32_t>(std::stoul(t));
  };
  first = parse(text.substr(0, dash));
  last = dash == std::string::npos ? first : parse(text.substr(dash + 1));
  if (last < first)
    throw InputError("--frames", "'" + text + "': the last frame is before the first");
  if (last - first >= kDrawMaxFrames)
    throw InputError("--frames",
                     "'" + text + "': more than " + std::to_string(kDrawMaxFrames) + " frames");
}

ImportSummary import_apitrace_dump(const std::string& dump_text, const std::string& blob_dir,
                                   uint32_t first, uint32_t last, const std::string& output,
                                   const std::string& name) {
  check_input_file(dump_text, "apitrace dump", kNoSizeLimit);
  const int fd = ::open(dump_text.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(dump_text, std::string("cannot open: ") + std::strerror(errno));
  try {
    ImportSummary s = run_interpreter(fd, name, blob_dir, false, first, last, output);
    ::close(fd);
    return s;
  } catch (...) {
    ::close(fd);
    throw;
  }
}

ImportSummary import_apitrace(const std::string& capture, uint32_t first, uint32_t last,
                              const std::string& output) {
  check_input_file(capture, "apitrace capture", kNoSizeLimit);
  refuse_overwriting_input(output);  // before the work, not only at the output's commit
  const std::string abs = std::filesystem::absolute(capture).string();
  std::string dir_template =
      (std::filesystem::temp_directory_path() / "texsim-import-XXXXXX").string();
  if (!::mkdtemp(dir_template.data()))
    throw InputError(capture,
                     std::string("cannot make a temporary directory: ") + std::strerror(errno));
  const std::string dir = dir_template;
  struct Cleanup {
    std::string dir;
    pid_t pid = -1;
    int fd = -1;
    ~Cleanup() {
      if (fd >= 0) ::close(fd);
      if (pid > 0) {
        ::kill(pid, SIGTERM);  // our own child, by its id
        int st = 0;
        ::waitpid(pid, &st, 0);
      }
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } cleanup{dir};
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw InputError(capture, std::string("cannot make a pipe: ") + std::strerror(errno));
  const std::string err_path = dir + "/dump.stderr";
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw InputError(capture, std::string("cannot start apitrace: ") + std::strerror(errno));
  }
  if (pid == 0) {
    // Child: only async-signal-safe calls until exec.
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (::chdir(dir.c_str()) != 0 || ::dup2(fds[1], 1) < 0 || err < 0 || ::dup2(err, 2) < 0)
      ::_exit(126);
    const char* argv[] = {"apitrace",       "dump",           "--blobs",
                          "--color=never",  "--arg-names=no", "--call-nos=yes",
                          "--multiline=no", abs.c_str(),      nullptr};
    ::execvp("apitrace", const_cast<char* const*>(argv));
    ::_exit(127);
  }
  ::close(fds[1]);
  cleanup.pid = pid;
  cleanup.fd = fds[0];
  ImportSummary s;
  try {
    s = run_interpreter(fds[0], capture, dir, true, first, last, output);
  } catch (const InputError& e) {
    // A dump that failed explains the error better than its truncated output does.
    ::close(cleanup.fd);
    cleanup.fd = -1;
    int st = 0;
    ::waitpid(pid, &st, 0);
    cleanup.pid = -1;
    // Killed by a signal: the pipe closed above (SIGPIPE) after the error, not its cause.
    if (WIFEXITED(st) && WEXITSTATUS(st) != 0) {
      std::string why = read_input_file(err_path, "apitrace dump errors", kMaxTextInput);
      if (why.size() > 400) why = why.substr(0, 400);
      std::replace(why.begin(), why.end(), '\n', ' ');
      const int code = WEXITSTATUS(st);
      if (code == 127)
        throw InputError(capture, "cannot run 'apitrace' (install Debian's apitrace package)");
      throw InputError(capture, "apitrace dump failed (status " + std::to_string(code) +
                                    "): " + why + " — " + e.what());
    }
    throw;
  }
  return s;
}

void print_import_summary(const ImportSummary& s, const std::string& output, std::ostream& out) {
  uint64_t draws = 0, verts = 0, tris = 0;
  for (const auto& [f, fs] : s.frames) {
    draws += fs.draws;
    verts += fs.vertices;
    tris += fs.triangles;
  }
  out << "texsim import apitrace: wrote " << output << " (" << s.bytes
      << " bytes): " << s.frames.size() << " frames, " << draws << " draws, " << verts
      << " vertices, " << tris << " triangles, " << s.textures << " textures (" << s.texture_bytes
      << " bytes); " << s.calls << " calls read\n";
  for (const auto& [f, fs] : s.frames) {
    uint64_t un = 0;
    for (const auto& [n, k] : fs.uninterpreted) un += k;
    out << "frame " << f << ": " << fs.draws << " draws, " << fs.vertices << " vertices, "
        << fs.triangles << " triangles; " << un << " calls not interpreted";
    const char* sep = ": ";
    for (const auto& [n, k] : fs.uninterpreted) {
      out << sep << n << " " << k;
      sep = ", ";
    }
    out << "\n";
  }
}

}  // namespace texsim
