#include "pipeline/app/run.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <map>
#include <ostream>

#include "blocks/base/atomic_file.h"
#include "blocks/base/input_error.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/raster/scene_front_end.h"
#include "pipeline/reference/ground_truth.h"
#include "pipeline/report/run_report.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/texture_unit.h"
#include "traces/trace_file.h"

namespace texsim {

namespace {

class Progress {
 public:
  explicit Progress(bool on) : on_(on), t0_(std::chrono::steady_clock::now()) {}
  void tick(uint64_t n) {
    if (!on_ || (n & 0xFFFF) != 0) return;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    if (s < 1.0) return;
    std::fprintf(stderr, "\r  %llu fragments, %.1f M/s   ", static_cast<unsigned long long>(n),
                 static_cast<double>(n) / s / 1e6);
    shown_ = true;
  }
  ~Progress() {
    if (shown_) std::fprintf(stderr, "\n");
  }

 private:
  bool on_;
  bool shown_ = false;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

RunSummary run_simulation(const RunOptions& opt, std::ostream& log) {
  // Scene: a file, the built-in default, or (trace only) none.
  const bool use_scene = !opt.scene.empty() || opt.trace.empty();
  Scene scene =
      (opt.scene.empty() || opt.scene == "default") ? default_scene() : load_scene(opt.scene);

  // Textures and the map from fragment texture ids to loaded textures.
  TextureSet textures;
  std::map<uint32_t, int> tex_index;
  std::unique_ptr<TraceReader> reader;
  std::vector<std::string> tex_names;
  if (!opt.trace.empty()) {
    reader = std::make_unique<TraceReader>(opt.trace);
    const std::string dir = std::filesystem::path(opt.trace).parent_path().string();
    for (const auto& t : reader->header().textures) {
      Texture tex = load_texture(t.source, dir);
      if (static_cast<uint32_t>(tex.width(0)) != t.width ||
          static_cast<uint32_t>(tex.height(0)) != t.height) {
        throw InputError(opt.trace, "texture " + std::to_string(t.id) + " ('" + t.source +
                                        "') is " + std::to_string(tex.width(0)) + "x" +
                                        std::to_string(tex.height(0)) +
                                        " but the trace's texture table says " +
                                        std::to_string(t.width) + "x" + std::to_string(t.height));
      }
      tex_index[t.id] = textures.add(std::move(tex));
      tex_names.push_back(t.name + " = " + t.source);
    }
  } else {
    for (size_t i = 0; i < scene.textures.size(); ++i) {
      tex_index[static_cast<uint32_t>(i)] =
          textures.add(load_texture(scene.textures[i].source, scene.base_dir));
      tex_names.push_back(scene.textures[i].name + " = " + scene.textures[i].source);
    }
  }

  // Materials: the scene's (a fragment's material is that of plane `prim`), or one default.
  std::vector<MaterialSetup> mats;
  if (use_scene) {
    for (const auto& m : scene.materials) {
      mats.push_back(material_from_toml(m.name, m.texture, *m.effects, scene.path));
    }
  }
  if (!opt.trace.empty()) {
    // Trace fragments carry their coordinates: a material's coordinate unit has nothing to do.
    for (auto& m : mats) {
      if (!m.coords) continue;
      log << "texsim run: note: material '" << m.name
          << "': coords ignored, the trace's fragments carry their own coordinates\n";
      m.coords.reset();
    }
  }
  if (mats.empty()) {
    MaterialSetup d;
    d.name = "default";
    d.filter.filter = FilterMode::Trilinear;
    mats.push_back(d);
  }
  const PipelineSetup setup =
      PipelineSetup::from_toml(scene.pipeline ? *scene.pipeline : toml::table{}, scene.path);
  TextureUnit unit(textures, mats, setup, scene.tech, !opt.functional);

  std::vector<PlaneProjection> maps;
  if (use_scene) {
    for (const auto& p : scene.planes) maps.emplace_back(scene, p);
  }
  int width = scene.width, height = scene.height;
  if (!use_scene) width = height = 0;

  // Fragments are processed as they stream in; images grow to the trace's extent if needed.
  std::vector<Fragment> chunk;
  ImageRgb img(std::max(width, 1), std::max(height, 1), scene.background);
  ImageRgb ref(std::max(width, 1), std::max(height, 1), scene.background);
  uint64_t count = 0;
  int max_x = width - 1, max_y = height - 1;
  Progress progress(opt.progress);
  const int n = scene.reference_supersamples;
  // A fragment's colour (null: not textured, the background stays) and its ground truth.
  auto record = [&](const Fragment& f, const Fragment& g, int material, const Rgba* colour) {
    const Texture& tex = textures[static_cast<int>(g.tex)];
    const MaterialSetup& ms = mats[static_cast<size_t>(material)];
    const glm::dvec4 r = (use_scene && !maps.empty())
                             ? ground_truth_exact(tex, ms.address_u(), ms.address_v(), maps[f.prim],
                                                  static_cast<int>(f.x), static_cast<int>(f.y), n)
                             : ground_truth_footprint(tex, ms.address_u(), ms.address_v(), g, n);
    const int x = static_cast<int>(f.x), y = static_cast<int>(f.y);
    if (x >= img.width || y >= img.height) {
      // Grow geometrically (traces do not declare their extent); cropped at the end.
      const int w = x < img.width ? img.width : std::min(1 << 14, std::max(x + 1, 2 * img.width));
      const int h =
          y < img.height ? img.height : std::min(1 << 14, std::max(y + 1, 2 * img.height));
      img.resize(w, h, scene.background);
      ref.resize(w, h, scene.background);
    }
    max_x = std::max(max_x, x);
    max_y = std::max(max_y, y);
    // A pixel whose coordinates were rejected keeps the background, and counts as an error.
    const glm::dvec3& bg = scene.background;
    img.set(x, y, colour ? *colour : glm::vec4(glm::dvec4(bg, 1.0)), material);
    ref.set(x, y, glm::vec4(r.x, r.y, r.z, r.w));
    progress.tick(++count);
  };
  auto handle = [&](const Fragment& f, uint64_t index) {
    auto it = tex_index.find(f.tex);
    if (it == tex_index.end()) {
      throw InputError(opt.trace.empty() ? scene.path : opt.trace,
                       "record " + std::to_string(index) + ": texture id " + std::to_string(f.tex) +
                           " is not in the texture table");
    }
    if (f.x >= (1u << 14) || f.y >= (1u << 14)) {
      throw InputError(opt.trace, "record " + std::to_string(index) + ": pixel (" +
                                      std::to_string(f.x) + ", " + std::to_string(f.y) +
                                      ") is outside the 16384x16384 image limit");
    }
    Fragment g = f;
    g.tex = static_cast<uint32_t>(it->second);
    int material = 0;
    if (use_scene && !maps.empty()) {
      if (f.prim >= scene.planes.size()) {
        throw InputError(opt.trace, "record " + std::to_string(index) + ": primitive " +
                                        std::to_string(f.prim) + " is not a plane of scene " +
                                        scene.path);
      }
      material = scene.planes[f.prim].material;
    }
    const Rgba c = unit.process(g, material);
    record(f, g, material, &c);
  };
  if (reader) {
    uint64_t index = 0;
    while (reader->next_chunk(chunk) > 0) {
      for (const Fragment& f : chunk) handle(f, index++);
    }
  } else if (unit.front_stages() > 0) {
    // Some material computes its own coordinates: planes drawn one by one through the front end.
    draw_scene_front_end(scene, maps, unit, [&](const Fragment& f, int material, const Rgba* c) {
      Fragment g = f;
      g.tex = static_cast<uint32_t>(tex_index.at(f.tex));
      record(f, g, material, c);
    });
  } else {
    uint64_t index = 0;
    generate_fragments(scene, 0, [&](const Fragment& f) { handle(f, index++); });
  }
  if (count == 0)
    throw InputError(opt.trace.empty() ? scene.path : opt.trace, "no fragments to render");
  width = max_x + 1;
  height = max_y + 1;
  if (img.width != width || img.height != height) {
    img.resize(width, height, scene.background);
    ref.resize(width, height, scene.background);
  }
  RunSummary sum;
  sum.fragments = unit.fragments();
  sum.cycles = unit.cycles();
  sum.accuracy = compare_images(img, ref);

  RunInfo info;
  info.scene = use_scene ? scene.path : "(none: trace only)";
  info.trace = opt.trace;
  info.width = width;
  info.height = height;
  info.textures = tex_names;
  for (int m = 0; m < unit.material_count(); ++m)
    info.material_accuracy.push_back(compare_images(img, ref, m));
  info.reference =
      "Ground truth: level-0 texture, bilinear reconstruction in double, box-filtered over "
      "each pixel with " +
      std::to_string(n) + "x" + std::to_string(n) + " samples " +
      ((use_scene && !maps.empty())
           ? "mapped exactly through each plane's projective map."
           : "over the parallelogram spanned by the fragment's derivatives.");
  ensure_dir(opt.out);
  write_image(opt.out + "/image.png", img);
  write_image(opt.out + "/reference.png", ref);
  write_error_heatmap(opt.out + "/error.png", img, ref, sum.accuracy.max_abs);
  write_run_reports(opt.out, info, unit, sum.accuracy);
  log << "texsim run: " << sum.fragments << " fragments, " << sum.cycles << " cycles, PSNR "
      << sum.accuracy.psnr_db << " dB\n";
  log << "  report: " << opt.out << "/report.json, " << opt.out << "/report.md\n";
  log << "  images: " << opt.out << "/image.png, " << opt.out << "/reference.png, " << opt.out
      << "/error.png\n";
  return sum;
}

uint64_t generate_scene_trace(const std::string& scene_path, const std::string& out_path) {
  const Scene scene = scene_path.empty() ? default_scene() : load_scene(scene_path);
  (void)build_materials(scene);  // checks the materials' effects
  TraceHeader h;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture t = load_texture(scene.textures[i].source, scene.base_dir);
    std::string src = scene.textures[i].source;
    if (!is_procedural_source(src)) {
      // Paths in the trace are absolute so the trace can be moved away from the scene.
      src = std::filesystem::absolute(resolve_texture_path(src, scene.base_dir)).string();
    }
    h.textures.push_back({static_cast<uint32_t>(i), scene.textures[i].name, src,
                          static_cast<uint32_t>(t.width(0)), static_cast<uint32_t>(t.height(0))});
  }
  TraceWriter w(out_path, h);
  generate_fragments(scene, 0, [&](const Fragment& f) { w.write(f); });
  w.close();
  return w.records_written();
}

}  // namespace texsim
