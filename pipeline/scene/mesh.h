#pragma once
// Triangle meshes for scenes: loaded from OBJ (obj_loader.h) or built procedurally (boxes and
// grids), with texture coordinates from the file or from a declared projection. Positions and
// coordinates are double; every value is finite (the builders and the loader check it).
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <vector>

namespace texsim {

// How a mesh without texture coordinates gets them. None: the mesh must carry its own.
enum class UvProjection { None, Planar, Box, Spherical };
const char* to_string(UvProjection p);

struct MeshTriangle {
  int v[3] = {0, 0, 0};  // indices into Mesh::positions
  glm::dvec2 uv[3];      // texture coordinates of the three corners (normalised, 1 = a width)
  int line = 0;          // line of the face in the source file (0: procedural)
};

struct Mesh {
  std::string source;  // file path, or "procedural:box" / "procedural:grid"
  std::vector<glm::dvec3> positions;
  std::vector<MeshTriangle> triangles;
  bool has_uvs = false;  // every corner has a texture coordinate
};

// An axis-aligned box centred on the origin, 12 triangles wound counter-clockwise seen from
// outside, each face mapped to the whole [0,1]² texture.
Mesh make_box(const glm::dvec3& size);
// An nx × ny grid of quads in the x-z plane (y = 0), centred on the origin, 2·nx·ny triangles
// facing +y, texture coordinates spanning [0,1]² over the grid.
Mesh make_grid(int nx, int ny, const glm::dvec2& size);

// Replaces every corner's texture coordinate by the projection's, from the mesh's bounding
// box (docs/scenes.md gives the formulas):
// - Planar: onto the plane of the box's two largest extents, scaled to [0,1]²;
// - Box: each triangle onto the box face its normal points to most, scaled to [0,1]²;
// - Spherical: longitude and latitude around the box centre, u in [0,1] made continuous
//   across the seam within each triangle (so u may exceed 1 there), v in [0,1].
void project_uvs(Mesh& mesh, UvProjection p);

}  // namespace texsim
