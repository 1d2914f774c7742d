// libtexsim_oiio.so: OpenImageIO behind oiio_plugin_api.h. The only file of texsim that
// includes OpenImageIO; built as its own shared library, never linked into texsim.
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/oiioversion.h>
#include <OpenImageIO/texture.h>

#include <cerrno>
#include <cstring>
#include <exception>

#include "pipeline/image_io/oiio_plugin_api.h"

namespace texsim::oiio {

namespace {

class OiioReader final : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {}
  bool seek_level(int level) override {
    level_ = level;
    return in_->seek_subimage(0, level);
  }
  LevelSpec spec() const override {
    const OIIO::ImageSpec& s = in_->spec();
    return {s.width, s.height, s.depth, s.nchannels, s.format == OIIO::TypeDesc::UINT8};
  }
  bool read_float(int channels, float* out) override {
    return in_->read_image(0, level_, 0, channels, OIIO::TypeDesc::FLOAT, out);
  }
  bool read_uint8(int channels, uint8_t* out) override {
    return in_->read_image(0, level_, 0, channels, OIIO::TypeDesc::UINT8, out);
  }
  std::string error() override { return in_->geterror(); }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  int level_ = 0;
};

OIIO::TextureOpt::Wrap wrap_mode(const std::string& name) {
  if (name == "clamp") return OIIO::TextureOpt::WrapClamp;
  if (name == "mirror") return OIIO::TextureOpt::WrapMirror;
  return OIIO::TextureOpt::WrapPeriodic;
}

class OiioPeer final : public TexturePeer {
 public:
  ~OiioPeer() override {
    if (ts_) OIIO::TextureSystem::destroy(ts_);
  }
  // Writes the .tx (OIIO builds its own MIP chain, box filter) and opens it; "" or the reason.
  std::string open(const PeerSetup& s) {
    OIIO::ImageBuf src(OIIO::ImageSpec(s.width, s.height, 4, OIIO::TypeDesc::FLOAT));
    src.set_pixels(OIIO::ROI(0, s.width, 0, s.height, 0, 1, 0, 4), OIIO::TypeDesc::FLOAT, s.rgba);
    OIIO::ImageSpec conf;
    conf.tile_width = 64;
    conf.tile_height = 64;
    conf.format = s.uint8 ? OIIO::TypeDesc::UINT8 : OIIO::TypeDesc::FLOAT;
    conf.attribute("maketx:filtername", "box");
    conf.attribute("wrapmodes", std::string(s.wrap) + "," + s.wrap);
    if (!OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, src, s.tx_path,
                                          conf)) {
      return "OpenImageIO make_texture failed: " + OIIO::geterror();
    }
    ts_ = OIIO::TextureSystem::create(false);
    ts_->attribute("automip", 0);
    ts_->attribute("max_memory_MB", 64.0f);
    handle_ = ts_->get_texture_handle(OIIO::ustring(s.tx_path));
    thread_ = ts_->get_perthread_info();
    if (!handle_) return "OpenImageIO TextureSystem cannot open the .tx";
    opt_.mipmode = s.aniso ? OIIO::TextureOpt::MipModeAniso : OIIO::TextureOpt::MipModeTrilinear;
    opt_.interpmode = OIIO::TextureOpt::InterpBilinear;
    opt_.anisotropic = s.max_aniso;
    opt_.swrap = opt_.twrap = wrap_mode(s.wrap);
    return "";
  }
  void lookup(const float q[6], float rgba[4]) const override {
    ts_->texture(handle_, thread_, opt_, q[0], q[1], q[2], q[3], q[4], q[5], 4, rgba);
  }

 private:
  OIIO::TextureSystem* ts_ = nullptr;
  OIIO::TextureSystem::TextureHandle* handle_ = nullptr;
  OIIO::TextureSystem::Perthread* thread_ = nullptr;
  mutable OIIO::TextureOpt opt_;
};

class OiioPlugin final : public Plugin {
 public:
  std::string version() const override { return OIIO_VERSION_STRING; }

  std::unique_ptr<ImageReader> open(const std::string& path, std::string* error) override {
    try {
      auto in = OIIO::ImageInput::open(path);
      if (in) return std::make_unique<OiioReader>(std::move(in));
      *error = OIIO::geterror();
    } catch (const std::exception& e) {
      *error = e.what();
    }
    return nullptr;
  }

  bool write_uint8(const std::string& path, const std::string& format_from, int width, int height,
                   int channels, const uint8_t* pixels, bool fast, std::string* error) override {
    try {
      auto out = OIIO::ImageOutput::create(format_from);
      if (!out) {
        *error = "no image writer for this file type: " + OIIO::geterror();
        return false;
      }
      OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
      if (fast) {
        spec.attribute("png:compressionLevel", 1);
        spec.attribute("png:filter", 8);  // PNG_FILTER_NONE: no per-row filter search
      }
      errno = 0;
      if (out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels) &&
          out->close()) {
        return true;
      }
      // The library's message names the file it wrote; errno says more when it is set.
      *error = errno ? std::strerror(errno) : out->geterror();
    } catch (const std::exception& e) {
      *error = e.what();
    }
    return false;
  }

  std::unique_ptr<TexturePeer> make_peer(const PeerSetup& setup, std::string* error) override {
    try {
      auto peer = std::make_unique<OiioPeer>();
      *error = peer->open(setup);
      if (error->empty()) return peer;
    } catch (const std::exception& e) {
      *error = e.what();
    }
    return nullptr;
  }
};

}  // namespace

}  // namespace texsim::oiio

extern "C" __attribute__((visibility("default"))) texsim::oiio::Plugin* texsim_oiio_plugin(
    int abi) {
  static texsim::oiio::OiioPlugin plugin;
  return abi == texsim::oiio::kAbi ? &plugin : nullptr;
}
