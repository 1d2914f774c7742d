#include "pipeline/scene/obj_loader.h"

#include <sys/stat.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <sstream>
#include <streambuf>
#include <string_view>

#include "blocks/base/input_error.h"
#include "blocks/base/input_file.h"
#include "pipeline/scene/scene_memory.h"

namespace texsim {

namespace {

// "\r\n" and a lone '\r' become '\n': the library ends a line at either, texsim's scan too.
void normalise_line_endings(std::string& t) {
  size_t o = 0;
  for (size_t i = 0; i < t.size(); ++i) {
    if (t[i] != '\r') {
      t[o++] = t[i];
      continue;
    }
    t[o++] = '\n';
    if (i + 1 < t.size() && t[i + 1] == '\n') ++i;
  }
  t.resize(o);
}

// Fields of a line split as the library splits them: on spaces and tabs only.
std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t b = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > b) out.push_back(line.substr(b, i - b));
  }
  return out;
}

std::string limit_text(double limit) {
  std::ostringstream o;
  o << limit;
  return o.str();
}

// A decimal number (no "nan", "inf" or hex, which the library and strtod read differently),
// finite and within ±limit.
void check_number(std::string_view tok, const std::string& where, const char* what, double limit) {
  const std::string t(tok);
  char* end = nullptr;
  const double d = std::strtod(t.c_str(), &end);
  if (t.find_first_not_of("0123456789+-.eE") != std::string::npos || end != t.c_str() + t.size() ||
      !std::isfinite(d)) {
    throw InputError(where, std::string(what) + " coordinate '" + t + "' is not a finite number");
  }
  if (std::fabs(d) > limit) {
    throw InputError(where, std::string(what) + " coordinate '" + t + "' is beyond ±" +
                                limit_text(limit) + " (docs/cli.md#input-limits)");
  }
}

void check_numbers(const std::vector<std::string_view>& f, size_t min, const std::string& where,
                   const char* what, double limit) {
  if (f.size() - 1 < min)
    throw InputError(where, std::string(what) + " needs " + std::to_string(min) + " numbers");
  if (f.size() - 1 > 7) throw InputError(where, std::string(what) + " has too many numbers");
  for (size_t i = 1; i < f.size(); ++i) check_number(f[i], where, what, limit);
}

struct FaceRef {
  int line = 0;
  uint8_t corners = 0;
};

// The largest positive index beyond the elements read so far, per kind, and its line: OBJ
// allows such an index if the file has the element by its end.
struct ForwardRef {
  int line = 0;
  long index = 0;
};

struct ObjScan {
  std::vector<FaceRef> faces;
  ForwardRef forward[3];
  long count[3] = {0, 0, 0};  // v, vt, vn lines
  uint64_t corners = 0, triangles = 0;
};

const char* const kKindName[3] = {"vertex", "texture coordinate", "normal"};

// One part of a face corner: a nonzero integer; a negative one counts back from the `count`
// elements read so far, as the library resolves it.
void corner_part(std::string_view part, std::string_view tok, int kind, ObjScan& s, int line,
                 const std::string& where) {
  const std::string p(part);
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(p.c_str(), &end, 10);
  if (p.empty() || end != p.c_str() + p.size() || v == 0 || errno == ERANGE) {
    throw InputError(where, "face corner '" + std::string(tok) + "' is not a " +
                                (kind == 0 ? "vertex index" : "valid index"));
  }
  const long n = s.count[kind];
  if (v < 0 && -v > n) {
    throw InputError(where, "face refers to " + std::string(kKindName[kind]) + " " +
                                std::to_string(v) + " but only " + std::to_string(n) +
                                " come before it");
  }
  if (v > n && v > s.forward[kind].index) s.forward[kind] = {line, v};
}

void scan_face(const std::vector<std::string_view>& fl, ObjScan& s, int no,
               const std::string& where) {
  const size_t corners = fl.size() - 1;
  if (corners < 3) throw InputError(where, "a face needs at least 3 corners");
  if (corners > kMaxObjCorners) {
    throw InputError(where, "a face has " + std::to_string(corners) + " corners; at most " +
                                std::to_string(kMaxObjCorners) +
                                " (the OBJ library keeps a face's corner count in one byte)");
  }
  for (size_t c = 1; c < fl.size(); ++c) {
    const std::string_view tok = fl[c];
    const size_t a = tok.find('/');
    corner_part(tok.substr(0, a), tok, 0, s, no, where);
    if (a == std::string_view::npos) continue;
    const std::string_view rest = tok.substr(a + 1);
    const size_t b = rest.find('/');
    if (b != 0) corner_part(rest.substr(0, b), tok, 1, s, no, where);  // "v//vn" has no vt
    if (b != std::string_view::npos) corner_part(rest.substr(b + 1), tok, 2, s, no, where);
  }
  s.corners += corners;
  s.triangles += corners - 2;
  s.faces.push_back({no, static_cast<uint8_t>(corners)});
}

