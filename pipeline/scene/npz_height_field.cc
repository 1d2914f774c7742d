#include "pipeline/scene/npz_height_field.h"

#include <sys/stat.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/scene/scene_memory.h"

namespace texsim {

namespace {

// The .npy header is at most this long (numpy writes well under 1 KiB).
constexpr size_t kMaxHeader = size_t{1} << 16;

uint32_t le(const std::string& b, size_t at, int bytes) {
  uint32_t v = 0;
  for (int i = bytes - 1; i >= 0; --i)
    v = (v << 8) | static_cast<uint8_t>(b[at + static_cast<size_t>(i)]);
  return v;
}

struct Member {
  std::string name;
  uint32_t method = 0, packed = 0, size = 0, local = 0;
};

// The archive's members from its central directory.
std::vector<Member> members(const std::string& path, const std::string& z) {
  if (z.size() < 22) throw InputError(path, "not a .npz (zip) archive: too short");
  size_t eocd = std::string::npos;
  for (size_t i = z.size() - 22 + 1; i-- > 0 && z.size() - i <= 22 + 65535;) {
    if (le(z, i, 4) == 0x06054b50U) {
      eocd = i;
      break;
    }
  }
  if (eocd == std::string::npos) throw InputError(path, "not a .npz (zip) archive");
  const uint32_t count = le(z, eocd + 10, 2);
  size_t at = le(z, eocd + 16, 4);
  std::vector<Member> out;
  for (uint32_t k = 0; k < count; ++k) {
    if (at > z.size() || z.size() - at < 46 || le(z, at, 4) != 0x02014b50U)
      throw InputError(path, "damaged zip central directory");
    Member m;
    m.method = le(z, at + 10, 2);
    m.packed = le(z, at + 20, 4);
    m.size = le(z, at + 24, 4);
    const uint32_t n = le(z, at + 28, 2), extra = le(z, at + 30, 2), comment = le(z, at + 32, 2);
    m.local = le(z, at + 42, 4);
    if (z.size() - at - 46 < n) throw InputError(path, "damaged zip central directory");
    m.name = z.substr(at + 46, n);
    out.push_back(m);
    at += size_t{46} + n + extra + comment;
  }
  return out;
}

// Up to `want` bytes of a member's data (inflating stops there), and whether that is all of
// it. The declared uncompressed size is checked against the limit before anything is inflated.
std::string member_bytes(const std::string& path, const std::string& z, const Member& m,
                         size_t want) {
  const std::string where = "zip member '" + m.name + "'";
  if (m.size > kMaxNpzBytes) {
    throw InputError(path, where + ": declares " + std::to_string(m.size) +
                               " bytes uncompressed, more than the limit of " +
                               std::to_string(kMaxNpzBytes));
  }
  if (static_cast<size_t>(m.local) > z.size() || z.size() - m.local < 30 ||
      le(z, m.local, 4) != 0x04034b50U)
    throw InputError(path, "damaged " + where);
  const size_t data = size_t{m.local} + 30 + le(z, m.local + 26, 2) + le(z, m.local + 28, 2);
  if (data > z.size() || z.size() - data < m.packed) throw InputError(path, "truncated " + where);
  want = std::min<size_t>(want, m.size);
  if (m.method == 0) {
    if (m.packed != m.size) throw InputError(path, where + ": stored sizes differ");
    return z.substr(data, want);
  }
  if (m.method != 8) throw InputError(path, where + ": compression other than deflate");
  std::string out(want, '\0');
  z_stream s{};
  if (inflateInit2(&s, -15) != Z_OK) throw InputError(path, "zlib: cannot start inflate");
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(z.data() + data));
  s.avail_in = m.packed;
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = static_cast<uInt>(want);
  const int rc = inflate(&s, Z_SYNC_FLUSH);
  const uLong got = s.total_out;
  inflateEnd(&s);
  const bool ok = rc == Z_STREAM_END ? got == m.size : (rc == Z_OK || rc == Z_BUF_ERROR);
  if (!ok || got != want) throw InputError(path, where + ": damaged deflate data");
  return out;
}

// The .npy header dictionary, e.g. {'descr': '<i2', 'fortran_order': False, 'shape': (3, 4), }
// parsed as a Python literal: string keys, each once; values a string, a boolean or a tuple
// of whole numbers.
struct NpyHeader {
  std::string descr;
  bool fortran = false;
  std::vector<uint64_t> shape;
};

class HeaderParser {
 public:
  HeaderParser(std::string_view text, std::string where) : t_(text), where_(std::move(where)) {}

