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
#include "traces/trace_tools.h"

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

// The textures of a run and the map from fragment texture ids to them.
struct RunTextures {
  TextureSet set;
  std::map<uint32_t, int> index;       // texture id of the input -> texture of the set
  std::map<std::string, int> by_name;  // texture name -> texture of the set
  std::vector<std::string> names;      // "name = source", for the report
};

// A trace's texture table: each texture loaded (relative to the trace) and checked against the
// size the table declares.
RunTextures load_trace_textures(const TraceReader& reader, const std::string& trace_path) {
  RunTextures t;
  const std::string dir = std::filesystem::path(trace_path).parent_path().string();
  for (const auto& e : reader.header().textures) {
    Texture tex = load_texture(e.source, dir);
    if (static_cast<uint32_t>(tex.width(0)) != e.width ||
        static_cast<uint32_t>(tex.height(0)) != e.height) {
      throw InputError(trace_path, "texture " + std::to_string(e.id) + " ('" + e.source + "') is " +
                                       std::to_string(tex.width(0)) + "x" +
                                       std::to_string(tex.height(0)) +
                                       " but the trace's texture table says " +
                                       std::to_string(e.width) + "x" + std::to_string(e.height));
    }
    const int id = t.set.add(std::move(tex));
    t.index[e.id] = id;
    t.by_name[e.name] = id;
    t.names.push_back(e.name + " = " + e.source);
  }
  return t;
}

// A scene's textures, ids in declaration order.
RunTextures load_scene_textures(const Scene& scene) {
  RunTextures t;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const int id = t.set.add(load_scene_texture(scene, i));
    t.index[static_cast<uint32_t>(i)] = id;
    t.by_name[scene.textures[i].name] = id;
    t.names.push_back(scene.textures[i].name + " = " + scene.textures[i].source);
  }
  return t;
}

