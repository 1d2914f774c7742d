// texsim's filters against a real renderer: Mesa's softpipe, whose anisotropic path is
// Heckbert's EWA, and llvmpipe draw the floor of scenes/photo.toml (a grass photograph seen at a
// grazing angle) from the same camera, plane and mip pyramid (pipeline/reference/mesa_peer.h).
// texsim's EWA must agree with softpipe's to ≥ 50 dB PSNR over the floor's pixels. Skipped,
// with the reason, where Mesa cannot start.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

#include "blocks/base/input_error.h"
#include "blocks/base/tech_table.h"
#include "pipeline/geometry/plane_projection.h"
#include "pipeline/reference/footprint_reference.h"
#include "pipeline/reference/mesa_peer.h"
#include "pipeline/scene/scene.h"
#include "pipeline/scene/texture_loader.h"
#include "pipeline/texture/effect_registry.h"
#include "pipeline/texture/texture_unit.h"

namespace texsim {
namespace {

// The photo scene's floor: its plane, texture and fragments (pixel centres, analytic
// derivatives, as the study's views).
struct Floor {
  Scene scene = load_scene(std::string(TEXSIM_SOURCE_DIR) + "/scenes/photo.toml");
  TextureSet set;
  std::vector<Fragment> frags;
  int tex = 0;  // the floor's texture in `set` (every scene texture, in order)
  Floor() {
    const ScenePrimitive& p = scene.primitives[0];
    for (const SceneTexture& t : scene.textures) set.add(load_texture(t.source, scene.base_dir));
    set.place(TexelLayout::Tiled4x4);
    tex = scene.materials[static_cast<size_t>(p.material)].texture;
    const PlaneProjection proj(scene, p);
    for (int y = 0; y < scene.height; ++y) {
      for (int x = 0; x < scene.width; ++x) {
        const UvSample s = proj.at(x + 0.5, y + 0.5);
        if (!s.inside) continue;
        frags.push_back(s.fragment(static_cast<uint32_t>(x), static_cast<uint32_t>(y)));
        frags.back().tex = static_cast<uint32_t>(tex);
      }
    }
  }
  // The fragments with OpenGL's coarse derivatives, as softpipe takes them: differences of
  // u, v across the top row and the left column of the fragment's 2x2 pixel quad.
  std::vector<Fragment> quad_derivative_frags() const {
    const PlaneProjection proj(scene, scene.primitives[0]);
    std::vector<Fragment> out = frags;
    for (Fragment& f : out) {
      const double x0 = (f.x & ~1u) + 0.5, y0 = (f.y & ~1u) + 0.5;
      const UvSample a = proj.at(x0, y0), b = proj.at(x0 + 1, y0), c = proj.at(x0, y0 + 1);
      f.dudx = b.u - a.u;
      f.dvdx = b.v - a.v;
      f.dudy = c.u - a.u;
      f.dvdy = c.v - a.v;
    }
    return out;
  }
  // The floor alone as Mesa draws it (wrap addressing, as the scene's floor material).
  MesaView view(bool aniso) const {
    Scene only = scene;
    only.primitives.resize(1);
    MesaView v =
        mesa_view(only, set, std::vector<AddressMode>(scene.materials.size(), AddressMode::Wrap));
    v.filter = aniso ? MesaFilter::Anisotropic : MesaFilter::Trilinear;
    return v;
  }
  // texsim's functional texture unit with one material given by its effect tables' TOML.
  std::vector<Rgba> texsim(const std::string& effects) { return texsim(effects, frags); }
  std::vector<Rgba> texsim(const std::string& effects, const std::vector<Fragment>& fs) {
    const toml::table t = toml::parse(effects);
    const MaterialSetup mat = material_from_toml("floor", tex, t, "test");
    TextureUnit unit(set, {mat}, PipelineSetup{}, TechTable::defaults(), false);
    std::vector<Rgba> out;
    out.reserve(fs.size());
    for (const Fragment& f : fs) out.push_back(unit.process(f, 0));
    return out;
  }
  std::vector<Rgba> mesa(const MesaPeer& peer, bool aniso) const {
    const MesaImage img = peer.render(view(aniso));
    std::vector<Rgba> out;
    out.reserve(frags.size());
    for (const Fragment& f : frags)
      out.push_back(img.at(static_cast<int>(f.x), static_cast<int>(f.y)));
    return out;
  }
};

// PSNR (peak 1) of a against b over R, G, B.
double psnr(const std::vector<Rgba>& a, const std::vector<Rgba>& b) {
  double se = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double e = static_cast<double>(a[i][c]) - b[i][c];
      se += e * e;
    }
  }
  const double mse = se / (3.0 * static_cast<double>(a.size()));
  return mse > 0 ? 10.0 * std::log10(1.0 / mse) : 999.0;
}

// Colours rounded to 8 bits, as Mesa's RGBA8 framebuffer stores them.
std::vector<Rgba> rgba8(std::vector<Rgba> c) {
  for (Rgba& p : c) {
    for (int k = 0; k < 4; ++k) p[k] = std::round(p[k] * 255.0f) / 255.0f;
  }
  return c;
}

