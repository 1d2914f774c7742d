#include "pipeline/scene/obj_loader.h"

#include <sys/stat.h>
#include <tiny_obj_loader.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {

// Lines of the file's faces in order, and its vertex and texture-coordinate counts.
struct ObjLines {
  std::vector<int> face_line;
  long vertices = 0, texcoords = 0;
};

// The vertex part of a face corner "v", "v/vt", "v//vn" or "v/vt/vn", as OBJ counts it.
bool corner_index(const std::string& tok, long& v) {
  char* end = nullptr;
  v = std::strtol(tok.c_str(), &end, 10);
  return end != tok.c_str() && (*end == '\0' || *end == '/') && v != 0;
}

void check_numbers(std::istringstream& in, int min, const std::string& where, const char* what) {
  std::string tok;
  int n = 0;
  while (in >> tok && n < 4) {
    char* end = nullptr;
    const double d = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(d)) {
      throw InputError(where,
                       std::string(what) + " coordinate '" + tok + "' is not a finite number");
    }
    ++n;
  }
  if (n < min)
    throw InputError(where, std::string(what) + " needs " + std::to_string(min) + " numbers");
}

// Reads the file once for the errors tinyobjloader does not report with a line.
ObjLines scan(const std::string& file) {
  std::ifstream f(file);
  ObjLines s;
  std::string line;
  std::vector<std::pair<int, std::vector<long>>> faces;
  for (int no = 1; std::getline(f, line); ++no) {
    std::istringstream in(line);
    std::string key;
    if (!(in >> key)) continue;
    const std::string where = file + ":" + std::to_string(no);
    if (key == "v") {
      check_numbers(in, 3, where, "vertex");
      ++s.vertices;
    } else if (key == "vt") {
      check_numbers(in, 1, where, "texture");
      ++s.texcoords;
    } else if (key == "f") {
      std::vector<long> idx;
      std::string tok;
      while (in >> tok) {
        long v = 0;
        if (!corner_index(tok, v))
          throw InputError(where, "face corner '" + tok + "' is not a vertex index");
        // Negative indices count back from the vertices read so far.
        idx.push_back(v < 0 ? s.vertices + v + 1 : v);
      }
      if (idx.size() < 3) throw InputError(where, "a face needs at least 3 corners");
      faces.emplace_back(no, std::move(idx));
      s.face_line.push_back(no);
    }
  }
  for (const auto& [no, idx] : faces) {
    for (long v : idx) {
      if (v < 1 || v > s.vertices) {
        throw InputError(file + ":" + std::to_string(no),
                         "face refers to vertex " + std::to_string(v) + " but the file has " +
                             std::to_string(s.vertices));
      }
    }
  }
  return s;
}

glm::dvec3 position(const tinyobj::attrib_t& a, int i) {
  const auto k = static_cast<size_t>(i) * 3;
  return {a.vertices[k], a.vertices[k + 1], a.vertices[k + 2]};
}

}  // namespace

Mesh load_obj(const std::string& path, const std::string& base_dir, UvProjection projection) {
  const std::string file = std::filesystem::path(path).is_absolute() || base_dir.empty()
                               ? path
                               : (std::filesystem::path(base_dir) / path).string();
  struct stat st {};
  if (::stat(file.c_str(), &st) != 0) throw InputError(file, "mesh file not found");
  if (!S_ISREG(st.st_mode)) throw InputError(file, "mesh file is not a regular file");
  const ObjLines lines = scan(file);

  tinyobj::ObjReader reader;
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = false;  // fans below, so each triangle keeps its face's line
  if (!reader.ParseFromFile(file, cfg))
    throw InputError(file, "cannot read mesh: " + reader.Error());
  const tinyobj::attrib_t& a = reader.GetAttrib();
  Mesh m;
  m.source = file;
  for (size_t i = 0; i * 3 < a.vertices.size(); ++i)
    m.positions.push_back(position(a, static_cast<int>(i)));
  size_t face = 0;
  bool all_uvs = true;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t corner = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      const int line = face < lines.face_line.size() ? lines.face_line[face] : 0;
      const auto* c = &shape.mesh.indices[corner];
      for (unsigned k = 1; k + 1 < n; ++k) {
        MeshTriangle t;
        t.line = line;
        const tinyobj::index_t* tri[3] = {&c[0], &c[k], &c[k + 1]};
        for (int j = 0; j < 3; ++j) {
          t.v[j] = tri[j]->vertex_index;
          const int ti = tri[j]->texcoord_index;
          if (ti < 0 || static_cast<size_t>(ti) * 2 + 1 >= a.texcoords.size()) {
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
  project_uvs(m, projection);
  return m;
}

}  // namespace texsim
