// Multi-frame traces give per-frame accuracy and the images of one chosen frame; a run's
// memory follows the pixels its fragments cover and is estimated before the run, which is
// refused with a clear message above --max-memory; running out of memory is a clear error.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "testbench/lib/cli_harness.h"

namespace {

using namespace cli_harness;  // NOLINT(google-build-using-namespace)
namespace fs = std::filesystem;

const char* kTable =
    "# texture 0 checker \"procedural:checker?size=64&cells=8\" 64 64\n"
    "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,lod_bias\n";

// One fragment line at pixel (x, y) of `frame`, coordinates following the pixel.
std::string frag(int frame, int x, int y) {
  return std::to_string(frame) + ",0," + std::to_string(x) + "," + std::to_string(y) + ",0," +
         std::to_string(0.013 * x) + "," + std::to_string(0.017 * y) + ",0.013,0,0,0.017,0\n";
}

// A 40 × 30 block of fragments of `frame`; `rows` < 30 covers only the first rows.
std::string block(int frame, int rows = 30) {
  std::string s;
  for (int y = 0; y < rows; ++y) {
    for (int x = 0; x < 40; ++x) s += frag(frame, x, y);
  }
  return s;
}

// The 8-bit RGB pixels of a PNG (empty if it cannot be read).
std::vector<uint8_t> read_rgb(const std::string& png, int& w) {
  auto in = OIIO::ImageInput::open(png);
  if (!in) return {};
  w = in->spec().width;
  std::vector<uint8_t> px(static_cast<size_t>(w) * in->spec().height * 3);
  in->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, px.data());
  return px;
}

TEST_F(Cli, EveryFrameIsComparedWithItsOwnGroundTruth) {
  write("one.csv", std::string(kTable) + block(0));
  write("two.csv", std::string(kTable) + block(0) + block(1));
  ASSERT_EQ(sh("run --no-progress --trace " + path("one.csv") + " --out " + path("o1")).code, 0);
  const Result r = sh("run --no-progress --trace " + path("two.csv") + " --out " + path("o2"));
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("over 2 frames (images: frame 0)"), std::string::npos) << r.out;
  const Json one = load_json(path("o1/report.json")), two = load_json(path("o2/report.json"));
  // Composited into one image, the two frames counted 1200 pixels; compared each on its own,
  // they are 2400 pixels, each frame's error that of the single-frame run.
  EXPECT_EQ(num(one, "accuracy.pixels"), 1200);
  EXPECT_EQ(num(two, "accuracy.pixels"), 2400);
  ASSERT_EQ(two.at("frames").size(), 2u);
  for (int f = 0; f < 2; ++f) {
    const Json& fr = two["frames"][f];
    EXPECT_EQ(num(fr, "accuracy.pixels"), 1200);
    EXPECT_DOUBLE_EQ(num(fr, "accuracy.psnr_db"), num(one, "accuracy.psnr_db"));
  }
  EXPECT_NEAR(num(two, "accuracy.psnr_db"), num(one, "accuracy.psnr_db"), 1e-9);
  EXPECT_EQ(num(two, "image.frame"), 0);
  EXPECT_NE(two.at("accuracy").at("reference").get<std::string>().find("its own ground truth"),
            std::string::npos);
  EXPECT_NE(slurp(path("o2/report.md")).find("| 1 | "), std::string::npos);
}

TEST_F(Cli, FrameOptionSelectsTheImagesWritten) {
  write("t.csv", std::string(kTable) + block(0) + block(1, 10));
  ASSERT_EQ(sh("run --no-progress --trace " + path("t.csv") + " --out " + path("a")).code, 0);
  const Result r =
      sh("run --no-progress --trace " + path("t.csv") + " --frame 1 --out " + path("b"));
  ASSERT_EQ(r.code, 0) << r.out;
  // Frame 1 covers rows 0..9 as frame 0 does; below them it shows the background.
  int wa = 0, wb = 0;
  const std::vector<uint8_t> a = read_rgb(path("a/image.png"), wa),
                             b = read_rgb(path("b/image.png"), wb);
  ASSERT_EQ(a.size(), 40u * 30 * 3);
  ASSERT_EQ(b.size(), a.size());
  for (int y = 0; y < 30; ++y) {
    const auto row = static_cast<std::ptrdiff_t>(y) * 40 * 3;
    const bool same = std::equal(a.begin() + row, a.begin() + row + 120, b.begin() + row);
    EXPECT_EQ(same, y < 10) << "row " << y;
  }
  EXPECT_EQ(num(load_json(path("b/report.json")), "image.frame"), 1);

  const Result missing =
      sh("run --no-progress --trace " + path("t.csv") + " --frame 7 --out " + path("c"));
  EXPECT_EQ(missing.code, 2) << missing.out;
  EXPECT_NE(missing.out.find("--frame 7: the trace has no such frame (its frames: 0, 1)"),
            std::string::npos)
      << missing.out;
  expect_no_outputs(path("c"));
}