// A started peer, or the test skipped with Mesa's reason.
#define REQUIRE_MESA(peer) \
  if (!(peer).available()) GTEST_SKIP() << (peer).why_not()

TEST(MesaPeer, SoftpipeEwaAgreesWithTexsimEwaOnThePhotoFloor) {
  const MesaPeer softpipe(MesaDriver::Softpipe);
  REQUIRE_MESA(softpipe);
  Floor floor;
  ASSERT_GT(floor.frags.size(), 50000u);
  const std::vector<Rgba> ewa = floor.texsim("ewa = {}\n");
  const std::vector<Rgba> mesa = floor.mesa(softpipe, true);
  const double db = psnr(ewa, mesa);
  std::cout << "texsim EWA vs " << softpipe.renderer() << " EWA on scenes/photo.toml's floor ("
            << floor.frags.size() << " pixels): " << db << " dB\n";
  RecordProperty("psnr_texsim_ewa_vs_softpipe_db", std::to_string(db));
  EXPECT_GE(db, 50.0);
}

// With softpipe's own inputs (its 2x2-quad derivatives, its 8-bit output) the two EWAs are
// closer still: what remains is the filters themselves (texsim's 256-entry weight LUT and
// float set-up against softpipe's own Gaussian weight table).
TEST(MesaPeer, SoftpipeEwaAgreesWithTexsimEwaOnTheSameDerivatives) {
  const MesaPeer softpipe(MesaDriver::Softpipe);
  REQUIRE_MESA(softpipe);
  Floor floor;
  const double db = psnr(rgba8(floor.texsim("ewa = {}\n", floor.quad_derivative_frags())),
                         floor.mesa(softpipe, true));
  std::cout << "texsim EWA on 2x2-quad derivatives, rounded to 8 bits, vs softpipe EWA: " << db
            << " dB\n";
  EXPECT_GE(db, 56.0);
}

// Both EWAs against the Gaussian-pixel ground truth (footprint_reference.h) on every
// `stride`-th floor pixel: texsim's must be at least as close as softpipe's, within 0.5 dB.
TEST(MesaPeer, EwaAgainstTheGaussianPixelTruth) {
  const MesaPeer softpipe(MesaDriver::Softpipe);
  REQUIRE_MESA(softpipe);
  Floor floor;
  const std::vector<Rgba> ewa = floor.texsim("ewa = {}\n");
  const std::vector<Rgba> mesa = floor.mesa(softpipe, true);
  const PlaneProjection proj(floor.scene, floor.scene.primitives[0]);
  const size_t stride = 29;
  std::vector<Rgba> truth, a, b;
  for (size_t i = 0; i < floor.frags.size(); i += stride) {
    const Fragment& f = floor.frags[i];
    truth.emplace_back(footprint_reference(floor.set[floor.tex], proj, static_cast<int>(f.x),
                                           static_cast<int>(f.y), FootprintReferenceConfig{})
                           .colour);
    a.push_back(ewa[i]);
    b.push_back(mesa[i]);
  }
  const double da = psnr(a, truth), db = psnr(b, truth);
  std::cout << "Gaussian-pixel truth on " << truth.size() << " floor pixels: texsim EWA " << da
            << " dB, softpipe EWA " << db << " dB, texsim vs softpipe " << psnr(a, b) << " dB\n";
  EXPECT_GE(da, db - 0.5);
}

// Trilinear filtering leaves little freedom: texsim's and Mesa's agree closely.
TEST(MesaPeer, TrilinearAgreesWithTexsimTrilinear) {
  for (MesaDriver d : {MesaDriver::Softpipe, MesaDriver::Llvmpipe}) {
    const MesaPeer peer(d);
    REQUIRE_MESA(peer);
    Floor floor;
    const double db = psnr(floor.texsim("filter = { mode = \"trilinear\", address = \"wrap\" }\n"),
                           floor.mesa(peer, false));
    std::cout << "texsim trilinear vs " << peer.renderer() << " trilinear: " << db << " dB\n";
    // softpipe takes one LOD per 2x2 quad, llvmpipe one per pixel as texsim does.
    EXPECT_GE(db, d == MesaDriver::Softpipe ? 40.0 : 50.0) << to_string(d);
  }
}

// Where Mesa cannot start, the peer says why instead of failing.
TEST(MesaPeer, UnavailableSaysWhy) {
  setenv("TEXSIM_NO_MESA", "1", 1);
  const MesaPeer peer(MesaDriver::Llvmpipe);
  unsetenv("TEXSIM_NO_MESA");
  EXPECT_FALSE(peer.available());
  EXPECT_EQ(peer.why_not().rfind("Mesa not available: ", 0), 0u) << peer.why_not();
  EXPECT_THROW(peer.render(MesaView{}), InputError);
}

}  // namespace
}  // namespace texsim
