#include "pipeline/reference/truth_key.h"

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <string_view>

#include "pipeline/reference/footprint_reference.h"
#include "pipeline/reference/ground_truth.h"

namespace texsim {

namespace {

// Values are hashed by value, each with a tag naming its field, so that no two different
// inputs feed the same bytes (and padding, e.g. a long double's, is never read).
class KeyWriter {
 public:
  void tag(std::string_view name) {
    u64(name.size());
    sha_.update(name.data(), name.size());
  }
  void u64(uint64_t v) {
    uint8_t b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<uint8_t>(v >> (8 * i));
    sha_.update(b, 8);
  }
  void i64(int64_t v) { u64(static_cast<uint64_t>(v)); }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  // A long double exactly: its exponent and its 64-bit significand.
  void f80(long double v) {
    static_assert(LDBL_MANT_DIG <= 64, "a long double's significand must fit 64 bits");
    int e = 0;
    const long double m = std::frexp(v, &e);
    // |m| in [½, 1) with 64 significant bits: |m|·2^64 is an integer below 2^64.
    u64(std::isfinite(v) ? static_cast<uint64_t>(std::ldexp(std::fabs(m), 64)) : 0);
    i64(e);
    u64(std::signbit(v) ? 1 : 0);
    u64(std::isnan(v) ? 2 : std::isinf(v) ? 1 : 0);
  }
  void v3(const glm::dvec3& v) {
    f64(v.x);
    f64(v.y);
    f64(v.z);
  }
  void v2(const glm::dvec2& v) {
    f64(v.x);
    f64(v.y);
  }
  void bytes(const void* p, size_t n) {
    u64(n);
    sha_.update(p, n);
  }
  TruthKey finish() { return sha_.finish(); }

 private:
  Sha256 sha_;
};

void write_camera(KeyWriter& w, const Camera& c) {
  w.tag("camera");
  w.v3(c.position);
  w.v3(c.look_at);
  w.v3(c.up);
  w.f80(c.tan_half_fov_y);
  w.f64(c.near);
  w.i64(c.width);
  w.i64(c.height);
  w.u64(c.orthographic ? 1 : 0);
  w.f80(c.ortho_half_height);
}

void write_primitive(KeyWriter& w, const ScenePrimitive& p) {
  w.tag("primitive");
  w.u64(static_cast<uint64_t>(p.shape));
  w.i64(p.material);
  w.v3(p.origin);
  w.v3(p.edge_u);
  w.v3(p.edge_v);
  w.v2(p.uv_origin);
  w.v2(p.uv_edge_u);
  w.v2(p.uv_edge_v);
  w.u64(p.cull_back ? 1 : 0);
}

void write_texture(KeyWriter& w, const Texture& t) {
  w.tag("texture");
  w.u64(static_cast<uint64_t>(t.format()));
  w.i64(t.levels());
  size_t texels = 0;
  for (int l = 0; l < t.levels(); ++l) {
    w.i64(t.width(l));
    w.i64(t.height(l));
    texels += static_cast<size_t>(t.width(l)) * static_cast<size_t>(t.height(l));
  }
  // The store holds every level, level after level: its content is the texture's.
  if (t.format() == TexelFormat::Rgba8) {
    w.bytes(t.rgba8(0), texels * 4);
  } else {
    w.bytes(t.rgba32f(0), texels * 4 * sizeof(float));
  }
}

}  // namespace

TruthKey truth_key(const TruthKeyInputs& in) {
  KeyWriter w;
  w.tag("texsim ground truth");
  w.u64(kTruthVersion);
  // The sampler's constants: a change there changes the truth even if the version is not
  // bumped.
  w.f64(TruthSampling::kTolerance);
  w.i64(TruthSampling::kMaxGrid);
  w.i64(TruthSampling::kMaxAspect);
  w.i64(TruthSampling::kMinPointsCap);
  w.f64(TruthSampling::kTexelsPerPoint);
  w.i64(TruthSampling::kTiers);
  const PixelModel gauss;
  w.f64(gauss.sigma_px);
  w.f64(gauss.radius_px);
  w.tag("reference");
  w.u64(static_cast<uint64_t>(in.pixel));
  w.i64(in.samples);
  w.tag("image");
  w.i64(in.width);
  w.i64(in.height);
  w.u64(in.cameras.size());
  for (const Camera& c : in.cameras) write_camera(w, c);
  const size_t prims = in.primitives ? in.primitives->size() : 0;
  w.u64(prims);
  for (size_t i = 0; i < prims; ++i) write_primitive(w, (*in.primitives)[i]);
  const int textures = in.textures ? in.textures->size() : 0;
  w.i64(textures);
  // The truth samples each texture as loaded, before any storage format (Texture::reference).
  for (int i = 0; i < textures; ++i) write_texture(w, (*in.textures)[i].reference());
  w.u64(in.materials.size());
  for (const TruthMaterialKey& m : in.materials) {
    w.tag("material");
    w.i64(m.texture);
    w.u64(static_cast<uint64_t>(m.address_u));
    w.u64(static_cast<uint64_t>(m.address_v));
    w.u64(m.surface ? 1 : 0);
    if (m.address_u == AddressMode::Border || m.address_v == AddressMode::Border) {
      for (int c = 0; c < 4; ++c) w.u64(std::bit_cast<uint32_t>(m.border[c]));
    }
    if (m.offset_u != 0 || m.offset_v != 0) {
      w.tag("offset");
      w.i64(m.offset_u);
      w.i64(m.offset_v);
    }
  }
  return w.finish();
}

TruthKey truth_tier_key(const TruthKey& key, int tier) {
  KeyWriter w;
  w.tag("texsim ground truth tier");
  w.bytes(key.data(), key.size());
  w.i64(tier);
  w.f64(TruthSampling::tolerance_of(tier));
  return w.finish();
}

}  // namespace texsim