TEST_F(Cli, FramesMustBeContiguous) {
  write("t.csv", std::string(kTable) + block(0, 1) + block(1, 1) + frag(0, 5, 5));
  const Result r = sh("run --no-progress --trace " + path("t.csv") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("record 80: frame 0 appears again after frame 1"), std::string::npos)
      << r.out;
  expect_no_outputs(path("o"));
}

// Peak resident memory of the children this process has waited for, in MiB.
long children_peak_mib() {
  rusage ru{};
  getrusage(RUSAGE_CHILDREN, &ru);
  return ru.ru_maxrss / 1024;
}

TEST_F(Cli, TwoFragmentsAcrossTheLargestImageAreRefusedBeforeTheRun) {
  // (0, 0) and (16383, 16383): buffers for the whole 16384² extent, about 9 GB.
  write("t.csv", std::string(kTable) + frag(0, 0, 0) + frag(0, 16383, 16383));
  const Result r = sh("run --no-progress --trace " + path("t.csv") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("its fragments cover pixels (0, 0) to (16383, 16383): the run needs an "
                       "estimated"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("over the --max-memory limit of 4.00 GiB"), std::string::npos) << r.out;
  EXPECT_LT(children_peak_mib(), 200);
  expect_no_outputs(path("o"));
}

TEST_F(Cli, BuffersFollowTheCoveredPixelsNotTheImageSize) {
  // Two fragments near the far corner of a 16384² image: buffers for 4 × 4 pixels; only the
  // written 8-bit image spans the whole canvas.
  write("t.csv", std::string(kTable) + frag(0, 16380, 16380) + frag(0, 16383, 16383));
  const Result r = sh("run --no-progress --trace " + path("t.csv") + " --out " + path("o"));
  ASSERT_EQ(r.code, 0) << r.out;
  const Json j = load_json(path("o/report.json"));
  EXPECT_EQ(num(j, "image.width"), 16384);
  EXPECT_EQ(num(j, "image.height"), 16384);
  EXPECT_EQ(num(j, "accuracy.pixels"), 2);
  // One 8-bit canvas (768 MiB) at a time; the float buffers of a 16384² image would be 9 GB.
  EXPECT_LT(children_peak_mib(), 1200);
}

TEST_F(Cli, LargestSceneImageIsEstimatedAndRefusedOrSizedByItsPlanes) {
  const std::string big =
      "[output]\nwidth = 16384\nheight = 16384\n"
      "[textures.t]\nsource = \"procedural:checker?size=64\"\n"
      "[materials.m]\ntexture = \"t\"\n[[planes]]\nmaterial = \"m\"\n";
  // A floor filling the lower half: refused, naming the scene's keys.
  write("full.toml", big +
                         "origin = [-500.0, -1.0, -0.5]\nedge_u = [1000.0, 0.0, 0.0]\n"
                         "edge_v = [0.0, 0.0, -1000.0]\n");
  const Result r = sh("run " + path("full.toml") + " --no-progress --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("full.toml: [output] width = 16384, height = 16384: the run needs an "
                       "estimated"),
            std::string::npos)
      << r.out;
  expect_no_outputs(path("o"));
  // A small square far away: buffers and the reference generator cover only its pixels.
  write("small.toml", big +
                          "origin = [-0.05, -0.05, -40.0]\nedge_u = [0.1, 0.0, 0.0]\n"
                          "edge_v = [0.0, 0.1, 0.0]\n");
  const Result s = sh("run " + path("small.toml") + " --no-progress --out " + path("s"));
  ASSERT_EQ(s.code, 0) << s.out;
  const Json j = load_json(path("s/report.json"));
  EXPECT_EQ(num(j, "image.width"), 16384);
  EXPECT_GT(num(j, "fragments"), 100);
  EXPECT_LT(children_peak_mib(), 1200);
}