  NpyHeader parse() {
    NpyHeader h;
    std::map<std::string, int> seen;
    expect('{');
    while (!peek('}')) {
      const std::string key = string();
      expect(':');
      if (++seen[key] > 1) fail("key '" + key + "' appears twice");
      if (key == "descr") {
        h.descr = string();
      } else if (key == "fortran_order") {
        h.fortran = boolean();
      } else if (key == "shape") {
        h.shape = tuple();
      } else {
        fail("unknown key '" + key + "'");
      }
      if (!peek(',')) break;
      expect(',');
    }
    expect('}');
    skip();
    if (i_ != t_.size()) fail("text after the dictionary");
    for (const char* k : {"descr", "fortran_order", "shape"})
      if (seen.count(k) == 0) fail(std::string("no '") + k + "' key");
    return h;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(where_, ".npy header: " + what);
  }
  void skip() {
    while (i_ < t_.size() && (t_[i_] == ' ' || t_[i_] == '\n' || t_[i_] == '\t')) ++i_;
  }
  bool peek(char c) {
    skip();
    return i_ < t_.size() && t_[i_] == c;
  }
  void expect(char c) {
    if (!peek(c)) fail(std::string("expected '") + c + "' at byte " + std::to_string(i_));
    ++i_;
  }
  std::string string() {
    skip();
    if (i_ >= t_.size() || (t_[i_] != '\'' && t_[i_] != '"'))
      fail("expected a quoted string at byte " + std::to_string(i_));
    const char q = t_[i_++];
    const size_t e = t_.find(q, i_);
    if (e == std::string_view::npos) fail("unterminated string");
    std::string s(t_.substr(i_, e - i_));
    if (s.find('\\') != std::string::npos) fail("escapes in strings are not supported");
    i_ = e + 1;
    return s;
  }
  bool boolean() {
    skip();
    for (const auto& [word, v] : {std::pair{"True", true}, std::pair{"False", false}}) {
      const size_t n = std::strlen(word);
      if (t_.substr(i_, n) == word) {
        i_ += n;
        return v;
      }
    }
    fail("fortran_order must be True or False");
  }
  std::vector<uint64_t> tuple() {
    std::vector<uint64_t> dims;
    expect('(');
    while (!peek(')')) {
      size_t b = i_;
      uint64_t v = 0;
      while (i_ < t_.size() && t_[i_] >= '0' && t_[i_] <= '9') {
        v = v * 10 + static_cast<uint64_t>(t_[i_++] - '0');
        if (v > UINT32_MAX) fail("a shape dimension beyond 32 bits");
      }
      if (i_ == b) fail("shape: expected a whole number at byte " + std::to_string(i_));
      if (dims.size() >= 32) fail("shape: more than 32 dimensions");
      dims.push_back(v);
      if (!peek(',')) break;
      expect(',');
      b = i_;
    }
    expect(')');
    return dims;
  }