// One line of the text (without its '\n').
void scan_line(std::string_view line, int no, const std::string& file, ObjScan& s) {
  const std::string where = file + ":" + std::to_string(no);
  for (const char c : line) {
    if (static_cast<unsigned char>(c) < 0x20 && c != '\t') {
      char buf[8];
      std::snprintf(buf, sizeof buf, "0x%02x", static_cast<unsigned char>(c));
      throw InputError(where, std::string("control character ") + buf +
                                  " (OBJ fields are separated by spaces and tabs)");
    }
  }
  const std::vector<std::string_view> f = fields(line);
  if (f.empty()) return;
  int kind = -1;
  if (f[0] == "v") {
    check_numbers(f, 3, where, "vertex", kMaxObjCoordinate);
    kind = 0;
  } else if (f[0] == "vt") {
    check_numbers(f, 1, where, "texture", kMaxObjTexcoord);
    kind = 1;
  } else if (f[0] == "vn") {
    check_numbers(f, 3, where, "normal", kMaxObjCoordinate);
    kind = 2;
  } else if (f[0] == "f") {
    scan_face(f, s, no, where);
    if (static_cast<long>(s.faces.size()) > kMaxObjElements)
      throw InputError(where, "more than " + std::to_string(kMaxObjElements) + " faces");
  }
  if (kind >= 0 && ++s.count[kind] > kMaxObjElements) {
    throw InputError(
        where, "more than " + std::to_string(kMaxObjElements) + " " + kKindName[kind] + " lines");
  }
}

// Reads the text once for everything the library lets through or does not report by line.
ObjScan scan(const std::string& text, const std::string& file, const MeshBudget& budget) {
  ObjScan s;
  size_t at = 0;
  for (int no = 1; at < text.size(); ++no) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    scan_line(std::string_view(text).substr(at, end - at), no, file, s);
    at = end + 1;
  }
  for (int k = 0; k < 3; ++k) {
    const ForwardRef& f = s.forward[k];
    if (f.index > s.count[k]) {
      throw InputError(file + ":" + std::to_string(f.line),
                       "face refers to " + std::string(kKindName[k]) + " " +
                           std::to_string(f.index) + " but the file has " +
                           std::to_string(s.count[k]));
    }
  }
  if (s.triangles > budget.max_triangles) {
    throw InputError(file, "the mesh has " + std::to_string(s.triangles) +
                               " triangles, more than the " + std::to_string(budget.max_triangles) +
                               " allowed");
  }
  const uint64_t bytes =
      sat_add(mesh_bytes(static_cast<uint64_t>(s.count[0]), s.corners, s.triangles, budget),
              sat_mul(text.size(), 2));
  if (bytes > budget.max_bytes) {
    throw InputError(file, "loading the mesh would take an estimated " +
                               std::to_string(bytes >> 20) + " MiB, over the memory limit of " +
                               std::to_string(budget.max_bytes >> 20) + " MiB (--max-memory)");
  }
  return s;
}

// The library reads the text in place through this buffer (no second copy).
struct TextBuf : std::streambuf {
  explicit TextBuf(std::string& t) { setg(t.data(), t.data(), t.data() + t.size()); }
};

// `mtllib` files opened through read_input_file: a directory, FIFO or device is an error, a
// missing file is left out as the library does (texsim uses no OBJ material).
class MtlReader : public tinyobj::MaterialReader {
 public:
  explicit MtlReader(std::string base_dir) : base_(std::move(base_dir)) {}
  bool operator()(const std::string& id, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* map, std::string* warn, std::string* err) override {
    if (error) return false;
    try {
      const std::string path = base_.empty() ? id : (std::filesystem::path(base_) / id).string();
      struct stat st {};
      if (::lstat(path.c_str(), &st) != 0 && errno == ENOENT) return false;
      std::string text = read_input_file(path, "OBJ material library", kMaxTextInput);
      normalise_line_endings(text);
      TextBuf buf(text);
      std::istream in(&buf);
      tinyobj::LoadMtl(map, materials, &in, warn, err);
      return true;
    } catch (...) {
      error = std::current_exception();
      return false;
    }
  }
  std::exception_ptr error;

 private:
  std::string base_;
};

glm::dvec3 position(const tinyobj::attrib_t& a, size_t i) {
  return {a.vertices[i * 3], a.vertices[i * 3 + 1], a.vertices[i * 3 + 2]};
}

