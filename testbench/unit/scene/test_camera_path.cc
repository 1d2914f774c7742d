// Camera paths: frame k's camera is the path's interpolation at t_k = k/(N-1) (position
// linear, orientation slerped), checked against values worked out by hand; the frames' fragments
// differ; a shipped path scene runs as a multi-frame run with a report per frame; bad paths are
// errors naming the key.
#include <gtest/gtest.h>

#include <cmath>
#include <glm/geometric.hpp>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "pipeline/app/fragment_router.h"
#include "pipeline/app/run.h"
#include "pipeline/raster/fragment_generator.h"
#include "pipeline/scene/scene.h"
#include "testbench/lib/cli_harness.h"
#include "testbench/lib/error_of.h"
#include "testbench/lib/temp_dir.h"

namespace texsim {
namespace {

const char* const kRest = R"(
[textures.t]
source = "procedural:checker?size=64&cells=8"
[materials.m]
texture = "t"
[[planes]]
material = "m"
origin = [-4.0, -1.0, 2.0]
edge_u = [8.0, 0.0, 0.0]
edge_v = [0.0, 0.0, -8.0]
)";

Scene scene(const std::string& head) { return parse_scene(head + kRest, "p.toml", ""); }
std::string error(const std::string& head) {
  return error_of([&] { (void)scene(head); });
}

void expect_near(const glm::dvec3& a, const glm::dvec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-9);
  EXPECT_NEAR(a.y, b.y, 1e-9);
  EXPECT_NEAR(a.z, b.z, 1e-9);
}

// The unit view direction and up of a camera.
glm::dvec3 dir(const Camera& c) { return glm::normalize(c.look_at - c.position); }

TEST(CameraPath, FrameKIsThePathAtKOverNMinusOne) {
  // Four frames over t in [0, 1]; the camera slides along x and turns from -z to -x (a quarter
  // turn about y), its look-at point 2 units ahead throughout.
  const Scene s = scene(R"([output]
width = 64
height = 48
frames = 4
[camera]
path = [ { t = 0.0, position = [0.0, 0.0, 0.0], look_at = [0.0, 0.0, -2.0] },
         { t = 1.0, position = [3.0, 0.0, 0.0], look_at = [1.0, 0.0, 0.0] } ]
)");
  ASSERT_EQ(s.frames, 4);
  for (int k = 0; k < 4; ++k) {
    const Camera c = frame_camera(s, k);
    const double t = k / 3.0, a = t * std::acos(-1.0) / 2;  // the turn so far
    expect_near(c.position, glm::dvec3(3 * t, 0, 0));
    expect_near(dir(c), glm::dvec3(-std::sin(a), 0, -std::cos(a)));
    expect_near(glm::normalize(c.up), glm::dvec3(0, 1, 0));
    EXPECT_NEAR(glm::length(c.look_at - c.position), 2, 1e-9);
  }
  // Frame 0 is the scene's own camera.
  expect_near(s.camera.position, glm::dvec3(0));
  expect_near(dir(s.camera), glm::dvec3(0, 0, -1));
}

TEST(CameraPath, AviationKeysAndSeveralSegments) {
  // yaw 90 looks along -z (as [camera] yaw does); three keys at uneven times: frame 2 of 3 is
  // at t = 4, the middle of the second segment.
  const Scene s = scene(R"([output]
frames = 3
[camera]
path = [ { t = 0.0, position = [0.0, 1.0, 0.0], yaw = 90.0 },
         { t = 2.0, position = [0.0, 1.0, -2.0], yaw = 90.0 },
         { t = 4.0, position = [0.0, 3.0, -2.0], yaw = 90.0, pitch = -90.0 } ]
)");
  expect_near(dir(frame_camera(s, 0)), glm::dvec3(0, 0, -1));
  const Camera c1 = frame_camera(s, 1);  // t = 2: the second key
  expect_near(c1.position, glm::dvec3(0, 1, -2));
  const Camera c2 = frame_camera(s, 2);  // t = 4: the last key, looking straight down
  expect_near(c2.position, glm::dvec3(0, 3, -2));
  expect_near(dir(c2), glm::dvec3(0, -1, 0));
}

TEST(CameraPath, EveryFrameHasItsOwnFragments) {
  const Scene s = scene(R"([output]
width = 32
height = 24
frames = 2
[camera]
path = [ { t = 0.0, position = [0.0, 1.0, 0.0], look_at = [0.0, 0.0, -4.0] },
         { t = 1.0, position = [1.0, 2.0, 0.0], look_at = [-1.0, 0.0, -4.0] } ]
)");
  std::vector<std::vector<Fragment>> frames;
  for (int k = 0; k < 2; ++k) {
    Scene f = s;
    f.camera = frame_camera(s, k);
    frames.push_back(generate_fragments(f, static_cast<uint32_t>(k)));
    ASSERT_FALSE(frames.back().empty());
    for (const Fragment& g : frames.back()) ASSERT_EQ(g.frame, static_cast<uint32_t>(k));
  }
  // The same pixels see other texture coordinates in the second frame.
  std::map<std::pair<uint32_t, uint32_t>, std::pair<double, double>> first;
  for (const Fragment& g : frames[0]) first[{g.x, g.y}] = {g.u, g.v};
  size_t same_pixel = 0, differ = 0;
  for (const Fragment& g : frames[1]) {
    const auto it = first.find({g.x, g.y});
    if (it == first.end()) continue;
    ++same_pixel;
    if (it->second != std::make_pair(static_cast<double>(g.u), static_cast<double>(g.v))) ++differ;
  }
  EXPECT_GT(same_pixel, frames[0].size() / 2);
  EXPECT_EQ(differ, same_pixel);
}

