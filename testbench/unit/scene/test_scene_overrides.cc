// --set KEY=VALUE: each override changes the scene as the same key in the file would, and is
// validated the same way, with messages naming the override.
#include <gtest/gtest.h>

#include "blocks/base/input_error.h"
#include "pipeline/scene/scene.h"

namespace texsim {
namespace {

std::string error_of(const std::vector<std::string>& sets) {
  try {
    default_scene(sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SceneOverrides, ChangeKeysAsTheFileWould) {
  const Scene base = default_scene();
  const Scene s =
      default_scene({"output.width=100", "output.background=[0.5, 0.25, 1]", "camera.fov_y=45",
                     "planes.1.material=floor", "reference.supersamples=3", "tech.clock_mhz=250",
                     "tech.latency.mul=5", "pipeline.dram={ latency = 7 }"});
  EXPECT_EQ(s.width, 100);
  EXPECT_EQ(s.height, base.height);
  EXPECT_EQ(s.background, glm::dvec3(0.5, 0.25, 1));
  EXPECT_EQ(s.primitives[1].material, s.primitives[0].material);
  EXPECT_NE(base.primitives[1].material, base.primitives[0].material);
  EXPECT_EQ(s.reference_samples, 3);
  EXPECT_EQ(s.tech.clock_mhz, 250);
  EXPECT_EQ(s.tech.lat(OpKind::Mul), 5);
  ASSERT_NE(s.pipeline, nullptr);
  EXPECT_EQ((*s.pipeline)["dram"]["latency"].value<int64_t>(), 7);
  // Later overrides win; a bare word is a string.
  EXPECT_EQ(default_scene({"output.width=100", "output.width=50"}).width, 50);
  EXPECT_EQ(default_scene({"textures.checker.source=procedural:noise"}).textures[0].source,
            "procedural:noise");
}

TEST(SceneOverrides, BadOverridesNameTheOption) {
  EXPECT_EQ(error_of({"output.width=0"}),
            "--set output.width: scene.output.width: value 0 out of range [1, 16384]");
  EXPECT_EQ(error_of({"camera.fov_y=\"x\""}).find("--set camera.fov_y: "), 0u);
  EXPECT_EQ(error_of({"planes.9.material=floor"}),
            "--set planes.9.material: 'planes.9': the array has 3 elements (indices from 0)");
  EXPECT_EQ(error_of({"output.width.x=3"}),
            "--set output.width.x: 'output.width' is a value, not a table or array");
  EXPECT_EQ(error_of({"width"}), "--set width: expected KEY=VALUE");
  EXPECT_EQ(error_of({"output..width=3"}), "--set output..width: empty key in 'output..width'");
  EXPECT_NE(error_of({"camera.fov_y=[1,"}).find("--set camera.fov_y: '[1,' is not a TOML value"),
            std::string::npos);
  EXPECT_NE(error_of({"frob.x=1"}).find("unknown key 'frob'"), std::string::npos);
}

// A value holding a newline would add lines to the scene (`output.width=100\n[frob]`): every
// control character but tab is refused, naming the override and the byte.
TEST(SceneOverrides, ControlCharactersAreRefused) {
  EXPECT_EQ(error_of({"output.width=100\nother = 1"}),
            "--set output.width: control character \\x0a at byte 17: a --set KEY=VALUE is one "
            "line without control characters");
  EXPECT_NE(error_of({"output.width=100\r"}).find("control character \\x0d at byte 17"),
            std::string::npos);
  EXPECT_NE(error_of({"materials.floor.filter.mode=\"ewa\x1b[2J\""}).find("\\x1b"),
            std::string::npos);
  EXPECT_NE(error_of({"output.wi\ndth=3"}).find("--set output.wi: control character \\x0a"),
            std::string::npos);
  EXPECT_NE(error_of({"output.width=1\x7f"}).find("\\x7f"), std::string::npos);
  EXPECT_EQ(default_scene({"output.background=[0.5,\t0.25, 1]"}).background,
            glm::dvec3(0.5, 0.25, 1));
}

}  // namespace
}  // namespace texsim
