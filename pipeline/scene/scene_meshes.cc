#include "pipeline/scene/scene_meshes.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/geometry/aviation_camera.h"
#include "pipeline/scene/mesh.h"
#include "pipeline/scene/obj_loader.h"
#include "pipeline/scene/scene_memory.h"
#include "pipeline/scene/scene_values.h"

namespace texsim {

namespace {

std::string at(const std::string& src, const toml::node& n) { return source_at(src, n); }

// Per face: the scene's primitive and two projections of it (the run's and the generator's).
constexpr uint64_t kBytesPerFace = sizeof(ScenePrimitive) + 2 * kPlaneProjectionBytes;
// Placed vertices beyond this magnitude overflow the projections' products.
constexpr double kMaxWorldCoordinate = 1e15;

}  // namespace

int read_material(const Scene& s, const ConfigReader& r) {
  const toml::node* n = r.table().get("material");
  if (!n || !n->is_string()) r.fail("material", "expected a material name");
  const std::string name = *n->value<std::string>();
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return static_cast<int>(i);
  throw InputError(at(s.path, *n), "unknown material '" + name + "'");
}

MeshBudget scene_mesh_budget(const Scene& s) {
  MeshBudget b;
  b.bytes_per_triangle = kBytesPerFace;
  b.max_triangles = kMaxScenePrimitives - std::min(s.primitives.size(), kMaxScenePrimitives);
  const uint64_t used = sat_mul(s.primitives.size(), kBytesPerFace);
  const uint64_t limit = scene_memory_limit();
  b.max_bytes = used >= limit ? 0 : limit - used;
  return b;
}

MeshPlacement read_placement(const ConfigReader& r) {
  MeshPlacement pl;
  pl.position = read_vec<3>(r, "position", pl.position);
  const glm::dvec3 rot = read_vec<3>(r, "rotation", glm::dvec3(0));
  pl.rotation = aviation_rotation(rot.x, rot.y, rot.z);
  pl.scale = r.get_double("scale", 1);
  if (!(pl.scale > 0) || !std::isfinite(pl.scale)) r.fail("scale", "must be a finite number > 0");
  pl.uv_scale = read_vec<2>(r, "uv_scale", glm::dvec2(1));
  pl.cull = r.get_choice("cull", 0, {"none", "back"}) == 1;
  return pl;
}

void append_mesh(const Mesh& mesh, const MeshPlacement& pl, const std::vector<int>* materials,
                 SceneMesh sm, const toml::node& e, Scene& s) {
  if (s.primitives.size() + mesh.triangles.size() > kMaxScenePrimitives) {
    throw InputError(at(s.path, e), sm.source + ": the scene would hold more than " +
                                        std::to_string(kMaxScenePrimitives) + " primitives");
  }
  std::vector<glm::dvec3> world(mesh.positions.size());
  for (size_t i = 0; i < world.size(); ++i) {
    world[i] = pl.apply(mesh.positions[i]);
    for (int k = 0; k < 3; ++k) {
      if (!(std::fabs(world[i][k]) <= kMaxWorldCoordinate)) {
        throw InputError(at(s.path, e), sm.source + ": vertex " + std::to_string(i + 1) +
                                            " placed at a coordinate beyond ±1e15 (position, "
                                            "scale and the mesh's coordinates together)");
      }
    }
  }
  s.primitives.reserve(s.primitives.size() + mesh.triangles.size());
  sm.first = s.primitives.size();
  sm.vertices = world.size();
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    const MeshTriangle& t = mesh.triangles[i];
    ScenePrimitive p;
    p.shape = ScenePrimitive::Shape::Triangle;
    p.material = materials ? (*materials)[i] : sm.material;
    p.origin = world[static_cast<size_t>(t.v[0])];
    p.edge_u = world[static_cast<size_t>(t.v[1])] - p.origin;
    p.edge_v = world[static_cast<size_t>(t.v[2])] - p.origin;
    p.uv_origin = t.uv[0] * pl.uv_scale;
    p.uv_edge_u = (t.uv[1] - t.uv[0]) * pl.uv_scale;
    p.uv_edge_v = (t.uv[2] - t.uv[0]) * pl.uv_scale;
    p.cull_back = pl.cull;
    p.mesh = static_cast<int>(s.meshes.size());
    s.primitives.push_back(p);
  }
  sm.count = s.primitives.size() - sm.first;
  s.meshes.push_back(std::move(sm));
}

