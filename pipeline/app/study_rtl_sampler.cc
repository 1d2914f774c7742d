#include "pipeline/app/study_rtl_sampler.h"

#include <cstdio>
#include <filesystem>
#include <sstream>

#include "blocks/base/input_error.h"
#include "pipeline/app/run.h"

namespace texsim {

namespace {

// One functional run (colours only: the image does not depend on the clock), no files.
RunCapture run_material(const std::string& scene, const std::string& material,
                        const std::vector<std::string>& filter_keys) {
  RunOptions o;
  o.scene = scene;
  o.functional = true;
  o.threads = 1;
  for (const std::string& k : filter_keys) {
    std::string key = "materials.";
    key += material;
    key += ".filter.";
    key += k;
    o.overrides.push_back(key);
  }
  RunCapture c;  // write_outputs false
  o.capture = &c;
  std::ostringstream quiet;
  run_simulation(o, quiet);
  return c;
}

int32_t material_index(const RunCapture& c, const std::string& scene, const std::string& m) {
  for (size_t i = 0; i < c.material_names.size() && i < c.materials.size(); ++i) {
    if (c.material_names[i] == m) return static_cast<int32_t>(i);
  }
  throw InputError(scene, "no material " + m + " in the run's accuracy");
}

}  // namespace

SamplerSceneError SamplerSceneErrors::measure(int sub_bits, int mip_bits) {
  if (!float_image_) {
    RunCapture f = run_material(scene_, material_, {"arithmetic=\"float\""});
    if (!f.image) throw InputError(scene_, "the float32 run gave no image");
    float_image_ = std::move(f.image);
  }
  const RunCapture c =
      run_material(scene_, material_,
                   {"arithmetic=\"fixed\"", "sub_texel_bits=" + std::to_string(sub_bits),
                    "mipmap_bits=" + std::to_string(mip_bits)});
  const int32_t i = material_index(c, scene_, material_);
  if (!c.image) throw InputError(scene_, "the fixed-arithmetic run gave no image");
  const AccuracyMetrics& t = c.materials[static_cast<size_t>(i)];
  return {t.psnr_db, compare_images(*c.image, *float_image_, i).psnr_db, t.pixels};
}

std::string SamplerSceneErrors::cell(int sub_bits, int mip_bits) {
  const SamplerSceneError e = measure(sub_bits, mip_bits);
  char b[160];
  std::snprintf(b, sizeof b, "PSNR %.2f dB vs truth, %.2f dB vs float32 (%s %s)", e.psnr_db,
                e.psnr_vs_float_db, std::filesystem::path(scene_).filename().string().c_str(),
                material_.c_str());
  return b;
}

}  // namespace texsim
