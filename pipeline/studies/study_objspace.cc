#include "pipeline/studies/study_objspace.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "blocks/base/config_reader.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/object_space_pipeline.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/studies/study_table.h"

namespace texsim {

namespace {

constexpr double kPi = 3.14159265358979323846;
const std::vector<std::string> kMethods = {"object-space", "trilinear", "vulkan", "ewa", "feline"};

std::string fmt(double v, int prec = 4) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", prec, v);
  return b;
}

TextureSet load_set(const Scene& scene) {
  TextureSet set;
  for (size_t i = 0; i < scene.textures.size(); ++i) set.add(load_scene_texture(scene, i));
  return set;
}

// The scene's materials filtered by `method` (screen space), each keeping its texture and
// address modes: trilinear; Vulkan probes (trilinear with aniso = "vulkan", 16:1); EWA; Feline.
std::vector<MaterialSetup> variant_materials(const std::vector<MaterialSetup>& base,
                                             const std::string& method) {
  std::vector<MaterialSetup> out;
  for (const MaterialSetup& m : base) {
    const std::string addr = std::string("address_u = \"") + to_string(m.address_u()) +
                             "\", address_v = \"" + to_string(m.address_v()) + "\"";
    std::string text;
    if (method == "ewa") {
      text = "ewa = { weight = \"lut\", max_aniso = 16, " + addr + " }\n";
    } else if (method == "feline") {
      text = "feline = { " + addr + " }\n";
    } else {
      text = "filter = { mode = \"trilinear\", " + addr + " }\n";
      if (method == "vulkan") text += "lod = { aniso = \"vulkan\", max_aniso = 16 }\n";
    }
    const toml::table t = parse_toml(text, "study objspace " + method);
    out.push_back(material_from_toml(m.name, m.texture, t, "study objspace " + method));
  }
  return out;
}

struct ScreenRun {
  std::vector<Rgba> image;
  std::vector<int32_t> prim;  // the primitive kept at each pixel, -1: none
  uint64_t fragments = 0, cycles = 0, texels = 0, dram_bytes = 0;
  OpCounts ops;
};

ScreenRun run_screen(const Scene& scene, TextureSet& set, const std::vector<MaterialSetup>& mats) {
  const size_t n = static_cast<size_t>(scene.width) * static_cast<size_t>(scene.height);
  ScreenRun r;
  r.image.assign(n, Rgba(0));
  r.prim.assign(n, -1);
  TextureUnit unit(set, mats, PipelineSetup{}, scene.tech, true);
  std::vector<RasterCounters> raster;
  generate_fragments(
      scene, 0,
      [&](const Fragment& f) {
        const int m = scene.primitives[f.prim].material;
        const size_t at = static_cast<size_t>(f.y) * static_cast<size_t>(scene.width) + f.x;
        r.image[at] = unit.process(f, m);
        r.prim[at] = static_cast<int32_t>(f.prim);
      },
      &raster, &mats);
  unit.check_timing_invariants();
  r.fragments = unit.fragments();
  uint64_t raster_cycles = 0;
  for (const RasterCounters& c : raster) {
    raster_cycles += c.cycles;
    r.ops += c.ops;
  }
  // The rasteriser and the texture unit run as one pipeline: the slower one sets the frame.
  r.cycles = std::max(unit.cycles(), raster_cycles);
  for (const BlockUse& b : unit.blocks()) {
    if (b.name == "cache") continue;
    r.ops += b.ops;
    r.texels += b.texels;
  }
  r.dram_bytes = unit.memory().dram_totals().bytes;
  return r;
}

ImageRgb reference_image(const Scene& scene, const TextureSet& set,
                         const std::vector<MaterialSetup>& mats, const std::vector<int32_t>& prim,
                         int n) {
  ImageRgb ref(scene.width, scene.height, scene.background);
  std::map<int32_t, PlaneProjection> maps;
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const int32_t p = prim[static_cast<size_t>(y) * static_cast<size_t>(scene.width) + x];
      if (p < 0) continue;
      auto it = maps.find(p);
      if (it == maps.end())
        it =
            maps.emplace(p, PlaneProjection(scene, scene.primitives[static_cast<size_t>(p)])).first;
      const MaterialSetup& m =
          mats[static_cast<size_t>(scene.primitives[static_cast<size_t>(p)].material)];
      ref.set(x, y,
              glm::vec4(ground_truth_exact(set[m.texture], m.address_u(), m.address_v(), it->second,
                                           x, y, n)));
    }
  }
  return ref;
}

