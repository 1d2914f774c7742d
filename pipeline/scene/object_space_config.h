#pragma once
// The settings of the object-space pipeline variant (docs/derivations/object-space.md) and their
// reading from a material's `object_space` effect table (docs/scenes.md):
//   object_space = { max_step_px = 0.75, band_ratio = 2.0, max_samples = 4e8, lanes = 1 }
// The scene reads the table (the texture unit has nothing to build for it); the object-space
// pipeline (pipeline/raster/object_space_pipeline.h) runs the material's polygons.
#include "blocks/geometry/polygon_rotation.h"
#include "blocks/geometry/sample_projection.h"
#include "blocks/raster/object_space_raster.h"
#include "blocks/raster/splat_resolve.h"

namespace texsim {

class ConfigReader;

struct ObjectSpaceConfig {
  ObjectSpaceRaster::Config raster;
  SplatResolve::Config splat;
  PolygonRotation::Config rotation;
  SampleProjection::Config projection;
  double band_ratio = 2.0;   // far/near depth ratio of a band at most (0: never split)
  double max_samples = 4e8;  // per frame: more is an InputError (a polygon too dense to walk)

  // Keys: max_step_px (the sample-density factor s of the hole-free rule, (0, 4]), band_ratio
  // (0 or (1, 1e6]), max_samples ([1, 1e12]), lanes (1..64, every block of the variant).
  static ObjectSpaceConfig from_toml(const ConfigReader& r);
};

}  // namespace texsim