// The scene's materials (a fragment's material is that of plane `prim`), or one default. Each
// material's texture is bound by name to the loaded textures (with a trace: its table's).
std::vector<MaterialSetup> run_materials(const Scene& scene, bool use_scene,
                                         const RunTextures& textures, const std::string& trace,
                                         std::ostream& log) {
  const bool from_trace = !trace.empty();
  std::vector<MaterialSetup> mats;
  if (use_scene) {
    for (const auto& m : scene.materials) {
      const std::string& name = scene.textures[static_cast<size_t>(m.texture)].name;
      const auto it = textures.by_name.find(name);
      if (it == textures.by_name.end()) {
        std::string have;
        for (const auto& [n, id] : textures.by_name) have += (have.empty() ? "'" : ", '") + n + "'";
        throw InputError(trace, "the texture table has no texture named '" + name +
                                    "', which material '" + m.name + "' of " + scene.path +
                                    " uses (the table has " + (have.empty() ? "none" : have) + ")");
      }
      mats.push_back(material_from_toml(m.name, it->second, *m.effects, scene.path));
    }
  }
  if (from_trace) {
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
  return mats;
}

// A fragment's ground truth: exact through its plane's projective map when the scene's planes
// are known, otherwise over the footprint its derivatives span.
struct GroundTruth {
  const TextureSet& textures;
  const std::vector<MaterialSetup>& mats;
  const std::vector<PlaneProjection>& maps;  // empty: from the fragment's derivatives
  int supersamples;

  bool exact() const { return !maps.empty(); }
  // f: the fragment as given; g: the same with its texture id mapped to the loaded texture.
  glm::dvec4 operator()(const Fragment& f, const Fragment& g, int material) const {
    const Texture& tex = textures[static_cast<int>(g.tex)];
    const MaterialSetup& ms = mats[static_cast<size_t>(material)];
    return exact() ? ground_truth_exact(tex, ms.address_u(), ms.address_v(), maps[f.prim],
                                        static_cast<int>(f.x), static_cast<int>(f.y), supersamples)
                   : ground_truth_footprint(tex, ms.address_u(), ms.address_v(), g, supersamples);
  }
};

// The simulated image and its ground truth. Traces do not declare their extent: the images
// grow to the fragments seen and are cropped to them at the end.
class RunImages {
 public:
  RunImages(int width, int height, glm::dvec3 background)
      : img(std::max(width, 1), std::max(height, 1), background),
        ref(std::max(width, 1), std::max(height, 1), background),
        background_(background),
        max_x_(width - 1),
        max_y_(height - 1) {}

  // colour null: not textured (coordinates rejected), the pixel keeps the background and
  // counts as an error.
  void set(int x, int y, const Rgba* colour, int material, const glm::dvec4& truth) {
    if (x >= img.width || y >= img.height) {
      // Grow geometrically; cropped at the end.
      const int w = x < img.width ? img.width : std::min(1 << 14, std::max(x + 1, 2 * img.width));
      const int h =
          y < img.height ? img.height : std::min(1 << 14, std::max(y + 1, 2 * img.height));
      img.resize(w, h, background_);
      ref.resize(w, h, background_);
    }
    max_x_ = std::max(max_x_, x);
    max_y_ = std::max(max_y_, y);
    img.set(x, y, colour ? *colour : glm::vec4(glm::dvec4(background_, 1.0)), material);
    ref.set(x, y, glm::vec4(truth.x, truth.y, truth.z, truth.w));
    ++count_;
  }
  uint64_t count() const { return count_; }
  // Crops both images to the pixels written.
  void crop() {
    const int width = max_x_ + 1, height = max_y_ + 1;
    if (img.width != width || img.height != height) {
      img.resize(width, height, background_);
      ref.resize(width, height, background_);
    }
  }

  ImageRgb img, ref;

 private:
  glm::dvec3 background_;
  int max_x_, max_y_;
  uint64_t count_ = 0;
};

// Writes the images and reports to opt.out and a summary to log.
void write_run_outputs(const RunOptions& opt, const RunInfo& info, const RunImages& images,
                       const TextureUnit& unit, const RunSummary& sum, std::ostream& log) {
  ensure_dir(opt.out);
  write_image(opt.out + "/image.png", images.img);
  write_image(opt.out + "/reference.png", images.ref);
  write_error_heatmap(opt.out + "/error.png", images.img, images.ref, sum.accuracy.max_abs);
  write_run_reports(opt.out, info, unit, sum.accuracy);
  log << "texsim run: " << sum.fragments << " fragments, " << sum.cycles << " cycles, PSNR "
      << sum.accuracy.psnr_db << " dB\n";
  log << "  report: " << opt.out << "/report.json, " << opt.out << "/report.md\n";
  log << "  images: " << opt.out << "/image.png, " << opt.out << "/reference.png, " << opt.out
      << "/error.png\n";
}

}  // namespace

