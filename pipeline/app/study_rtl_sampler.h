#pragma once
// The accuracy column of the RTL sampler in `texsim study rtl` (docs/rtl/study.md): the C++
// FixedSampler (bit-exact with texsim_sampler.v) at S sub-texel and M mipmap bits on a shipped
// scene's fragments, its image against the scene's ground truth, and against the same
// material's float32 sampler (the precision lost to the widths alone). Here, beside
// `texsim run`, because the study library does not run scenes.
#include <cstdint>
#include <memory>
#include <string>

#include "pipeline/report/image_metrics.h"

namespace texsim {

struct SamplerSceneError {
  double psnr_db = 0;           // against the ground truth, over the material's pixels
  double psnr_vs_float_db = 0;  // against the float32 sampler's image, same pixels
  uint64_t pixels = 0;
};

class SamplerSceneErrors {
 public:
  SamplerSceneErrors(std::string scene, std::string material)
      : scene_(std::move(scene)), material_(std::move(material)) {}

  // Runs the scene functionally (no files) with the material at filter.arithmetic = "fixed",
  // sub_texel_bits = `sub_bits`, mipmap_bits = `mip_bits` (and once at "float"). Throws
  // InputError on a scene or material the fixed sampler does not cover.
  SamplerSceneError measure(int sub_bits, int mip_bits);

  // "PSNR 39.79 dB vs truth, 52.10 dB vs float32 (bunny.toml fur)": the study's error cell.
  std::string cell(int sub_bits, int mip_bits);

 private:
  std::string scene_, material_;
  std::unique_ptr<ImageRgb> float_image_;
};

}  // namespace texsim