namespace {

Mesh build_grid(const ConfigReader& r, const Scene& s) {
  const glm::dvec2 size = read_vec<2>(r, "size", glm::dvec2(1));
  const glm::dvec2 cells = read_vec<2>(r, "cells", glm::dvec2(1));
  if (!(size.x > 0 && size.y > 0)) r.fail("size", "must be > 0");
  for (int i = 0; i < 2; ++i) {
    if (!(cells[i] >= 1 && cells[i] <= 1024 && cells[i] == std::floor(cells[i])))
      r.fail("cells", "must be whole numbers in 1..1024");
  }
  const auto nx = static_cast<uint64_t>(cells.x), ny = static_cast<uint64_t>(cells.y);
  const MeshBudget b = scene_mesh_budget(s);
  const uint64_t bytes = mesh_bytes((nx + 1) * (ny + 1), 0, 2 * nx * ny, b);
  if (bytes > b.max_bytes) {
    r.fail("cells", "a grid of " + std::to_string(nx) + " x " + std::to_string(ny) +
                        " cells would take an estimated " + std::to_string(bytes >> 20) +
                        " MiB, over the memory limit (--max-memory) with the faces before it");
  }
  return make_grid(static_cast<int>(nx), static_cast<int>(ny), size);
}

Mesh build_mesh(const ConfigReader& r, const Scene& s, const std::string& source,
                UvProjection proj) {
  if (source == "box") {
    if (r.table().contains("cells")) r.fail("cells", "grid only");
    const glm::dvec3 size = read_vec<3>(r, "size", glm::dvec3(1));
    if (!(size.x > 0 && size.y > 0 && size.z > 0)) r.fail("size", "must be > 0");
    return make_box(size);
  }
  if (source == "grid") return build_grid(r, s);
  for (const char* k : {"size", "cells"}) {
    if (r.table().contains(k)) r.fail(k, "box and grid only");
  }
  return load_obj(source, s.base_dir, proj, scene_mesh_budget(s));
}

void parse_mesh(const toml::node& e, Scene& s) {
  if (!e.is_table()) throw InputError(at(s.path, e), "meshes: each entry must be a table");
  const ConfigReader r(*e.as_table(), s.path, "meshes[" + std::to_string(s.meshes.size()) + "]");
  r.reject_unknown({"material", "source", "uv", "size", "cells", "position", "rotation", "scale",
                    "uv_scale", "cull"});
  SceneMesh sm;
  sm.material = read_material(s, r);
  sm.source = r.get_string("source", "");
  if (sm.source.empty()) r.fail("source", "expected \"box\", \"grid\" or an OBJ file");
  static const std::vector<std::string_view> kUv = {"file", "planar", "box", "spherical"};
  const int uv = r.get_choice("uv", 0, kUv);
  sm.uv = std::string(kUv[static_cast<size_t>(uv)]);
  const UvProjection proj = uv == 0   ? UvProjection::None
                            : uv == 1 ? UvProjection::Planar
                            : uv == 2 ? UvProjection::Box
                                      : UvProjection::Spherical;
  Mesh mesh = build_mesh(r, s, sm.source, proj);
  project_uvs(mesh, proj);  // procedural meshes carry their own; a projection replaces them
  const MeshPlacement pl = read_placement(r);
  append_mesh(mesh, pl, nullptr, std::move(sm), e, s);
}

}  // namespace

void parse_meshes(const toml::table& root, Scene& s) {
  const toml::node* mn = root.get("meshes");
  if (!mn) return;
  const toml::array* arr = mn->as_array();
  if (!arr) throw InputError(at(s.path, *mn), "meshes: expected an array of tables ([[meshes]])");
  for (const toml::node& e : *arr) parse_mesh(e, s);
}

}  // namespace texsim