// The colours of the pixels the screen-space coverage holds, as an image.
ImageRgb masked_image(const Scene& scene, const std::vector<Rgba>& colours,
                      const std::vector<int32_t>& prim) {
  ImageRgb img(scene.width, scene.height, scene.background);
  for (int y = 0; y < scene.height; ++y) {
    for (int x = 0; x < scene.width; ++x) {
      const size_t at = static_cast<size_t>(y) * static_cast<size_t>(scene.width) + x;
      if (prim[at] >= 0) img.set(x, y, colours[at]);
    }
  }
  return img;
}

// Reference | object space | trilinear | EWA, side by side.
void write_side_by_side(const std::string& path, const std::vector<const ImageRgb*>& imgs) {
  const int w = imgs[0]->width, h = imgs[0]->height;
  ImageRgb out(w * static_cast<int>(imgs.size()), h, glm::dvec3(imgs[0]->background));
  for (size_t k = 0; k < imgs.size(); ++k) {
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t at = static_cast<size_t>(y) * static_cast<size_t>(w) + x;
        const glm::vec4 c(imgs[k]->rgb[at * 3], imgs[k]->rgb[at * 3 + 1], imgs[k]->rgb[at * 3 + 2],
                          1);
        out.set(static_cast<int>(k) * w + x, y, c);
      }
    }
  }
  write_image(path, out);
}

struct SceneCase {
  std::string sweep, name;
  Scene scene;
  double tilt = -1, area = 0;
  std::string image;   // side-by-side image file ("" for none)
  double step = 0.75;  // object space's max_step_px
  double band_ratio = ObjectSpaceConfig{}.band_ratio;
  int lanes = 1;       // object space's lanes per block
  bool screen = true;  // false: object space only (the screen-space rows are another case's)
};

// The area of object space's four blocks at a configuration (the texture unit aside).
double object_space_area(const ObjectSpaceConfig& cfg, const TechTable& t) {
  return PolygonRotation(cfg.rotation).timing(t).area +
         ObjectSpaceRaster(cfg.raster).timing(t).area +
         SampleProjection(cfg.projection).timing(t).area + SplatResolve(cfg.splat).timing(t).area;
}