  std::string_view t_;
  std::string where_;
  size_t i_ = 0;
};

struct ElementType {
  const char* descr;
  int bytes;
};
constexpr ElementType kTypes[] = {{"<i2", 2}, {"<u2", 2}, {"<i4", 4}, {"<f4", 4}, {"<f8", 8}};

// A parsed .npy prologue: where the data starts and what it holds.
struct NpyLayout {
  NpyHeader header;
  size_t start = 0;
  const ElementType* type = nullptr;
  int rows = 0, cols = 0;  // 0: not a 2-D array
  uint64_t data_bytes() const {
    return static_cast<uint64_t>(rows) * static_cast<uint64_t>(cols) *
           static_cast<uint64_t>(type ? type->bytes : 0);
  }
};

// The prologue from the array's first bytes (at least its header), checked before its data
// is read: version, header, element type, shape and memory.
NpyLayout npy_layout(const std::string& b, const std::string& where) {
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0)
    throw InputError(where, "not a .npy array (no \\x93NUMPY magic)");
  const int major = static_cast<uint8_t>(b[6]), minor = static_cast<uint8_t>(b[7]);
  if (major < 1 || major > 3 || minor != 0) {
    throw InputError(where, ".npy version " + std::to_string(major) + "." + std::to_string(minor) +
                                " (1.0, 2.0 or 3.0 are read)");
  }
  const size_t prefix = major == 1 ? 10 : 12;
  if (b.size() < prefix) throw InputError(where, "truncated .npy header");
  const size_t hl = major == 1 ? le(b, 8, 2) : le(b, 8, 4);
  if (hl > kMaxHeader) throw InputError(where, ".npy header longer than 64 KiB");
  if (b.size() - prefix < hl) throw InputError(where, "truncated .npy header");
  NpyLayout l;
  l.start = prefix + hl;
  l.header = HeaderParser(std::string_view(b).substr(prefix, hl), where).parse();
  if (l.header.shape.size() != 2) return l;
  if (l.header.fortran) throw InputError(where, "Fortran order is not supported");
  const auto* t = std::find_if(std::begin(kTypes), std::end(kTypes),
                               [&](const ElementType& x) { return l.header.descr == x.descr; });
  if (t == std::end(kTypes)) {
    throw InputError(
        where, "unsupported element type '" + l.header.descr + "' (<i2, <u2, <i4, <f4 or <f8)");
  }
  const uint64_t rows = l.header.shape[0], cols = l.header.shape[1];
  if (rows < 1 || cols < 1 || rows > kMaxNpzSide || cols > kMaxNpzSide) {
    throw InputError(where, "shape (" + std::to_string(rows) + ", " + std::to_string(cols) +
                                "): each side must be 1.." + std::to_string(kMaxNpzSide));
  }
  l.type = t;
  l.rows = static_cast<int>(rows);
  l.cols = static_cast<int>(cols);
  // The array as read, its heights, the RGBA copy and the texture with its MIP chain.
  const uint64_t n = rows * cols;
  const uint64_t bytes = n * static_cast<uint64_t>(t->bytes) + n * 8 + n * 16 + n * 16 * 4 / 3;
  if (bytes > scene_memory_limit()) {
    throw InputError(where, "a " + std::to_string(rows) + " x " + std::to_string(cols) +
                                " height field would take an estimated " +
                                std::to_string(bytes >> 20) +
                                " MiB, over the memory limit (--max-memory)");
  }
  return l;
}

double element(const std::string& b, size_t at, const ElementType& t) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const uint32_t raw = le(b, at, std::min(t.bytes, 4));
  const std::string_view d = t.descr;
  if (d == "<i2") {
    const auto x = static_cast<int16_t>(raw);
    return x == std::numeric_limits<int16_t>::min() ? nan : x;
  }
  if (d == "<u2") return static_cast<uint16_t>(raw);
  if (d == "<i4") {
    const auto x = static_cast<int32_t>(raw);
    return x == std::numeric_limits<int32_t>::min() ? nan : x;
  }
  if (d == "<f4") {
    float x = 0;
    std::memcpy(&x, &raw, 4);
    return x;
  }
  const uint64_t bits = uint64_t{raw} | (uint64_t{le(b, at + 4, 4)} << 32);
  double v = 0;
  std::memcpy(&v, &bits, 8);
  return v;
}

