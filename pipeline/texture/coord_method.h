#pragma once
// Texture-coordinate and derivative generation selectable by name (method × number format):
// the front end of the texture unit as the study and scenes instantiate it. Each generator
// runs one coordinate block (blocks/uv_*) or derivative block (blocks/derivatives_*) over the
// pixels of a screen triangle and reports, per fragment, the value, the ops and the cost in
// its pipeline stage (docs/studies/study-coords.md).
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "blocks/base/op_counts.h"
#include "blocks/base/tech_table.h"
#include "blocks/geometry/near_clipper.h"
#include "blocks/geometry/projective_map.h"
#include "blocks/raster/raster_types.h"
#include "blocks/texture/derivs/ellipse_setup.h"
#include "pipeline/kernel/clocked_pipeline.h"

namespace texsim {

class ConfigReader;

// A screen triangle to texture: its map (normalised: q <= 1 on its pixels), its vertices
// (pixel-index coordinates: the centre of pixel i is x = i) and the pixels it covers, as
// raster rows.
struct CoordTriangle {
  ProjectiveMap map;
  double x[3] = {0, 0, 0};
  double y[3] = {0, 0, 0};
  std::vector<RowSpan> rows;
};

// The pixels of [0,w)×[0,h) the screen triangle (x[i], y[i]) covers, as raster rows: the
// edge-function rasteriser (top-left rule, 8 sub-pixel bits) behind the guard-band clipper.
std::vector<RowSpan> triangle_rows(const double x[3], const double y[3], int32_t w, int32_t h);

struct CoordFragment {
  int32_t x = 0, y = 0;
  CoordSample uv;
};

struct CoordGeneratorStats {
  uint64_t fragments = 0;
  uint64_t rows = 0;       // set-ups of rows (or constant-depth lines)
  uint64_t triangles = 0;  // set-ups of triangles
  uint64_t divisions = 0;  // div + rcp operations (the seed's "divisions")
};

// Number formats every generator supports: "float", "double" and the fixed-point widths below.
const std::vector<std::string>& coord_format_names();

class CoordGenerator {
 public:
  virtual ~CoordGenerator() = default;
  // Methods: heckbert, heckbert-rcp, incremental, incremental-k4, incremental-bidir,
  // incremental-direct, affine, quadratic, cubic, biquadratic, bicubic, constant-depth, affine-16
  // and quadratic-32 (the row cut into 16- / 32-pixel segments, each with its own polynomial).
  // Throws InputError naming the unknown method or format.
  static std::unique_ptr<CoordGenerator> create(const std::string& method,
                                                const std::string& format,
                                                Datapath datapath = Datapath::Spatial);
  static const std::vector<std::string>& method_names();

  virtual const std::string& method() const = 0;
  virtual const std::string& format() const = 0;
  // The generator's stage in a clocked pipeline: per-pixel timing of its block; row and
  // triangle set-ups come as ItemCost::extra_ii on the first pixel of each.
  virtual StageConfig stage(const TechTable& t) const = 0;
  // Operations per pixel of the block, set-ups excluded.
  virtual OpCounts pixel_ops() const = 0;
  // Generates the triangle's fragments in the method's traversal order (rows, or
  // constant-depth lines), appending them to `out` and their cost in this stage to `costs`;
  // adds the operations to `ops`.
  virtual void generate(const CoordTriangle& tri, const TechTable& t,
                        std::vector<CoordFragment>& out, std::vector<ItemCost>& costs,
                        OpCounts& ops, CoordGeneratorStats& stats) const = 0;
};

class DerivGenerator {
 public:
  virtual ~DerivGenerator() = default;
  // Methods: analytic, quad, heckbert-fd (classic), accelerated-fd, iterative.
  static std::unique_ptr<DerivGenerator> create(const std::string& method,
                                                const std::string& format,
                                                Datapath datapath = Datapath::Spatial);
  static const std::vector<std::string>& method_names();

  virtual const std::string& method() const = 0;
  virtual const std::string& format() const = 0;
  virtual StageConfig stage(const TechTable& t) const = 0;
  virtual OpCounts pixel_ops() const = 0;  // per pixel, set-ups excluded
  // Derivatives of every covered pixel in raster-row order (tri.rows), with costs and ops as
  // CoordGenerator::generate. The quad method charges its helper pixels' coordinates
  // (incremental adder ops) in `ops`.
  virtual void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordDerivs>& out,
                        std::vector<ItemCost>& costs, OpCounts& ops) const = 0;
};

// The ellipse set-up of one number format (determinant or AC - B²/4 form).
class EllipseGenerator {
 public:
  virtual ~EllipseGenerator() = default;
  // form: "determinant" or "ac-b2".
  static std::unique_ptr<EllipseGenerator> create(const std::string& form,
                                                  const std::string& format,
                                                  Datapath datapath = Datapath::Spatial);
  virtual StageConfig stage(const TechTable& t) const = 0;
  virtual OpCounts pixel_ops() const = 0;
  virtual EllipseCoeffs eval(const CoordDerivs& d) const = 0;
};

// Per-material selection: the coordinate method, derivative method, ellipse form and number
// format of a material's texture front end, and the fragments it produces.
struct CoordUnitConfig {
  std::string coords = "incremental";
  std::string derivs = "analytic";  // or "none"
  std::string format = "float";
  Datapath datapath = Datapath::Spatial;
  // The method's blocks as their own Config::from_toml read the material's table, in any
  // number format; unset: the method's blocks with their defaults and `datapath`.
  std::function<std::unique_ptr<CoordGenerator>(const std::string& format)> coord_block;
  std::function<std::unique_ptr<DerivGenerator>(const std::string& format)> deriv_block;
  // A material's `coords` table: keys method, derivs, format, datapath, and the coordinate
  // block's own keys (e.g. lanes of incremental-k4), read by that block's Config::from_toml.
  // Unknown keys and names are InputErrors naming the file, line, block and key.
  static CoordUnitConfig from_toml(const ConfigReader& r);
};

struct CoordUnitFragment {
  int32_t x = 0, y = 0;
  CoordSample uv;
  CoordDerivs d;  // valid = false when derivs = "none" or rejected
};

class CoordUnit {
 public:
  explicit CoordUnit(const CoordUnitConfig& c);  // throws InputError on unknown names
  const CoordUnitConfig& config() const { return cfg_; }
  // Pipeline stages of this front end (coordinates, then derivatives if any).
  std::vector<StageConfig> stages(const TechTable& t) const;
  // Fragments of a triangle in the coordinate method's traversal order; `costs` gets one
  // ItemCost per fragment per stage (stage-major within each fragment: costs[i*S + s]).
  // Operations go to `coord_ops` (coordinate block) and `deriv_ops` (derivative block).
  void generate(const CoordTriangle& tri, const TechTable& t, std::vector<CoordUnitFragment>& out,
                std::vector<ItemCost>& costs, OpCounts& coord_ops, OpCounts& deriv_ops) const;
  bool has_derivs() const { return derivs_ != nullptr; }

 private:
  CoordUnitConfig cfg_;
  std::unique_ptr<CoordGenerator> coords_;
  std::unique_ptr<DerivGenerator> derivs_;
};

}  // namespace texsim