// Every method on one scene: one row each.
void measure_case(const SceneCase& sc, const ObjspaceStudyOptions& opt, const std::string& dir,
                  std::vector<ObjspaceRow>& rows, std::ostream& log) {
  const Scene& scene = sc.scene;
  TextureSet set = load_set(scene);
  const std::vector<MaterialSetup> base = build_materials(scene);
  std::vector<ImageRgb> images;
  ImageRgb ref(1, 1, glm::dvec3(0));
  std::vector<int32_t> prim;
  ObjspaceRow proto;
  proto.sweep = sc.sweep;
  proto.scene = sc.name;
  proto.width = scene.width;
  proto.height = scene.height;
  proto.tilt_deg = sc.tilt;
  proto.area = sc.area;
  proto.step_px = sc.step;
  proto.band_ratio = sc.band_ratio;
  proto.lanes = sc.lanes;
  proto.primitives = scene.primitives.size();
  // Screen space first: its coverage defines the pixels compared and the reference.
  std::vector<ObjspaceRow> screen_rows;
  for (size_t k = 1; k < kMethods.size(); ++k) {
    if (!sc.screen && k > 1) break;  // the first run still gives the coverage and reference
    const ScreenRun s = run_screen(scene, set, variant_materials(base, kMethods[k]));
    if (k == 1) {
      prim = s.prim;
      ref = reference_image(scene, set, base, prim, opt.reference_supersamples);
    }
    ObjspaceRow r = proto;
    r.method = kMethods[k];
    r.items = s.fragments;
    r.cycles = s.cycles;
    r.ops = s.ops;
    r.texels = s.texels;
    r.dram_bytes = s.dram_bytes;
    images.push_back(masked_image(scene, s.image, prim));
    r.acc = compare_images(images.back(), ref);
    r.pixels = r.acc.pixels;
    screen_rows.push_back(r);
  }
  ObjectSpaceConfig cfg;
  cfg.raster.max_step_px = sc.step;
  cfg.band_ratio = sc.band_ratio;
  cfg.raster.lanes = cfg.splat.lanes = cfg.rotation.lanes = cfg.projection.lanes = sc.lanes;
  const ObjectSpaceResult o = render_object_space(scene, set, base, PipelineSetup{}, cfg);
  ObjspaceRow r = proto;
  r.method = kMethods[0];
  r.items = o.samples;
  r.cycles = o.cycles;
  r.ops = o.total_ops();
  r.texels = o.texels;
  r.dram_bytes = o.dram_bytes;
  r.buffer_bytes = o.buffer_bytes();
  r.holes = o.resolve.holes;
  r.bands = o.bands;
  r.block_area = object_space_area(cfg, scene.tech);
  r.texture_cycles = o.texture_cycles;
  r.lane_cycles = std::max({o.raster_cycles, o.projection_cycles, o.splat_cycles});
  const ImageRgb oimg = masked_image(scene, o.image, prim);
  r.acc = compare_images(oimg, ref);
  r.pixels = r.acc.pixels;
  rows.push_back(r);
  if (sc.screen) {
    for (ObjspaceRow& s : screen_rows) rows.push_back(std::move(s));
  }
  if (opt.images && !sc.image.empty())
    write_side_by_side(dir + "/" + sc.image, {&ref, &oimg, &images[0], &images[2]});
  log << "  " << sc.sweep << " " << sc.name << " " << scene.width << "x" << scene.height
      << (sc.tilt >= 0 ? " tilt " + fmt(sc.tilt) : "") << ": " << scene.primitives.size()
      << " primitives, object space " << o.samples << " samples in " << o.bands << " bands, "
      << o.resolve.holes << " holes\n";
}

std::vector<std::string> size_overrides(int w) {
  return {"output.width=" + std::to_string(w), "output.height=" + std::to_string(w * 3 / 4)};
}

// A square of the given area centred on the view axis at depth 3, tilted about the screen's x
// axis (its top edge away from the eye) and turned 20° about the view axis, cut into n × n
// parallelograms (one primitive each); a checker of 16 × 16 cells over the whole square.
Scene square_scene(int size, double tilt_deg, double area, int n) {
  Scene sc = parse_scene("[output]\nwidth = " + std::to_string(size) +
                             "\nheight = " + std::to_string(size) +
                             "\nbackground = [0.0, 0.0, 0.0]\n[camera]\n"
                             "position = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\n"
                             "fov_y = 50.0\n[textures.t]\n"
                             "source = \"procedural:checker?size=256&cells=16\"\n"
                             "[materials.m]\ntexture = \"t\"\n"
                             "filter = { mode = \"trilinear\", address = \"wrap\" }\n",
                         "study objspace square", "");
  const double t = tilt_deg * kPi / 180, a = 20 * kPi / 180, s = std::sqrt(area);
  const glm::dvec3 ux{std::cos(a), std::sin(a), 0}, uy{-std::sin(a), std::cos(a), 0};
  const glm::dvec3 eu = ux * s, ev = (uy * std::cos(t) + glm::dvec3(0, 0, -1) * std::sin(t)) * s;
  const glm::dvec3 o = glm::dvec3(0, 0, -3) - eu * 0.5 - ev * 0.5;
  const double step = 1.0 / n;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      ScenePrimitive p;
      p.origin = o + eu * (i * step) + ev * (j * step);
      p.edge_u = eu * step;
      p.edge_v = ev * step;
      p.uv_origin = {i * step, j * step};
      p.uv_edge_u = {step, 0};
      p.uv_edge_v = {0, step};
      sc.primitives.push_back(p);
    }
  }
  return sc;
}

