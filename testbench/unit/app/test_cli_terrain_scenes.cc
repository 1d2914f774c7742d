// The terrain flyover scenes end to end (geometry → raster → texture with the terrain relief
// stage → lighting): the procedural one runs and reports the terrain marcher and the lighting
// blocks, with an image close to its ground truth; a DEM scene whose .npz is missing stops
// with an error naming the file and the package that ships it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)
namespace fs = std::filesystem;

std::string read(const std::string& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(Cli, TerrainFlyoverRunsEndToEnd) {
  const std::string out = path("fly");
  const Result r = sh(std::string("run ") + TEXSIM_SOURCE_DIR +
                      "/scenes/terrain_flyover.toml --no-progress --out " + out);
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string md = read(out + "/report.md");
  for (const char* block : {"relief.terrain_ray_marcher", "lighting.normal_unit",
                            "lighting.blinn_phong", "Relief method terrain"}) {
    EXPECT_NE(md.find(block), std::string::npos) << block;
  }
  const size_t p = r.out.find("PSNR ");
  ASSERT_NE(p, std::string::npos) << r.out;
  EXPECT_GT(std::stod(r.out.substr(p + 5)), 24.0) << r.out;  // measured 28.1 dB
}

TEST_F(Cli, TerrainDemSceneNamesAMissingHeightField) {
  std::string scene = read(std::string(TEXSIM_SOURCE_DIR) + "/scenes/terrain_dem.toml");
  const std::string real = "/usr/share/matplotlib/mpl-data/sample_data/jacksboro_fault_dem.npz";
  const std::string missing = path("nowhere/jacksboro_fault_dem.npz");
  const size_t at = scene.find(real);
  ASSERT_NE(at, std::string::npos);
  scene.replace(at, real.size(), missing);
  const std::string file = path("dem.toml");
  std::ofstream(file) << scene;
  const Result r = sh("run " + file + " --no-progress --out " + path("dem"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(missing), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("python-matplotlib-data"), std::string::npos) << r.out;
}

}  // namespace