// The heights of a checked layout (NaN for no-data); ±inf is refused.
void read_heights(const std::string& b, const NpyLayout& l, const std::string& where,
                  NpzHeightField& f) {
  if (b.size() < l.start || b.size() - l.start < l.data_bytes())
    throw InputError(where, "truncated data");
  const size_t n = static_cast<size_t>(l.rows) * static_cast<size_t>(l.cols);
  f.width = l.cols;
  f.height = l.rows;
  f.h.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const double v = element(b, l.start + i * static_cast<size_t>(l.type->bytes), *l.type);
    if (std::isinf(v)) {
      throw InputError(where, "height at row " + std::to_string(i / static_cast<size_t>(l.cols)) +
                                  ", column " + std::to_string(i % static_cast<size_t>(l.cols)) +
                                  " is infinite (NaN marks no-data)");
    }
    f.h[i] = v;
  }
}

// Replaces no-data by the lowest valid height and normalises to [0, 1]. Halves before the
// difference so heights spanning ±1.8e308 do not overflow to inf (and NaN).
void normalise(NpzHeightField& f, const std::string& where) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : f.h) {
    if (std::isnan(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const bool any = lo <= hi;
  f.min = any ? lo : 0;
  f.max = any ? hi : 0;
  const bool halve = any && !std::isfinite(hi - lo);
  const double s = halve ? 0.5 : 1.0, base = lo * s, span = hi * s - lo * s;
  for (double& v : f.h) {
    if (std::isnan(v)) {
      ++f.no_data;
      v = 0;
      continue;
    }
    v = span > 0 ? std::clamp((v * s - base) / span, 0.0, 1.0) : 0;
    if (!std::isfinite(v)) throw InputError(where, "heights cannot be normalised");
  }
}

}  // namespace

bool is_npz_source(const std::string& source) {
  return source.size() > 4 && source.compare(source.size() - 4, 4, ".npz") == 0;
}

NpzHeightField parse_npy_height_field(const std::string& bytes, const std::string& where) {
  const NpyLayout l = npy_layout(bytes, where);
  NpzHeightField f;
  if (l.rows == 0) return f;
  read_heights(bytes, l, where, f);
  normalise(f, where);
  return f;
}

NpzHeightField read_npz_height_field(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 && errno == ENOENT) {
    throw InputError(path,
                     "height field not found (the sample DEMs come with Debian's "
                     "python-matplotlib-data: scripts/setup-debian.sh installs it)");
  }
  const std::string z = read_input_file(path, ".npz height field", kMaxNpzBytes);
  for (const Member& m : members(path, z)) {
    if (m.name.size() < 4 || m.name.compare(m.name.size() - 4, 4, ".npy") != 0) continue;
    const std::string where = path + ": member '" + m.name + "'";
    // The header first (a few KiB at most), so the shape is checked before the data is inflated.
    const NpyLayout l = npy_layout(member_bytes(path, z, m, 12 + kMaxHeader), where);
    if (l.rows == 0) continue;
    if (m.size < l.start || m.size - l.start < l.data_bytes())
      throw InputError(where, "truncated data");
    NpzHeightField f;
    f.array = m.name;
    read_heights(member_bytes(path, z, m, l.start + l.data_bytes()), l, where, f);
    normalise(f, where);
    return f;
  }
  throw InputError(path, "no 2-D array in the .npz archive");
}
Texture npz_height_texture(const std::string& path) {
  const NpzHeightField f = read_npz_height_field(path);
  std::vector<float> rgba;
  rgba.reserve(f.h.size() * 4);
  for (const double v : f.h) {
    const auto g = static_cast<float>(v);
    rgba.insert(rgba.end(), {g, g, g, 1.0F});
  }
  return Texture::from_rgba(path, f.width, f.height, rgba, TexelFormat::Rgba32f, true);
}

}  // namespace texsim