std::vector<SceneCase> study_cases(const ObjspaceStudyOptions& opt) {
  std::vector<SceneCase> cases;
  for (const int w : opt.widths) {
    const bool pic = w == 320;
    cases.push_back({"resolution", "floor", default_scene(size_overrides(w)), -1, 0,
                     pic ? "floor_side_by_side.png" : ""});
    if (opt.cube) {
      cases.push_back({"resolution", "cube",
                       load_scene(opt.scenes_dir + "/cube.toml", size_overrides(w)), -1, 0,
                       pic ? "cube_side_by_side.png" : ""});
    }
    if (opt.mesh) {
      cases.push_back({"resolution", "bunny",
                       load_scene(opt.scenes_dir + "/bunny.toml", size_overrides(w)), -1, 0,
                       pic ? "bunny_side_by_side.png" : ""});
    }
  }
  for (const double t : opt.tilts) {
    cases.push_back({"tilt", "square", square_scene(opt.tilt_size, t, 1, 1), t, 1,
                     t == 75 ? "square_tilt75_side_by_side.png" : ""});
  }
  for (const int n : opt.grid_cells)
    cases.push_back({"count", "square", square_scene(opt.tilt_size, 60, 1, n), 60, 1, ""});
  for (const double a : opt.areas)
    cases.push_back({"area", "square", square_scene(opt.tilt_size, 60, a, 1), 60, a, ""});
  for (const double st : opt.steps)
    cases.push_back({"density", "floor", default_scene(size_overrides(320)), -1, 0, "", st});
  for (const double b : opt.band_ratios) {
    cases.push_back(
        {"bands", "floor", default_scene(size_overrides(opt.bands_width)), -1, 0, "", 0.75, b});
  }
  for (const int k : opt.lane_counts) {
    cases.push_back({"lanes", "floor", default_scene(size_overrides(opt.lanes_width)), -1, 0, "",
                     0.75, ObjectSpaceConfig{}.band_ratio, k, false});
  }
  return cases;
}

StudyTable table(const std::vector<ObjspaceRow>& rows) {
  StudyTable t({"sweep",
                "scene",
                "method",
                "width",
                "height",
                "tilt °",
                "area",
                "step px",
                "band ratio",
                "bands",
                "lanes",
                "block area",
                "texture cycles",
                "lane cycles",
                "primitives",
                "pixels",
                "fragments or samples",
                "cycles",
                "cycles per pixel",
                "ops",
                "add",
                "mul",
                "div",
                "rcp",
                "sqrt",
                "lut",
                "cmp",
                "mem",
                "texels",
                "DRAM bytes",
                "splat buffer bytes",
                "holes",
                "PSNR dB",
                "NMSE",
                "max error"},
               "lllrrrrrrrrrrrrrrrrrrrrrrrrrrrrrrrr");
  for (const ObjspaceRow& r : rows) {
    const double px = r.pixels ? static_cast<double>(r.pixels) : 1;
    t.add({r.sweep,
           r.scene,
           r.method,
           std::to_string(r.width),
           std::to_string(r.height),
           r.tilt_deg >= 0 ? fmt(r.tilt_deg) : "",
           r.area > 0 ? fmt(r.area) : "",
           r.method == "object-space" ? fmt(r.step_px) : "",
           r.method == "object-space" ? fmt(r.band_ratio) : "",
           r.method == "object-space" ? std::to_string(r.bands) : "",
           r.method == "object-space" ? std::to_string(r.lanes) : "",
           r.method == "object-space" ? fmt(r.block_area, 5) : "",
           r.method == "object-space" ? std::to_string(r.texture_cycles) : "",
           r.method == "object-space" ? std::to_string(r.lane_cycles) : "",
           std::to_string(r.primitives),
           std::to_string(r.pixels),
           std::to_string(r.items),
           std::to_string(r.cycles),
           fmt(static_cast<double>(r.cycles) / px, 3),
           std::to_string(r.ops.total()),
           std::to_string(r.ops.add),
           std::to_string(r.ops.mul),
           std::to_string(r.ops.div),
           std::to_string(r.ops.rcp),
           std::to_string(r.ops.sqrt),
           std::to_string(r.ops.lut),
           std::to_string(r.ops.cmp),
           std::to_string(r.ops.mem),
           std::to_string(r.texels),
           std::to_string(r.dram_bytes),
           std::to_string(r.buffer_bytes),
           std::to_string(r.holes),
           fmt(r.acc.psnr_db),
           fmt(r.acc.nmse, 3),
           fmt(r.acc.max_abs, 3)});
  }
  return t;
}

