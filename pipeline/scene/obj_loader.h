#pragma once
// Wavefront OBJ meshes through the packaged tinyobjloader (double precision). texsim reads the
// file itself (read_input_file: a regular file within kMaxObjBytes), makes every line end in
// '\n' (so "\r\n" and a lone '\r' end a line for texsim's checks and the library alike), and
// checks the text first for what the library lets through silently — non-finite or huge
// numbers ("nan" parses as 0), indices out of range (vertex, texture and normal), faces with
// fewer than 3 or more than 255 corners (the library keeps the count in one byte) — so every
// error names the file and line. The library then parses the same text from a stream, its
// `mtllib` files opened through read_input_file too, and what it returns is checked against
// the scan. Polygons are split into fans of triangles. docs/cli.md#input-limits lists the
// limits below.
#include <cstdint>
#include <string>

#include "pipeline/scene/mesh.h"

namespace texsim {

inline constexpr uint64_t kMaxObjBytes = uint64_t{256} << 20;  // the OBJ file
inline constexpr long kMaxObjElements = long{1} << 24;         // v, vt and vn lines each; faces
inline constexpr int kMaxObjCorners = 255;                     // corners of one face
inline constexpr double kMaxObjCoordinate = 1e12;              // |x|, |y|, |z| of a vertex
inline constexpr double kMaxObjTexcoord = 1e6;                 // |u|, |v| of a texture coordinate

// What a caller will hold per mesh triangle beyond the mesh, and its memory limit: load_obj
// refuses a file whose counts (from the scan, before the library allocates) exceed them.
struct MeshBudget {
  uint64_t max_bytes = UINT64_MAX;
  uint64_t bytes_per_triangle = 0;  // e.g. the scene's primitive and its projections
  uint64_t max_triangles = UINT64_MAX;
};

// Bytes a mesh of these counts takes while it is loaded and placed (saturating).
uint64_t mesh_bytes(uint64_t vertices, uint64_t corners, uint64_t triangles,
                    const MeshBudget& budget);

// `path` relative to `base_dir` unless absolute. With `projection` None every face corner
// must have a texture coordinate (`f v/vt`); otherwise the projection supplies them all.
// Throws InputError "FILE:LINE: what" (or "FILE: what" for the file as a whole).
Mesh load_obj(const std::string& path, const std::string& base_dir, UvProjection projection,
              const MeshBudget& budget = {});
// The same from OBJ text already read (`file` names it in errors, `base_dir` is where its
// `mtllib` files are): the fuzz harness's entry.
Mesh parse_obj(std::string text, const std::string& file, const std::string& base_dir,
               UvProjection projection, const MeshBudget& budget = {});

}  // namespace texsim
