#include "pipeline/scene/model_stream.h"

#include <cmath>
#include <type_traits>

namespace texsim {

namespace {

constexpr uint32_t kMagic = 0x494d5854;  // "TXMI"
constexpr uint32_t kVersion = 1;
constexpr uint32_t kEnd = 0x2e444e45;  // "END."

class Writer {
 public:
  explicit Writer(ByteSink& out) : out_(out) {}
  template <class T>
  void put(T v) {
    static_assert(std::is_arithmetic_v<T>);
    out_.write(&v, sizeof v);
  }
  void put_string(const std::string& s) {
    put(static_cast<uint32_t>(s.size()));
    out_.write(s.data(), s.size());
  }

 private:
  ByteSink& out_;
};

// Exact reads through a buffer; every refusal names the byte it is at.
class Reader {
 public:
  Reader(ByteSource& in, const std::string& file, const std::string& who)
      : in_(in), file_(file), who_(who) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw ChildFailure(
        ChildFailure::Kind::Malformed, file_,
        who_ + " sent malformed data: " + what + ", at byte " + std::to_string(offset_));
  }
  void get(void* dst, size_t n) {
    auto* d = static_cast<char*>(dst);
    while (n > 0) {
      if (pos_ == len_) {
        len_ = in_.read_some(buf_, sizeof buf_);
        pos_ = 0;
        if (len_ == 0) fail("the output ends early");
      }
      const size_t k = std::min(n, len_ - pos_);
      std::memcpy(d, buf_ + pos_, k);
      pos_ += k;
      offset_ += k;
      d += k;
      n -= k;
    }
  }
  template <class T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    T v;
    get(&v, sizeof v);
    return v;
  }
  // A count of at most `max` ("what" names it).
  uint32_t count(uint64_t max, const char* what) {
    const auto n = get<uint32_t>();
    if (n > max) fail(std::string(what) + " " + std::to_string(n) + " over the limit");
    return n;
  }
  std::string string(uint64_t max, const char* what) {
    std::string s(count(max, what), '\0');
    get(s.data(), s.size());
    return s;
  }
  // A finite number within ±max.
  double number(double max, const char* what) {
    const auto v = get<double>();
    if (!(std::fabs(v) <= max)) fail(std::string(what) + " not finite or out of range");
    return v;
  }
  // An index below `n`.
  int index(size_t n, const char* what) {
    const auto v = get<int32_t>();
    if (v < 0 || static_cast<size_t>(v) >= n) fail(std::string(what) + " index out of range");
    return v;
  }

 private:
  ByteSource& in_;
  const std::string& file_;
  const std::string& who_;
  uint64_t offset_ = 0;
  size_t pos_ = 0, len_ = 0;
  char buf_[65536];
};

void read_model(Reader& r, Model& m, const std::string& file, const MeshBudget& budget) {
  const auto uvs = r.get<uint8_t>();
  if (uvs > 1) r.fail("has_uvs not 0 or 1");
  m.mesh.has_uvs = uvs == 1;
  const uint32_t materials = r.count(kMaxModelMaterials, "material count");
  if (materials == 0) r.fail("no materials");
  m.materials.resize(materials);
  for (ModelMaterial& mm : m.materials) {
    mm.name = r.string(kMaxModelNameBytes, "material name length");
    mm.texture = r.string(kMaxModelPathBytes, "texture path length");
  }
  const auto vertices = r.get<uint32_t>();
  // The same limits as the child's (before any allocation): an honest child never fails them.
  check_model_counts(vertices, 1, file, budget);
  m.mesh.positions.resize(vertices);
  for (glm::dvec3& p : m.mesh.positions) {
    for (int k = 0; k < 3; ++k) p[k] = r.number(kMaxModelCoordinate, "vertex coordinate");
  }
  const auto triangles = r.get<uint32_t>();
  check_model_counts(vertices, triangles, file, budget);
  m.mesh.triangles.resize(triangles);
  m.triangle_material.resize(triangles);
  for (uint32_t i = 0; i < triangles; ++i) {
    MeshTriangle& t = m.mesh.triangles[i];
    for (int& v : t.v) v = r.index(vertices, "vertex");
    for (glm::dvec2& uv : t.uv) {
      uv.x = r.number(kMaxModelTexcoord, "texture coordinate");
      uv.y = r.number(kMaxModelTexcoord, "texture coordinate");
    }
    m.triangle_material[i] = r.index(materials, "material");
  }
}

}  // namespace

void write_model_message(ByteSink& out, const ModelMessage& m) {
  Writer w(out);
  w.put(kMagic);
  w.put(kVersion);
  w.put(static_cast<uint32_t>(m.opened.size()));
  for (const std::string& f : m.opened) w.put_string(f);
  w.put(static_cast<uint8_t>(m.failed ? 1 : 0));
  if (m.failed) {
    w.put_string(m.error.size() > kMaxModelMessageBytes ? m.error.substr(0, kMaxModelMessageBytes)
                                                        : m.error);
  } else {
    w.put(static_cast<uint8_t>(m.model.mesh.has_uvs ? 1 : 0));
    w.put(static_cast<uint32_t>(m.model.materials.size()));
    for (const ModelMaterial& mm : m.model.materials) {
      w.put_string(mm.name);
      w.put_string(mm.texture);
    }
    w.put(static_cast<uint32_t>(m.model.mesh.positions.size()));
    for (const glm::dvec3& p : m.model.mesh.positions) {
      for (int k = 0; k < 3; ++k) w.put(p[k]);
    }
    w.put(static_cast<uint32_t>(m.model.mesh.triangles.size()));
    for (size_t i = 0; i < m.model.mesh.triangles.size(); ++i) {
      const MeshTriangle& t = m.model.mesh.triangles[i];
      for (const int v : t.v) w.put(static_cast<int32_t>(v));
      for (const glm::dvec2& uv : t.uv) {
        w.put(uv.x);
        w.put(uv.y);
      }
      w.put(static_cast<int32_t>(m.model.triangle_material[i]));
    }
  }
  w.put(kEnd);
}

ModelMessage read_model_message(ByteSource& in, const std::string& file, const std::string& who,
                                const MeshBudget& budget) {
  Reader r(in, file, who);
  if (r.get<uint32_t>() != kMagic) r.fail("no TXMI mark");
  if (r.get<uint32_t>() != kVersion) r.fail("not version 1");
  ModelMessage m;
  m.opened.resize(r.count(kMaxModelOpenedFiles, "opened file count"));
  for (std::string& f : m.opened) {
    f = r.string(kMaxModelPathBytes, "file name length");
    if (f.empty() || f.find('\0') != std::string::npos) r.fail("an opened file with no name");
  }
  const auto status = r.get<uint8_t>();
  if (status > 1) r.fail("status not 0 or 1");
  m.failed = status == 1;
  if (m.failed) {
    m.error = r.string(kMaxModelMessageBytes, "error message length");
    if (m.error.empty()) r.fail("an empty error message");
  } else {
    m.model.mesh.source = file;
    read_model(r, m.model, file, budget);
  }
  if (r.get<uint32_t>() != kEnd) r.fail("no end mark");
  return m;
}

}  // namespace texsim
