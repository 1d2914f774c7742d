#include "pipeline/scene/scene_meshes.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "blocks/base/config_reader.h"
#include "blocks/base/input_error.h"
#include "blocks/geometry/aviation_camera.h"
#include "pipeline/scene/mesh.h"
#include "pipeline/scene/obj_loader.h"
#include "pipeline/scene/scene_values.h"

namespace texsim {

namespace {

std::string at(const std::string& src, const toml::node& n) { return source_at(src, n); }

int material_of(const Scene& s, const ConfigReader& r) {
  const toml::node* n = r.table().get("material");
  if (!n || !n->is_string()) r.fail("material", "expected a material name");
  const std::string name = *n->value<std::string>();
  for (size_t i = 0; i < s.materials.size(); ++i)
    if (s.materials[i].name == name) return static_cast<int>(i);
  throw InputError(at(s.path, *n), "unknown material '" + name + "'");
}

Mesh build_mesh(const ConfigReader& r, const Scene& s, const std::string& source,
                UvProjection proj) {
  if (source == "box") {
    if (r.table().contains("cells")) r.fail("cells", "grid only");
    const glm::dvec3 size = read_vec<3>(r, "size", glm::dvec3(1));
    if (!(size.x > 0 && size.y > 0 && size.z > 0)) r.fail("size", "must be > 0");
    return make_box(size);
  }
  if (source == "grid") {
    const glm::dvec2 size = read_vec<2>(r, "size", glm::dvec2(1));
    const glm::dvec2 cells = read_vec<2>(r, "cells", glm::dvec2(1));
    if (!(size.x > 0 && size.y > 0)) r.fail("size", "must be > 0");
    for (int i = 0; i < 2; ++i) {
      if (!(cells[i] >= 1 && cells[i] <= 1024 && cells[i] == std::floor(cells[i])))
        r.fail("cells", "must be whole numbers in 1..1024");
    }
    return make_grid(static_cast<int>(cells.x), static_cast<int>(cells.y), size);
  }
  for (const char* k : {"size", "cells"}) {
    if (r.table().contains(k)) r.fail(k, "box and grid only");
  }
  return load_obj(source, s.base_dir, proj);
}

// The model transform: p' = position + A·(scale·p), A from aviation angles (degrees).
struct Placement {
  glm::dvec3 position{0};
  glm::dmat3 rotation{1.0};
  double scale = 1;
  glm::dvec3 apply(const glm::dvec3& p) const { return position + rotation * (scale * p); }
};

Placement placement(const ConfigReader& r) {
  Placement pl;
  pl.position = read_vec<3>(r, "position", pl.position);
  const glm::dvec3 rot = read_vec<3>(r, "rotation", glm::dvec3(0));
  pl.rotation = aviation_rotation(rot.x, rot.y, rot.z);
  pl.scale = r.get_double("scale", 1);
  if (!(pl.scale > 0) || !std::isfinite(pl.scale)) r.fail("scale", "must be a finite number > 0");
  return pl;
}

void parse_mesh(const toml::node& e, Scene& s) {
  if (!e.is_table()) throw InputError(at(s.path, e), "meshes: each entry must be a table");
  const ConfigReader r(*e.as_table(), s.path, "meshes[" + std::to_string(s.meshes.size()) + "]");
  r.reject_unknown({"material", "source", "uv", "size", "cells", "position", "rotation", "scale",
                    "uv_scale", "cull"});
  SceneMesh sm;
  sm.material = material_of(s, r);
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
  const Placement pl = placement(r);
  const glm::dvec2 uv_scale = read_vec<2>(r, "uv_scale", glm::dvec2(1));
  const bool cull = r.get_choice("cull", 0, {"none", "back"}) == 1;
  if (s.primitives.size() + mesh.triangles.size() > kMaxScenePrimitives) {
    throw InputError(at(s.path, e), sm.source + ": the scene would hold more than " +
                                        std::to_string(kMaxScenePrimitives) + " primitives");
  }
  std::vector<glm::dvec3> world(mesh.positions.size());
  for (size_t i = 0; i < world.size(); ++i) world[i] = pl.apply(mesh.positions[i]);
  sm.first = s.primitives.size();
  sm.vertices = world.size();
  for (const MeshTriangle& t : mesh.triangles) {
    ScenePrimitive p;
    p.shape = ScenePrimitive::Shape::Triangle;
    p.material = sm.material;
    p.origin = world[static_cast<size_t>(t.v[0])];
    p.edge_u = world[static_cast<size_t>(t.v[1])] - p.origin;
    p.edge_v = world[static_cast<size_t>(t.v[2])] - p.origin;
    p.uv_origin = t.uv[0] * uv_scale;
    p.uv_edge_u = (t.uv[1] - t.uv[0]) * uv_scale;
    p.uv_edge_v = (t.uv[2] - t.uv[0]) * uv_scale;
    p.cull_back = cull;
    p.mesh = static_cast<int>(s.meshes.size());
    s.primitives.push_back(p);
  }
  sm.count = s.primitives.size() - sm.first;
  s.meshes.push_back(std::move(sm));
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