TEST_F(Cli, MeshesAndObjectSpaceBuffersAreInTheEstimateBeforeAllocation) {
  // A 1024² grid mesh used 2 GB before --max-memory was checked.
  write("g.toml",
        "[output]\nwidth = 96\nheight = 72\n[camera]\nposition = [0.0, 1.0, 3.0]\n"
        "look_at = [0.0, 0.0, 0.0]\n[[meshes]]\nmaterial = \"m\"\nsource = \"grid\"\n"
        "cells = [1024, 1024]\n[textures.t]\nsource = \"procedural:checker?size=64\"\n"
        "[materials.m]\ntexture = \"t\"\n");
  Result r = sh("run --no-progress " + path("g.toml") + " --max-memory 1G --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("a grid of 1024 x 1024 cells would take an estimated"), std::string::npos)
      << r.out;
  EXPECT_LT(children_peak_mib(), 400);
  // The object-space passes' buffers of the whole image count too.
  r = sh("run --no-progress " + std::string(TEXSIM_SOURCE_DIR) +
         "/scenes/object_space.toml --set output.width=4096 --set output.height=4096 "
         "--max-memory 1G --out " +
         path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_EQ(r.out.find("object-space buffers: 0.00 GiB"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("object-space buffers: "), std::string::npos) << r.out;
  expect_no_outputs(path("o"));
}

TEST_F(Cli, TraceTextureErrorsNameTheTraceAndEntryAndSizesAreBounded) {
  write("t.csv",
        "# texture 0 crate nofile.png 64 64\n"
        "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,lod_bias\n" +
            frag(0, 1, 1));
  Result r = sh("run --no-progress --trace " + path("t.csv") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find(path("t.csv") + ": texture table entry 0 ('crate'): "), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("nofile.png"), std::string::npos) << r.out;
  // A procedural texture is bounded like a file (16384² rgba32f would be 5.7 GB).
  write("big.csv",
        "# texture 0 big \"procedural:noise?size=16384&format=rgba32f\" 16384 16384\n"
        "frame,prim,x,y,tex,u,v,dudx,dvdx,dudy,dvdy,lod_bias\n" +
            frag(0, 1, 1));
  r = sh("run --no-progress --trace " + path("big.csv") + " --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("size must be an integer in [1, 8192]"), std::string::npos) << r.out;
  EXPECT_LT(children_peak_mib(), 300);
  expect_no_outputs(path("o"));
}

TEST_F(Cli, MaxMemoryOptionIsParsedAndChecked) {
  write("t.csv", std::string(kTable) + block(0));
  Result r =
      sh("run --no-progress --trace " + path("t.csv") + " --max-memory 10K --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("over the --max-memory limit of 0.00 GiB"), std::string::npos) << r.out;
  r = sh("run --no-progress --trace " + path("t.csv") + " --max-memory lots --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--max-memory: 'lots' is not a size"), std::string::npos) << r.out;
  expect_no_outputs(path("o"));
  EXPECT_EQ(
      sh("run --no-progress --trace " + path("t.csv") + " --max-memory 1G --out " + path("o")).code,
      0);
}

#if !defined(__SANITIZE_ADDRESS__)
TEST_F(Cli, OutOfMemoryIsAClearErrorNotAnInternalOne) {
  // The estimate allows the run, the address space does not: the allocation fails.
  write("t.csv", std::string(kTable) + frag(0, 0, 0) + frag(0, 8000, 8000));
  const Result r =
      shell("ulimit -v 600000; " + std::string(TEXSIM_BINARY) + " run --no-progress --trace " +
            path("t.csv") + " --max-memory 100G --out " + path("o"));
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("texsim: error: out of memory"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("internal error"), std::string::npos) << r.out;
}
#endif

}  // namespace