RunSummary run_simulation(const RunOptions& opt, std::ostream& log) {
  ensure_dir(opt.out);  // an unwritable --out is found before the run, not after it
  // Scene: a file, the built-in default, or (trace only) none.
  const bool use_scene = !opt.scene.empty() || opt.trace.empty();
  Scene scene =
      (opt.scene.empty() || opt.scene == "default") ? default_scene() : load_scene(opt.scene);

  std::unique_ptr<TraceReader> reader;
  if (!opt.trace.empty()) reader = std::make_unique<TraceReader>(opt.trace);
  RunTextures textures =
      reader ? load_trace_textures(*reader, opt.trace) : load_scene_textures(scene);
  const std::vector<MaterialSetup> mats = run_materials(scene, use_scene, textures, opt.trace, log);
  // Both branches lvalues: a conditional with a temporary would copy the table, and a copied
  // toml table loses the line:column its messages name.
  static const toml::table kNoPipeline;
  const PipelineSetup setup =
      PipelineSetup::from_toml(scene.pipeline ? *scene.pipeline : kNoPipeline, scene.path);
  TextureUnit unit(textures.set, mats, setup, scene.tech, !opt.functional);

  std::vector<PlaneProjection> maps;
  if (use_scene) {
    for (const auto& p : scene.planes) maps.emplace_back(scene, p);
  }
  const GroundTruth truth{textures.set, mats, maps, scene.reference_supersamples};
  RunImages images(use_scene ? scene.width : 0, use_scene ? scene.height : 0, scene.background);
  Progress progress(opt.progress);
  // Fragments are processed as they stream in. f: as given; g: texture id of the loaded texture.
  auto record = [&](const Fragment& f, const Fragment& g, int material, const Rgba* colour) {
    images.set(static_cast<int>(f.x), static_cast<int>(f.y), colour, material,
               truth(f, g, material));
    progress.tick(images.count());
  };
  auto handle = [&](const Fragment& f, uint64_t index) {
    auto it = textures.index.find(f.tex);
    if (it == textures.index.end()) {
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
    if (truth.exact()) {
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
    std::vector<Fragment> chunk;
    uint64_t index = 0;
    while (reader->next_chunk(chunk) > 0) {
      for (const Fragment& f : chunk) handle(f, index++);
    }
  } else if (unit.front_stages() > 0) {
    // Some material computes its own coordinates: planes drawn one by one through the front end.
    draw_scene_front_end(scene, maps, unit, [&](const Fragment& f, int material, const Rgba* c) {
      Fragment g = f;
      g.tex = static_cast<uint32_t>(textures.index.at(f.tex));
      record(f, g, material, c);
    });
  } else {
    uint64_t index = 0;
    generate_fragments(scene, 0, [&](const Fragment& f) { handle(f, index++); });
  }
  if (images.count() == 0)
    throw InputError(opt.trace.empty() ? scene.path : opt.trace, "no fragments to render");
  images.crop();

  unit.check_timing_invariants();
  RunSummary sum;
  sum.fragments = unit.fragments();
  sum.cycles = unit.cycles();
  sum.accuracy = compare_images(images.img, images.ref);
  RunInfo info;
  info.scene = use_scene ? scene.path : "(none: trace only)";
  info.trace = opt.trace;
  info.width = images.img.width;
  info.height = images.img.height;
  info.textures = textures.names;
  for (int m = 0; m < unit.material_count(); ++m)
    info.material_accuracy.push_back(compare_images(images.img, images.ref, m));
  const int n = scene.reference_supersamples;
  info.reference =
      "Ground truth: level-0 texture, bilinear reconstruction in double, box-filtered over "
      "each pixel with " +
      std::to_string(n) + "x" + std::to_string(n) + " samples " +
      (truth.exact() ? "mapped exactly through each plane's projective map."
                     : "over the parallelogram spanned by the fragment's derivatives.");
  write_run_outputs(opt, info, images, unit, sum, log);
  return sum;
}

uint64_t generate_scene_trace(const std::string& scene_path, const std::string& out_path) {
  const Scene scene = scene_path.empty() ? default_scene() : load_scene(scene_path);
  (void)build_materials(scene);  // checks the materials' effects
  TraceHeader h;
  for (size_t i = 0; i < scene.textures.size(); ++i) {
    const Texture t = load_scene_texture(scene, i);
    std::string src = scene.textures[i].source;
    if (!is_procedural_source(src)) {
      // Paths in the trace are absolute so the trace can be moved away from the scene.
      src = std::filesystem::absolute(resolve_texture_path(src, scene.base_dir)).string();
    }
    h.textures.push_back({static_cast<uint32_t>(i), scene.textures[i].name, src,
                          static_cast<uint32_t>(t.width(0)), static_cast<uint32_t>(t.height(0))});
  }
  return write_trace(out_path, h, [&](auto& w) {
    generate_fragments(scene, 0, [&](const Fragment& f) { w.write(f); });
  });
}

}  // namespace texsim
