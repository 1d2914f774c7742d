#include "pipeline/studies/study_filters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <sstream>

#include "blocks/base/tech_table.h"
#include "blocks/texture/footprint/ewa_filter.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/report/image_metrics.h"
#include "pipeline/scene/procedural_texture.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/studies/study_filter_methods.h"
#include "pipeline/studies/study_filters_report.h"

namespace texsim {

namespace {

constexpr double kPi = 3.14159265358979323846;

std::string fmt_g(double v, int prec = 4) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", prec, v);
  return buf;
}

// One view: a plane tilted by θ = acos(1/N) about the screen's x axis, seen by a camera with a
// 20° field of view, so the footprint's anisotropy at the image centre is N. The plane spans
// depths D/2 … 2D along its receding axis (no horizon: footprints stay finite) and its texture
// scale puts `tpp` level-0 texels per pixel on the minor axis at the centre.
std::string view_scene_text(double aniso, int size, double tpp, int tex_size) {
  const double D = 10.0;
  const double theta = std::acos(1.0 / aniso);
  const double cs = std::cos(theta), sn = std::sin(theta);
  const double su = 0.8 * D, sv = 1.5 * D;
  const double pixel = 2.0 * D * std::tan(10.0 * kPi / 180.0) / size;  // world size at depth D
  const double texel = pixel / tpp;
  const double ox = -su / 2, oy = -0.5 * D * cs, oz = -D + 0.5 * D * sn;
  std::ostringstream s;
  s.precision(17);
  s << "[output]\nwidth = " << size << "\nheight = " << size << "\nbackground = [0.0, 0.0, 0.0]\n"
    << "[camera]\nposition = [0.0, 0.0, 0.0]\nlook_at = [0.0, 0.0, -1.0]\nup = [0.0, 1.0, 0.0]\n"
    << "fov_y = 20.0\nnear = 0.01\n"
    << "[textures.t]\nsource = \"procedural:checker?size=4\"\n"
    << "[materials.m]\ntexture = \"t\"\n"
    << "[[planes]]\nmaterial = \"m\"\norigin = [" << ox << ", " << oy << ", " << oz << "]\n"
    << "edge_u = [" << su << ", 0.0, 0.0]\nedge_v = [0.0, " << sv * cs << ", " << -sv * sn << "]\n"
    << "uv_scale = [" << su / (texel * tex_size) << ", " << sv / (texel * tex_size) << "]\n";
  return s.str();
}

struct StudyTexture {
  std::string name;  // "checker", "photo", "noise"
  std::string source;
  TextureSet set;  // the one texture, as the texture unit reads it
};

// Textures: a checkerboard (sharp edges), a photo, high-frequency noise.
std::vector<StudyTexture> study_textures() {
  std::vector<StudyTexture> textures;
  textures.push_back({"checker", "procedural:checker?size=256&cells=16", {}});
  textures.push_back({"photo", "/usr/share/glmark2/textures/crate-base.png", {}});
  textures.push_back({"noise", "procedural:noise?size=256&cells=32", {}});
  for (StudyTexture& t : textures) {
    t.set.add(is_procedural_source(t.source) ? make_procedural_texture(t.source, "study filters")
                                             : load_texture(t.source, ""));
    t.set.place(TexelLayout::Tiled4x4);
  }
  return textures;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t i = std::min(
      v.size() - 1, static_cast<size_t>(std::llround(p * static_cast<double>(v.size() - 1))));
  return v[i];
}

void sums_vs(const ImageRgb& img, const ImageRgb& ref, double& se, double& sref) {
  se = sref = 0;
  for (size_t i = 0; i < img.covered.size(); ++i) {
    if (!img.covered[i]) continue;
    for (size_t c = 0; c < 3; ++c) {
      const double e = static_cast<double>(img.rgb[i * 3 + c]) - ref.rgb[i * 3 + c];
      se += e * e;
      sref += static_cast<double>(ref.rgb[i * 3 + c]) * ref.rgb[i * 3 + c];
    }
  }
}

// One view of one texture: its fragments, the ground truth and the anisotropy spread.
struct View {
  double nominal = 0;
  Scene scene;  // the view's plane and camera (what a renderer peer draws)
  std::vector<Fragment> frags;
  ImageRgb ref;
  double p50 = 0, p90 = 0;
};

View make_view(const StudyTexture& st, double nominal, const StudyFiltersOptions& opt,
               std::ostream& log) {
  const auto t0 = std::chrono::steady_clock::now();
  const Texture& tex = st.set[0];
  const Scene scene =
      parse_scene(view_scene_text(nominal, opt.size, opt.texels_per_pixel, tex.width(0)),
                  "study filters view", "");
  const PlaneProjection proj(scene, scene.primitives[0]);
  View v{nominal,
         scene,
         pixel_fragments(proj, opt.size, opt.size),
         ImageRgb(opt.size, opt.size, scene.background),
         0,
         0};
  FootprintReferenceConfig rc;
  rc.address_u = rc.address_v = AddressMode::Wrap;
  std::vector<double> anisos;
  for (const Fragment& f : v.frags) {
    OpCounts scratch;
    anisos.push_back(
        footprint_setup<double>(f, tex.width(0), tex.height(0), 1.0, 1e12, scratch).aniso);
    const auto x = static_cast<int>(f.x), y = static_cast<int>(f.y);
    v.ref.set(x, y, glm::vec4(footprint_reference(tex, proj, x, y, rc).colour));
  }
  v.p50 = percentile(anisos, 0.5);
  v.p90 = percentile(anisos, 0.9);
  const double t_ref = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "  " << st.name << " aniso " << nominal << ": " << v.frags.size()
      << " fragments, aniso p50 " << fmt_g(v.p50, 3) << " p90 " << fmt_g(v.p90, 3) << ", reference "
      << fmt_g(t_ref, 3) << " s\n";
  return v;
}

// Every method on one view: rows appended, images kept for the pairwise comparisons.
void measure_view(StudyTexture& st, const View& v, const std::vector<StudyFilterMethod>& methods,
                  const StudyFiltersOptions& opt, const StudyFiles& files,
                  std::vector<FilterRow>& rows) {
  const TechTable tech = TechTable::defaults();
  std::vector<ImageRgb> images;
  images.reserve(methods.size());
  for (const StudyFilterMethod& m : methods) {
    FilterRow r;
    r.texture = st.name;
    r.nominal = v.nominal;
    r.aniso_p50 = v.p50;
    r.aniso_p90 = v.p90;
    r.method = &m;
    const auto t0 = std::chrono::steady_clock::now();
    r.run = run_study_filter_method(m, st.set, v.frags, tech, &v.scene);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ImageRgb img(v.ref.width, v.ref.height, glm::dvec3(0));
    for (size_t i = 0; i < v.frags.size(); ++i)
      img.set(static_cast<int>(v.frags[i].x), static_cast<int>(v.frags[i].y), r.run.colours[i]);
    r.run.colours.clear();
    r.fragments = v.frags.size();
    r.acc = compare_images(img, v.ref);
    sums_vs(img, v.ref, r.se, r.sref);
    for (size_t k = 0; k < images.size(); ++k) {
      if (!m.compare_to.empty() && methods[k].name == m.compare_to)
        sums_vs(img, images[k], r.se_pair, r.sref_pair);
    }
    if (opt.write_images) {
      write_image(files.path(st.name + "_a" + fmt_g(v.nominal, 3) + "_" +
                             std::to_string(&m - methods.data()) + ".png"),
                  img);
    }
    rows.push_back(std::move(r));
    images.push_back(std::move(img));
  }
  if (opt.write_images)
    write_image(files.path(st.name + "_a" + fmt_g(v.nominal, 3) + "_ref.png"), v.ref);
}

}  // namespace