// What the library returned agrees with the scan (counts, corners, indices in range).
void check_parsed(const tinyobj::attrib_t& a, const std::vector<tinyobj::shape_t>& shapes,
                  const ObjScan& s, const std::string& file) {
  const auto fail = [&](const std::string& what) {
    throw InputError(file, "the OBJ library read " + what + " differently from texsim's scan");
  };
  if (a.vertices.size() != static_cast<size_t>(s.count[0]) * 3 ||
      a.texcoords.size() != static_cast<size_t>(s.count[1]) * 2 ||
      a.normals.size() != static_cast<size_t>(s.count[2]) * 3)
    fail("the vertex, texture coordinate or normal count");
  for (const double x : a.vertices) {
    if (!(std::fabs(x) <= kMaxObjCoordinate)) fail("a vertex coordinate");
  }
  for (const double x : a.texcoords) {
    if (!(std::fabs(x) <= kMaxObjTexcoord)) fail("a texture coordinate");
  }
  size_t face = 0;
  for (const tinyobj::shape_t& shape : shapes) {
    size_t corner = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (face >= s.faces.size() || n != s.faces[face].corners ||
          corner + n > shape.mesh.indices.size())
        fail("the faces");
      for (size_t k = corner; k < corner + n; ++k) {
        const tinyobj::index_t& i = shape.mesh.indices[k];
        if (i.vertex_index < 0 || i.vertex_index >= s.count[0] || i.texcoord_index >= s.count[1] ||
            i.normal_index >= s.count[2])
          fail("a face index");
      }
      corner += n;
      ++face;
    }
  }
  if (face != s.faces.size()) fail("the face count");
}

// The library's faces as fans of triangles, each with its face's line.
Mesh build(const tinyobj::attrib_t& a, const std::vector<tinyobj::shape_t>& shapes,
           const ObjScan& s, const std::string& file, UvProjection projection) {
  Mesh m;
  m.source = file;
  m.positions.reserve(static_cast<size_t>(s.count[0]));
  for (size_t i = 0; i * 3 < a.vertices.size(); ++i) m.positions.push_back(position(a, i));
  m.triangles.reserve(s.triangles);
  size_t face = 0;
  bool all_uvs = true;
  for (const tinyobj::shape_t& shape : shapes) {
    size_t corner = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      const int line = s.faces[face].line;
      const auto* c = &shape.mesh.indices[corner];
      for (unsigned k = 1; k + 1 < n; ++k) {
        MeshTriangle t;
        t.line = line;
        const tinyobj::index_t* tri[3] = {&c[0], &c[k], &c[k + 1]};
        for (int j = 0; j < 3; ++j) {
          t.v[j] = tri[j]->vertex_index;
          const int ti = tri[j]->texcoord_index;
          if (ti < 0) {
            all_uvs = false;
            if (projection == UvProjection::None) {
              throw InputError(file + ":" + std::to_string(line),
                               "face corner has no texture coordinate and the scene declares no "
                               "uv projection (planar, box or spherical)");
            }
            continue;
          }
          t.uv[j] = {a.texcoords[static_cast<size_t>(ti) * 2],
                     a.texcoords[static_cast<size_t>(ti) * 2 + 1]};
        }
        m.triangles.push_back(t);
      }
      corner += n;
      ++face;
    }
  }
  if (m.triangles.empty()) throw InputError(file, "mesh has no faces");
  m.has_uvs = all_uvs;
  return m;
}

}  // namespace

uint64_t mesh_bytes(uint64_t vertices, uint64_t corners, uint64_t triangles,
                    const MeshBudget& budget) {
  // The library's copy, the mesh's and the placed one per vertex; an index triple per corner;
  // the mesh's triangle and the caller's share per triangle.
  const uint64_t v = sat_mul(vertices, 3 * sizeof(glm::dvec3));
  const uint64_t c = sat_mul(corners, sizeof(tinyobj::index_t) + 1);
  const uint64_t t = sat_mul(triangles, sat_add(sizeof(MeshTriangle), budget.bytes_per_triangle));
  return sat_add(sat_add(v, c), t);
}

Mesh parse_obj(std::string text, const std::string& file, const std::string& base_dir,
               UvProjection projection, const MeshBudget& budget) {
  normalise_line_endings(text);
  const ObjScan s = scan(text, file, budget);
  tinyobj::attrib_t a;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  MtlReader mtl(base_dir);
  TextBuf buf(text);
  std::istream in(&buf);
  // Not triangulated by the library: fans below, so each triangle keeps its face's line.
  const bool ok = tinyobj::LoadObj(&a, &shapes, &materials, &warn, &err, &in, &mtl, false);
  if (mtl.error) std::rethrow_exception(mtl.error);
  if (!ok) throw InputError(file, "cannot read mesh: " + err);
  check_parsed(a, shapes, s, file);
  Mesh m = build(a, shapes, s, file, projection);
  project_uvs(m, projection);
  return m;
}

Mesh load_obj(const std::string& path, const std::string& base_dir, UvProjection projection,
              const MeshBudget& budget) {
  const std::string file = std::filesystem::path(path).is_absolute() || base_dir.empty()
                               ? path
                               : (std::filesystem::path(base_dir) / path).string();
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) throw InputError(file, "mesh file not found");
  std::string text = read_input_file(file, "OBJ mesh", kMaxObjBytes);
  return parse_obj(std::move(text), file, std::filesystem::path(file).parent_path().string(),
                   projection, budget);
}

}  // namespace texsim