// Cycles of one method in one sweep, against the sweep's variable.
std::vector<LabelledPoint> series_of(const std::vector<ObjspaceRow>& rows, const std::string& sweep,
                                     const std::string& method, const std::string& scene) {
  std::vector<LabelledPoint> pts;
  for (const ObjspaceRow& r : rows) {
    if (r.sweep != sweep || r.method != method || r.scene != scene) continue;
    double x = r.tilt_deg;
    if (sweep == "resolution") x = static_cast<double>(r.width) * r.height;
    if (sweep == "count") x = static_cast<double>(r.primitives);
    if (sweep == "area") x = r.area;
    pts.push_back({x, static_cast<double>(r.cycles), ""});
  }
  return pts;
}

PlotSpec plot(const std::vector<ObjspaceRow>& rows, const std::string& sweep,
              const std::string& scene, const std::string& xlabel, bool logx) {
  PlotSpec p;
  p.title = "Object space against screen space: cycles per frame (" + sweep + ", " + scene + ")";
  p.xlabel = xlabel;
  p.ylabel = "cycles per frame";
  p.logx = logx;
  p.logy = true;
  for (const std::string& m : kMethods) {
    PlotSeries s = labelled_series(m, series_of(rows, sweep, m, scene));
    s.lines = true;
    p.series.push_back(std::move(s));
  }
  return p;
}

// Ratio of the cycles of `method` to those of object space, per row pair of a sweep.
std::vector<double> speedups(const std::vector<ObjspaceRow>& rows, const std::string& method,
                             const std::string& sweep) {
  std::vector<double> out;
  for (size_t i = 0; i < rows.size(); ++i) {
    const ObjspaceRow& o = rows[i];
    if (o.method != "object-space" || (!sweep.empty() && o.sweep != sweep)) continue;
    // Not the defaults: a grid step beyond the hole-free rule, or other depth bands.
    if (sweep.empty() && (o.sweep == "density" || o.sweep == "bands" || o.sweep == "lanes"))
      continue;
    for (size_t k = i + 1; k < rows.size() && rows[k].method != "object-space"; ++k) {
      if (rows[k].method == method && o.cycles > 0)
        out.push_back(static_cast<double>(rows[k].cycles) / static_cast<double>(o.cycles));
    }
  }
  return out;
}

double geomean(const std::vector<double>& v) {
  if (v.empty()) return 0;
  double s = 0;
  for (double x : v) s += std::log(x);
  return std::exp(s / static_cast<double>(v.size()));
}

// max / min of object space's cycles over a sweep of one scene.
double spread(const std::vector<ObjspaceRow>& rows, const std::string& sweep,
              const std::string& scene) {
  double lo = 0, hi = 0;
  for (const LabelledPoint& p : series_of(rows, sweep, "object-space", scene)) {
    lo = lo == 0 ? p.y : std::min(lo, p.y);
    hi = std::max(hi, p.y);
  }
  return lo > 0 ? hi / lo : 0;
}

// The image width of a sweep's rows (0 if it has none).
int rows_width(const std::vector<ObjspaceRow>& rows, const std::string& sweep) {
  for (const ObjspaceRow& r : rows) {
    if (r.sweep == sweep) return r.width;
  }
  return 0;
}