TEST(CameraPath, BadPathsNameTheKey) {
  EXPECT_EQ(error("[output]\nframes = 3\n"),
            "p.toml:1:1: output.frames = 3: several frames need a [camera] path to move along");
  EXPECT_NE(error("[camera]\npath = [ { t = 1.0, position = [0.0, 0.0, 0.0], look_at = [0.0, "
                  "0.0, -1.0] }, { t = 1.0, position = [1.0, 0.0, 0.0], look_at = [0.0, 0.0, "
                  "-1.0] } ]\n")
                .find("camera.path[1].t: times must increase"),
            std::string::npos);
  EXPECT_NE(error("[camera]\npath = [ { t = 0.0, position = [0.0, 0.0, 0.0] } ]\n")
                .find("camera.path[0]"),
            std::string::npos);
  EXPECT_NE(error("[camera]\nposition = [0.0, 0.0, 0.0]\npath = [ { t = 0.0, position = [0.0, "
                  "0.0, 0.0], yaw = 10.0 } ]\n")
                .find("not together with path"),
            std::string::npos);
  EXPECT_NE(error("[camera]\npath = [ { t = 0.0, position = [0.0, 0.0, 0.0], look_at = [0.0, "
                  "0.0, 0.0] } ]\n")
                .find("camera direction is zero"),
            std::string::npos);
}

using cli_harness::Cli;

TEST_F(Cli, ThePathSceneRunsEveryFrameWithItsOwnTruth) {
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/camera_path.toml";
  const auto r = cli_harness::sh("run " + scene + " --no-progress --frame 2 --out " + path("o"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = cli_harness::load_json(path("o/report.json"));
  ASSERT_EQ(j.at("frames").size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(j["frames"][k]["frame"], k);
    EXPECT_GT(j["frames"][k]["accuracy"]["pixels"].get<double>(), 1000);
  }
  EXPECT_NE(j["frames"][0]["fragments"], j["frames"][3]["fragments"]);
  // The trace of the same path holds the same four frames.
  const auto g = cli_harness::sh("trace gen " + scene + " -o " + path("p.csv"));
  ASSERT_EQ(g.code, 0) << g.out;
  const std::string csv = cli_harness::slurp(path("p.csv"));
  EXPECT_NE(csv.find("\n3,"), std::string::npos);
  EXPECT_EQ(csv.find("\n4,"), std::string::npos);
  EXPECT_NE(cli_harness::sh("run " + scene + " --no-progress --frame 4 --out " + path("x"))
                .out.find("--frame 4: the scene renders frames 0 to 3"),
            std::string::npos);
}

TEST(FrameOrder, PassesRecordsOnFrameByFrame) {
  std::vector<std::pair<uint32_t, uint64_t>> out;  // (frame, index) as passed on
  FrameOrder order([&](const Fragment& f, const Fragment&, int, const Rgba*, uint64_t i) {
    out.emplace_back(f.frame, i);
  });
  auto frag = [](uint32_t frame) {
    Fragment f;
    f.frame = frame;
    return f;
  };
  const Rgba c(0, 0, 0, 1);
  for (uint64_t i = 0; i < 3; ++i) order.emitted(0);
  order.record(frag(0), frag(0), 0, &c, 1);
  order.emitted(1);
  order.emitted(1);
  order.record(frag(1), frag(1), 0, &c, 4);  // frame 0 not complete: held
  order.emitted(3);
  order.record(frag(3), frag(3), 0, nullptr, 5);  // held too
  order.record(frag(0), frag(0), 0, &c, 0);
  EXPECT_EQ(out.size(), 2u);
  order.record(frag(0), frag(0), 0, &c, 2);  // frame 0 complete: frame 1's held record follows
  order.record(frag(1), frag(1), 0, &c, 3);  // frame 1 complete: frame 3's
  order.check_drained();
  const std::vector<std::pair<uint32_t, uint64_t>> want = {{0, 1}, {0, 0}, {0, 2},
                                                           {1, 4}, {1, 3}, {3, 5}};
  EXPECT_EQ(out, want);
}

// Several units on a camera path: every frame judged through its own maps, whatever the
// order the units commit in, so the accuracy equals one unit's, frame by frame.
TEST(CameraPathOnUnits, SixteenUnitsGiveOneUnitsImagesFrameByFrame) {
  const std::string scene = std::string(TEXSIM_SOURCE_DIR) + "/scenes/camera_path.toml";
  auto run = [&](const std::string& units, const std::string& out) {
    RunOptions o;
    o.scene = scene;
    o.out = out;
    o.threads = 2;
    o.workload = false;
    o.overrides = {"pipeline.units=" + units, "pipeline.l2.size_bytes=262144",
                   "pipeline.dram.model=banked", "reference.samples=2"};
    std::ostringstream log;
    run_simulation(o, log);
    return cli_harness::load_json(out + "/report.json");
  };
  const TempDir dir("camera_path_units");
  const auto one = run("1", dir.file("one")), many = run("16", dir.file("many"));
  ASSERT_EQ(one.at("frames").size(), 4u);
  ASSERT_EQ(many.at("frames").size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(many["frames"][k]["fragments"], one["frames"][k]["fragments"]) << k;
    EXPECT_EQ(many["frames"][k]["accuracy"], one["frames"][k]["accuracy"]) << k;
    EXPECT_LT(many["frames"][k]["cycles_end"].get<double>(),
              one["frames"][k]["cycles_end"].get<double>());
  }
  EXPECT_EQ(many["scheduler"]["late_items"], 0);
}

}  // namespace
}  // namespace texsim
