#pragma once
// Drawing a scene whose materials compute their own texture coordinates (material table
// `coords`, docs/scenes.md): planes are drawn one after another, each as the screen triangles
// of its near-clipped parallelogram. A material's coordinate unit walks each triangle in its
// own traversal order; the depth test comes after the front end and keeps the nearest plane
// per pixel, so occluded pixels cost front-end cycles and operations but nothing further.
#include <functional>
#include <vector>

#include "pipeline/geometry/plane_projection.h"
#include "pipeline/scene/scene.h"
#include "pipeline/texture/coord_method.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {

// A plane's screen triangles (a fan of its near-clipped polygon, rows clipped to the image)
// with its map in pixel-index coordinates and texels of a tw x th texture: q normalised to
// (0.5, 1] over the polygon, and the map translated by whole texture periods (wrap: tw,
// mirror: 2·tw; none for clamp) so that coordinates start near 0 whatever the plane's
// uv_offset. `rebase_u`, `rebase_v` (texels) is that translation.
struct PlaneTriangles {
  std::vector<CoordTriangle> tris;
  ProjectiveMap map;
  long double rebase_u = 0, rebase_v = 0;
};
PlaneTriangles plane_triangles(const PlaneProjection& proj, int width, int height, int tw, int th,
                               AddressMode au, AddressMode av);

// Draws the scene's planes in order through `unit` (frame 0) and calls
// `emit(fragment, material, colour)` for every pixel that a plane's triangles cover and that
// plane is nearest at; `colour` is null when the coordinate unit rejected the pixel's
// coordinates (the pixel is not textured). Materials without a coordinate unit take the
// reference generator's exact coordinates and derivatives.
void draw_scene_front_end(const Scene& scene, const std::vector<PlaneProjection>& maps,
                          TextureUnit& unit,
                          const std::function<void(const Fragment&, int, const Rgba*)>& emit);

// Where the front end's fragments go when they are not textured by `unit` itself (several
// texture units: each fragment to the unit of its tile). `unit` still runs the coordinate
// units (generate_coords) and gives the materials and textures.
struct FrontEndTarget {
  // A fragment to texture; `front`: its front-end costs (null for exact coordinates).
  std::function<void(const Fragment& f, int material, const ItemCost* front)> texture;
  // A generated fragment that leaves after the front end at pixel (x, y) (x < 0: off the
  // image): occluded, covered twice, or (`rejected`) its coordinates rejected.
  std::function<void(int material, const ItemCost* front, bool rejected, int32_t x, int32_t y)>
      drop;
  // A pixel left untextured (its coordinates rejected), after its drop.
  std::function<void(const Fragment& f, int material)> untextured;
};
void draw_scene_front_end(const Scene& scene, const std::vector<PlaneProjection>& maps,
                          TextureUnit& unit, const FrontEndTarget& target);

}  // namespace texsim