std::string claims(const std::vector<ObjspaceRow>& rows) {
  std::ostringstream s;
  s << "## The thesis's claims, re-measured as cycles\n\n"
    << "Speed-up = screen-space cycles ÷ object-space cycles (geometric mean over every scene "
       "and sweep point but the density sweep; > 1: object space is faster).\n\n"
    << "| against | all rows | resolution sweep | tilt sweep |\n|---|--:|--:|--:|\n";
  for (const std::string m : {"trilinear", "vulkan", "ewa", "feline"}) {
    s << "| " << m << " | " << fmt(geomean(speedups(rows, m, "")), 3) << " | "
      << fmt(geomean(speedups(rows, m, "resolution")), 3) << " | "
      << fmt(geomean(speedups(rows, m, "tilt")), 3) << " |\n";
  }
  std::vector<double> af;
  for (const std::string m : {"vulkan", "ewa", "feline"}) {
    const std::vector<double> v = speedups(rows, m, "");
    af.insert(af.end(), v.begin(), v.end());
  }
  const double floor_res = spread(rows, "resolution", "floor");
  const std::vector<LabelledPoint> res = series_of(rows, "resolution", "object-space", "floor");
  const std::vector<LabelledPoint> areas = series_of(rows, "area", "object-space", "square");
  const double af_ratio = geomean(af);
  s << "\n- Thesis: +30 % on average against screen space with anisotropic filtering. Model: "
    << "screen space with an anisotropic filter takes " << fmt(af_ratio, 3)
    << "× the object-space cycles (geometric mean over Vulkan probes, EWA and Feline and every "
       "row): object space takes "
    << fmt(af_ratio > 0 ? 1 / af_ratio : 0, 3) << "× their cycles"
    << (af_ratio < 1 ? " (the model disagrees)" : " (the model agrees in direction)") << ".\n";
  if (!res.empty()) {
    s << "- Thesis: speed independent of screen resolution. Model: object-space cycles of the "
         "floor grow "
      << fmt(floor_res, 3) << "× over the resolution sweep while its pixels grow "
      << fmt(res.back().x / res.front().x, 3)
      << "×: the hole-free step follows the pixel size, so the samples grow with the pixels "
         "(the model disagrees).\n";
  }
  s << "- Thesis: speed independent of polygon tilt. Model: object-space cycles vary "
    << fmt(spread(rows, "tilt", "square"), 3)
    << "× over tilts 0°…85° (max ÷ min) for a square of fixed area, while screen space's follow "
       "its shrinking pixel count (the model agrees).\n";
  if (areas.size() > 1) {
    s << "- Thesis: speed depends on total polygon area. Model: object-space cycles grow "
      << fmt(spread(rows, "area", "square"), 3) << "× when the square's area grows "
      << fmt(areas.back().x / areas.front().x, 3) << "× (the model agrees; the whole-frame resolve "
      << "is a fixed part); the same area cut into more polygons costs up to "
      << fmt(spread(rows, "count", "square"), 3) << "× (edge samples and set-up per polygon).\n";
  }
  for (const ObjspaceRow& r : rows) {
    if (r.sweep != "density" || r.method != "object-space") continue;
    s << "- A grid step of " << fmt(r.step_px)
      << " pixel instead of 3/4 (floor, 320 × 240): " << r.cycles << " cycles, " << r.holes
      << " holes of " << r.pixels << " pixels.\n";
  }
  const ObjspaceRow* banded = nullptr;
  for (const ObjspaceRow& r : rows) {
    if (r.sweep == "resolution" && r.scene == "floor" && r.method == "object-space" &&
        r.width == rows_width(rows, "bands"))
      banded = &r;
  }
  for (const ObjspaceRow& r : rows) {
    if (r.sweep != "bands" || r.method != "object-space") continue;
    s << "- Depth bands: band ratio " << fmt(r.band_ratio)
      << (r.band_ratio == 0 ? " (the thesis's one LOD and one grid step per polygon)" : "")
      << " on the floor, " << r.width << " × " << r.height << ": " << r.bands << " band(s), "
      << r.items << " samples, " << r.cycles << " cycles, PSNR " << fmt(r.acc.psnr_db) << " dB, "
      << r.holes << " holes";
    if (banded) {
      s << "; the default (" << banded->bands << " bands at ratio " << fmt(banded->band_ratio)
        << "): " << banded->items << " samples, " << banded->cycles << " cycles, PSNR "
        << fmt(banded->acc.psnr_db) << " dB";
    }
    s << ".\n";
  }
  return s.str();
}

