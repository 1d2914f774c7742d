#include "pipeline/reference/oiio_peer.h"

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <vector>

#include "blocks/base/input_error.h"
#include "pipeline/image_io/oiio_plugin.h"

namespace texsim {

struct OiioPeer::Impl {
  oiio::Plugin* plugin = nullptr;
  std::unique_ptr<oiio::TexturePeer> peer;
};

namespace {
std::atomic<int> g_counter{0};

const char* wrap_name(AddressMode m) {
  switch (m) {
    case AddressMode::Wrap:
      return "periodic";
    case AddressMode::Clamp:
      return "clamp";
    case AddressMode::Mirror:
      return "mirror";
    case AddressMode::Border:
      return "black";  // OpenImageIO's border is transparent black
    case AddressMode::MirrorClamp:
      return nullptr;  // no OpenImageIO wrap mode: refused below
  }
  return "periodic";
}
}  // namespace

OiioPeer::OiioPeer(const Texture& tex, const Config& cfg) : impl_(std::make_unique<Impl>()) {
  const int w = tex.width(0), h = tex.height(0);
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
  const std::filesystem::path dir = cfg.tx_dir.empty() ? std::filesystem::temp_directory_path()
                                                       : std::filesystem::path(cfg.tx_dir);
  const std::string path = (dir / ("texsim_oiio_peer_" + std::to_string(::getpid()) + "_" +
                                   std::to_string(g_counter++) + ".tx"))
                               .string();
  impl_->plugin = &oiio_plugin("the OpenImageIO peer");
  oiio::PeerSetup setup;
  setup.width = w;
  setup.height = h;
  setup.rgba = px.data();
  setup.uint8 = tex.format() == TexelFormat::Rgba8;
  setup.wrap = wrap_name(cfg.address);
  if (!setup.wrap) throw InputError("OpenImageIO peer", "has no mirror_clamp address mode");
  setup.aniso = cfg.aniso;
  setup.max_aniso = cfg.max_aniso;
  setup.tx_path = path;
  path_ = path;  // removed by the destructor, whatever make_peer left there
  std::string error;
  impl_->peer = impl_->plugin->make_peer(setup, &error);
  if (!impl_->peer) {
    std::error_code ec;
    std::filesystem::remove(path_, ec);  // a half-written .tx
    throw InputError(path_, error);
  }
}

OiioPeer::~OiioPeer() {
  impl_.reset();  // the TextureSystem first: it holds the .tx open
  std::error_code ec;
  if (!path_.empty()) std::filesystem::remove(path_, ec);
}

Rgba OiioPeer::lookup(const Fragment& f) const {
  if (!std::isfinite(f.u) || !std::isfinite(f.v) || !std::isfinite(f.dudx) ||
      !std::isfinite(f.dvdx) || !std::isfinite(f.dudy) || !std::isfinite(f.dvdy)) {
    return {0, 0, 0, 0};
  }
  const float q[6] = {static_cast<float>(f.u),    static_cast<float>(f.v),
                      static_cast<float>(f.dudx), static_cast<float>(f.dvdx),
                      static_cast<float>(f.dudy), static_cast<float>(f.dvdy)};
  float r[4] = {0, 0, 0, 0};
  impl_->peer->lookup(q, r);
  return {r[0], r[1], r[2], r[3]};
}

std::string OiioPeer::version() const { return impl_->plugin->version(); }

}  // namespace texsim
