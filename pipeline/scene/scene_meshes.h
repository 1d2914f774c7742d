#pragma once
// [[meshes]] entries of a scene (docs/scenes.md): an OBJ file or a procedural box or grid,
// placed by position, aviation-angle rotation and scale, with texture coordinates from the
// mesh or a declared projection; each face becomes one triangle primitive of the scene.
#include <toml++/toml.h>

#include "pipeline/scene/scene.h"

namespace texsim {

// Appends every mesh's faces to s.primitives (after the planes) and the meshes to s.meshes.
// Throws InputError naming file:line:column of the entry, or FILE:LINE of the OBJ file.
void parse_meshes(const toml::table& root, Scene& s);

// Faces a scene may hold in all: bounds memory (a primitive's projection is ~1 KB).
constexpr size_t kMaxScenePrimitives = size_t{1} << 22;
// Bytes the run's memory estimate reserves for one PlaneProjection (pipeline/geometry, a layer
// above this one): plane_projection.cc asserts that the type fits.
constexpr size_t kPlaneProjectionBytes = 1024;

}  // namespace texsim
