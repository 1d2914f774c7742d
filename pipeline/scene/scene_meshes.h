#pragma once
// [[meshes]] entries of a scene (docs/scenes.md): an OBJ file or a procedural box or grid,
// placed by position, aviation-angle rotation and scale, with texture coordinates from the
// mesh or a declared projection; each face becomes one triangle primitive of the scene.
#include <toml++/toml.h>

#include <glm/mat3x3.hpp>
#include <vector>

#include "blocks/base/config_reader.h"
#include "pipeline/scene/mesh.h"
#include "pipeline/scene/obj_loader.h"
#include "pipeline/scene/scene.h"

namespace texsim {

// Appends every mesh's faces to s.primitives (after the planes) and the meshes to s.meshes.
// Throws InputError naming file:line:column of the entry, or FILE:LINE of the OBJ file.
void parse_meshes(const toml::table& root, Scene& s);

// The model transform of a [[meshes]] or [[models]] entry: p' = position + A·(scale·p), A from
// aviation angles (degrees), with the entry's uv_scale and culling.
struct MeshPlacement {
  glm::dvec3 position{0};
  glm::dmat3 rotation{1.0};
  double scale = 1;
  glm::dvec2 uv_scale{1};
  bool cull = false;
  glm::dvec3 apply(const glm::dvec3& p) const { return position + rotation * (scale * p); }
};
// Reads position, rotation, scale, uv_scale and cull of an entry.
MeshPlacement read_placement(const ConfigReader& r);
// The entry's `material`: an index into s.materials, or an error naming the entry.
int read_material(const Scene& s, const ConfigReader& r);
// What the scene's faces so far leave of the memory limit for the next mesh.
MeshBudget scene_mesh_budget(const Scene& s);
// Places `mesh` and appends its faces to s.primitives and `sm` to s.meshes; each face takes
// sm.material, or (*materials)[face] when given. `e` (the entry) locates errors.
void append_mesh(const Mesh& mesh, const MeshPlacement& pl, const std::vector<int>* materials,
                 SceneMesh sm, const toml::node& e, Scene& s);

// Faces a scene may hold in all: bounds memory (a primitive's projection is ~1 KB).
constexpr size_t kMaxScenePrimitives = size_t{1} << 22;
// Bytes the run's memory estimate reserves for one PlaneProjection (pipeline/geometry, a layer
// above this one): plane_projection.cc asserts that the type fits.
constexpr size_t kPlaneProjectionBytes = 1024;

}  // namespace texsim