// The lane sweep: cycles per pixel, area and error per lane count.
std::string lanes_section(const std::vector<ObjspaceRow>& rows) {
  std::ostringstream s;
  const ObjspaceRow* one = nullptr;
  for (const ObjspaceRow& r : rows) {
    if (r.sweep == "lanes" && r.lanes == 1) one = &r;
  }
  bool any = false;
  for (const ObjspaceRow& r : rows) {
    if (r.sweep != "lanes") continue;
    if (!any) {
      s << "## Parallel lanes (\"GPU cores\") on the floor, " << r.width << " × " << r.height
        << "\n\nEach block of the variant (rotation, grid walk, projection, splat and resolve) "
           "`lanes` samples wide; one texture unit (one fragment per cycle at best). Cycles per "
           "pixel: the frame's; lane stages: the slowest of the grid walk, projection and splat "
           "per pixel; the frame takes the slower of those and the texture unit, plus the "
           "polygons' set-up and the resolve; area: the four blocks' (adder equivalents, the "
           "texture unit aside).\n\n"
        << "| lanes | cycles/px | lane stages cycles/px | texture unit cycles/px | speed-up | "
           "area | PSNR dB | NMSE |\n|--:|--:|--:|--:|--:|--:|--:|--:|\n";
      any = true;
    }
    const double px = r.pixels ? static_cast<double>(r.pixels) : 1;
    const auto lane_stage = static_cast<double>(r.lane_cycles);
    s << "| " << r.lanes << " | " << fmt(static_cast<double>(r.cycles) / px, 3) << " | "
      << fmt(lane_stage / px, 3) << " | " << fmt(static_cast<double>(r.texture_cycles) / px, 3)
      << " | "
      << (one && r.cycles ? fmt(static_cast<double>(one->cycles) / static_cast<double>(r.cycles), 3)
                          : "")
      << " | " << fmt(r.block_area, 5) << " | " << fmt(r.acc.psnr_db) << " | " << fmt(r.acc.nmse, 3)
      << " |\n";
  }
  return any ? s.str() + "\n" : "";
}

}  // namespace

std::vector<ObjspaceRow> measure_objspace_study(const ObjspaceStudyOptions& opt,
                                                const std::string& image_dir, std::ostream& log) {
  std::vector<ObjspaceRow> rows;
  for (const SceneCase& c : study_cases(opt)) measure_case(c, opt, image_dir, rows, log);
  return rows;
}

int run_study_objspace(const std::string& out_dir, std::ostream& log) {
  return run_study_objspace(out_dir, log, ObjspaceStudyOptions{});
}

int run_study_objspace(const std::string& out_dir, std::ostream& log,
                       const ObjspaceStudyOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  const std::vector<ObjspaceRow> rows = measure_objspace_study(opt, out_dir, log);
  const StudyTable t = table(rows);
  files.csv("objspace.csv", t);
  files.text("objspace.md",
             "# Study objspace: object-space texturing against screen-space filtering\n\n"
             "Object space: frustum clip, depth bands (far/near <= 2; the bands sweep: other "
             "ratios, 0 = one band per polygon as in the thesis), rotation parallel to the "
             "screen, the hole-free grid (one step <= 3/4 pixel on the screen), one LOD per band, "
             "trilinear fetch through the texture unit and cache, projection, 4-pixel area splat "
             "with depth visibility, resolve. Screen space: the edge rasteriser and the texture "
             "unit with trilinear, Vulkan probes (16:1), EWA (LUT weights, 16:1) or Feline. "
             "Cycles per frame: the slowest stage of each pipeline (docs/derivations/"
             "object-space.md). Errors: against the box-filtered ground truth (" +
                 std::to_string(opt.reference_supersamples) +
                 "² samples per pixel) over the "
                 "pixels screen space covers.\n\n" +
                 claims(rows) + "\n" + lanes_section(rows) + "## All rows\n\n" + t.markdown());
  files.plot("objspace_tilt.png", plot(rows, "tilt", "square", "polygon tilt (°)", false));
  files.plot("objspace_resolution.png",
             plot(rows, "resolution", "floor", "pixels of the image (floor scene)", true));
  files.plot("objspace_count.png",
             plot(rows, "count", "square", "polygons (same total area)", true));
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study objspace: wrote " << out_dir << "/objspace.csv, objspace.md, objspace_*.png in "
      << fmt(secs, 3) << " s\n";
  return 0;
}

}  // namespace texsim