std::vector<Fragment> study_filter_fragments(double aniso, const StudyFiltersOptions& opt,
                                             int texture_size) {
  const Scene scene = parse_scene(
      view_scene_text(aniso, opt.size, opt.texels_per_pixel, texture_size), "study view", "");
  return pixel_fragments(PlaneProjection(scene, scene.primitives[0]), opt.size, opt.size);
}

int run_study_filters(const std::string& out_dir, std::ostream& log) {
  return run_study_filters(out_dir, log, StudyFiltersOptions{});
}

int run_study_filters(const std::string& out_dir, std::ostream& log,
                      const StudyFiltersOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  const StudyFiles files(out_dir);
  std::vector<StudyTexture> textures = study_textures();
  const std::vector<StudyFilterMethod> methods = study_filter_methods(opt, &log);
  std::vector<FilterRow> rows;
  for (StudyTexture& st : textures) {
    for (double nominal : opt.anisotropies)
      measure_view(st, make_view(st, nominal, opt, log), methods, opt, files, rows);
  }
  write_study_filters_outputs(files, rows, methods, opt, log);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log << "study filters: wrote " << out_dir << "/filters.csv, filters.md, filters.png in "
      << fmt_g(secs, 3) << " s\n";
  return 0;
}

}  // namespace texsim
