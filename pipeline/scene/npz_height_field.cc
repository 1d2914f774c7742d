#include "pipeline/scene/npz_height_field.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

constexpr size_t kMaxBytes = size_t{1} << 28;
constexpr int kMaxSide = 8192;

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
    if (at + 46 > z.size() || le(z, at, 4) != 0x02014b50U)
      throw InputError(path, "damaged zip central directory");
    Member m;
    m.method = le(z, at + 10, 2);
    m.packed = le(z, at + 20, 4);
    m.size = le(z, at + 24, 4);
    const uint32_t n = le(z, at + 28, 2), extra = le(z, at + 30, 2), comment = le(z, at + 32, 2);
    m.local = le(z, at + 42, 4);
    if (at + 46 + n > z.size()) throw InputError(path, "damaged zip central directory");
    m.name = z.substr(at + 46, n);
    out.push_back(m);
    at += 46 + n + extra + comment;
  }
  return out;
}

std::string member_bytes(const std::string& path, const std::string& z, const Member& m) {
  if (m.size > kMaxBytes || static_cast<size_t>(m.local) + 30 > z.size() ||
      le(z, m.local, 4) != 0x04034b50U) {
    throw InputError(path, "damaged zip member '" + m.name + "'");
  }
  const size_t data = m.local + 30 + le(z, m.local + 26, 2) + le(z, m.local + 28, 2);
  if (data + m.packed > z.size()) throw InputError(path, "truncated zip member '" + m.name + "'");
  if (m.method == 0) return z.substr(data, m.packed);
  if (m.method != 8)
    throw InputError(path, "zip member '" + m.name + "': compression other than deflate");
  std::string out(m.size, '\0');
  z_stream s{};
  if (inflateInit2(&s, -15) != Z_OK) throw InputError(path, "zlib: cannot start inflate");
  s.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(z.data() + data));
  s.avail_in = m.packed;
  s.next_out = reinterpret_cast<Bytef*>(out.data());
  s.avail_out = m.size;
  const int rc = inflate(&s, Z_FINISH);
  inflateEnd(&s);
  if (rc != Z_STREAM_END || s.total_out != m.size)
    throw InputError(path, "zip member '" + m.name + "': damaged deflate data");
  return out;
}

// The value after `key` in a .npy header dict, up to the next top-level ',' or '}'.
std::string header_value(const std::string& hdr, const std::string& key) {
  const size_t k = hdr.find("'" + key + "'");
  if (k == std::string::npos) return "";
  size_t a = hdr.find(':', k);
  if (a == std::string::npos) return "";
  ++a;
  int depth = 0;
  size_t b = a;
  for (; b < hdr.size(); ++b) {
    if (hdr[b] == '(') ++depth;
    if (hdr[b] == ')') --depth;
    if (depth == 0 && (hdr[b] == ',' || hdr[b] == '}')) break;
  }
  std::string v = hdr.substr(a, b - a);
  v.erase(std::remove(v.begin(), v.end(), ' '), v.end());
  return v;
}

// Parses a 2-D .npy array into `f` (raw values, NaN for no-data); false if not 2-D.
bool parse_npy(const std::string& path, const std::string& b, NpzHeightField& f) {
  if (b.size() < 10 || b.compare(0, 6, "\x93NUMPY") != 0)
    throw InputError(path, "member '" + f.array + "' is not a .npy array");
  const bool v1 = b[6] == 1;
  const size_t hl = v1 ? le(b, 8, 2) : le(b, 8, 4), start = (v1 ? 10 : 12) + hl;
  if (start > b.size()) throw InputError(path, "member '" + f.array + "': truncated header");
  const std::string hdr = b.substr(v1 ? 10 : 12, hl);
  const std::string descr = header_value(hdr, "descr"), shape = header_value(hdr, "shape");
  if (header_value(hdr, "fortran_order") != "False")
    throw InputError(path, "member '" + f.array + "': Fortran order is not supported");
  int rows = 0, cols = 0;
  // Two dimensions: "(rows,cols)" with one comma ("(n,)" is 1-D, "(a,b,c)" 3-D).
  if (std::sscanf(shape.c_str(), "(%d,%d)", &rows, &cols) != 2 ||
      std::count(shape.begin(), shape.end(), ',') != 1)
    return false;
  if (rows <= 0 || cols <= 0 || rows > kMaxSide || cols > kMaxSide)
    throw InputError(path, "member '" + f.array + "': unsupported shape " + shape);
  struct Type {
    const char* name;
    int bytes;
  };
  const Type types[] = {{"'<i2'", 2}, {"'<u2'", 2}, {"'<i4'", 4}, {"'<f4'", 4}, {"'<f8'", 8}};
  const auto* t = std::find_if(std::begin(types), std::end(types),
                               [&](const Type& x) { return descr == x.name; });
  if (t == std::end(types))
    throw InputError(path, "member '" + f.array + "': unsupported element type " + descr);
  const size_t n = static_cast<size_t>(rows) * static_cast<size_t>(cols);
  if (start + n * static_cast<size_t>(t->bytes) > b.size())
    throw InputError(path, "member '" + f.array + "': truncated data");
  f.width = cols;
  f.height = rows;
  f.h.resize(n);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (size_t i = 0; i < n; ++i) {
    const size_t at = start + i * static_cast<size_t>(t->bytes);
    const uint32_t raw = le(b, at, std::min(t->bytes, 4));
    double v = 0;
    if (descr == "'<i2'") {
      const auto x = static_cast<int16_t>(raw);
      v = x == std::numeric_limits<int16_t>::min() ? nan : x;
    } else if (descr == "'<u2'") {
      v = static_cast<uint16_t>(raw);
    } else if (descr == "'<i4'") {
      const auto x = static_cast<int32_t>(raw);
      v = x == std::numeric_limits<int32_t>::min() ? nan : x;
    } else if (descr == "'<f4'") {
      float x = 0;
      std::memcpy(&x, &raw, 4);
      v = x;
    } else {
      const uint64_t lo = raw, hi = le(b, at + 4, 4);
      const uint64_t bits = lo | (hi << 32);
      std::memcpy(&v, &bits, 8);
    }
    f.h[i] = v;
  }
  return true;
}

// Replaces no-data by the lowest valid height and normalises to [0, 1].
void normalise(NpzHeightField& f) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const double v : f.h) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  const bool any = lo <= hi;
  f.min = any ? lo : 0;
  f.max = any ? hi : 0;
  const double span = hi - lo;
  for (double& v : f.h) {
    if (!std::isfinite(v)) {
      ++f.no_data;
      v = 0;
    } else {
      v = span > 0 ? (v - lo) / span : 0;
    }
  }
}

}  // namespace

bool is_npz_source(const std::string& source) {
  return source.size() > 4 && source.compare(source.size() - 4, 4, ".npz") == 0;
}

NpzHeightField read_npz_height_field(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path,
                     "height field not found (the sample DEMs come with Debian's "
                     "python-matplotlib-data: scripts/setup-debian.sh installs it)");
  }
  std::string z((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (z.size() > kMaxBytes) throw InputError(path, ".npz archive larger than 256 MiB");
  for (const Member& m : members(path, z)) {
    if (m.name.size() < 4 || m.name.compare(m.name.size() - 4, 4, ".npy") != 0) continue;
    NpzHeightField f;
    f.array = m.name;
    if (!parse_npy(path, member_bytes(path, z, m), f)) continue;
    normalise(f);
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
