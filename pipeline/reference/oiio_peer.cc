#include "pipeline/reference/oiio_peer.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/oiioversion.h>
#include <OpenImageIO/texture.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <vector>

#include "blocks/base/input_error.h"

namespace texsim {

struct OiioPeer::Impl {
  OIIO::TextureSystem* ts = nullptr;
  OIIO::TextureSystem::TextureHandle* handle = nullptr;
  OIIO::TextureSystem::Perthread* thread = nullptr;
  mutable OIIO::TextureOpt opt;
};

namespace {
std::atomic<int> g_counter{0};

OIIO::TextureOpt::Wrap to_oiio(AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return OIIO::TextureOpt::WrapPeriodic;
    case AddressMode::Clamp:
      return OIIO::TextureOpt::WrapClamp;
    case AddressMode::Mirror:
      return OIIO::TextureOpt::WrapMirror;
  }
  return OIIO::TextureOpt::WrapPeriodic;
}
}  // namespace

OiioPeer::OiioPeer(const Texture& tex, const Config& cfg) : impl_(std::make_unique<Impl>()) {
  const int w = tex.width(0), h = tex.height(0);
  const bool u8 = tex.format() == TexelFormat::Rgba8;
  OIIO::ImageSpec spec(w, h, 4, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf src(spec);
  std::vector<float> px(static_cast<size_t>(w) * static_cast<size_t>(h) * 4);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const Rgba c = tex.texel(0, x, y);
      const size_t i =
          (static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)) * 4;
      px[i] = c.r;
      px[i + 1] = c.g;
      px[i + 2] = c.b;
      px[i + 3] = c.a;
    }
  }
  src.set_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, 4), OIIO::TypeDesc::FLOAT, px.data());
  const std::filesystem::path dir = cfg.tx_dir.empty() ? std::filesystem::temp_directory_path()
                                                       : std::filesystem::path(cfg.tx_dir);
  path_ = (dir / ("texsim_oiio_peer_" + std::to_string(::getpid()) + "_" +
                  std::to_string(g_counter++) + ".tx"))
              .string();
  OIIO::ImageSpec conf;
  conf.tile_width = 64;
  conf.tile_height = 64;
  conf.format = u8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
  conf.attribute("maketx:filtername", "box");
  const char* wrap = cfg.address == AddressMode::Wrap
                         ? "periodic"
                         : (cfg.address == AddressMode::Clamp ? "clamp" : "mirror");
  conf.attribute("wrapmodes", std::string(wrap) + "," + wrap);
  if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src, path_, conf)) {
    throw InputError(path_, "OpenImageIO make_texture failed: " + OIIO::geterror());
  }
  impl_->ts = OIIO::TextureSystem::create(false);
  impl_->ts->attribute("automip", 0);
  impl_->ts->attribute("max_memory_MB", 64.0f);
  impl_->handle = impl_->ts->get_texture_handle(OIIO::ustring(path_));
  impl_->thread = impl_->ts->get_perthread_info();
  if (!impl_->handle) throw InputError(path_, "OpenImageIO TextureSystem cannot open the .tx");
  OIIO::TextureOpt& o = impl_->opt;
  o.mipmode = cfg.aniso ? OIIO::TextureOpt::MipModeAniso : OIIO::TextureOpt::MipModeTrilinear;
  o.interpmode = OIIO::TextureOpt::InterpBilinear;
  o.anisotropic = cfg.max_aniso;
  o.swrap = o.twrap = to_oiio(cfg.address);
}

OiioPeer::~OiioPeer() {
  if (impl_ && impl_->ts) OIIO::TextureSystem::destroy(impl_->ts);
  std::error_code ec;
  if (!path_.empty()) std::filesystem::remove(path_, ec);
}

Rgba OiioPeer::lookup(const Fragment& f) const {
  float r[4] = {0, 0, 0, 0};
  if (!std::isfinite(f.u) || !std::isfinite(f.v) || !std::isfinite(f.dudx) ||
      !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) || !std::isfinite(f.dvdy)) {
    return {0, 0, 0, 0};
  }
  impl_->ts->texture(impl_->handle, impl_->thread, impl_->opt, static_cast<float>(f.u),
                     static_cast<float>(f.v), static_cast<float>(f.dudx),
                     static_cast<float>(f.dvdx), static_cast<float>(f.dudy),
                     static_cast<float>(f.dvdy), 4, r);
  return {r[0], r[1], r[2], r[3]};
}

std::string OiioPeer::version() const { return OIIO_VERSION_STRING; }

}  // namespace texsim
