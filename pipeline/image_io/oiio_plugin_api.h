#pragma once
// The interface between texsim and its OpenImageIO plugin, libtexsim_oiio.so
// (oiio_backend.cc). OpenImageIO pulls in about 260 shared libraries whose initialisers cost
// ~0.2 s and ~120 MB at every process start, so texsim does not link it: the plugin is opened
// with dlopen the first time a file needs OpenImageIO (oiio_plugin.h). Both sides are built
// from this header by the same build; kAbi changes whenever it does, and the loader refuses a
// plugin of another ABI. Nothing here throws across the boundary: failures come back as
// false/null with the reason in `error`.
#include <cstdint>
#include <memory>
#include <string>

namespace texsim::oiio {

inline constexpr int kAbi = 1;
inline constexpr const char* kLibraryName = "libtexsim_oiio.so";
inline constexpr const char* kEntryPoint = "texsim_oiio_plugin";

// One MIP level of an opened file, as OpenImageIO describes it.
struct LevelSpec {
  int width = 0, height = 0, depth = 0, channels = 0;
  bool uint8 = false;  // stored as 8-bit unsigned
};

// An image file open for reading (OpenImageIO's ImageInput): its first subimage, level by level.
class ImageReader {
 public:
  virtual ~ImageReader() = default;
  // Moves to MIP level `level`; false when the file has no such level.
  virtual bool seek_level(int level) = 0;
  virtual LevelSpec spec() const = 0;
  // Channels [0, channels) of the current level, pixel-interleaved, top row first, converted
  // to float or to 8-bit by OpenImageIO. False on failure (error()).
  virtual bool read_float(int channels, float* out) = 0;
  virtual bool read_uint8(int channels, uint8_t* out) = 0;
  virtual std::string error() = 0;
};

// OpenImageIO's TextureSystem on one texture (pipeline/reference/oiio_peer.h).
class TexturePeer {
 public:
  virtual ~TexturePeer() = default;
  // One filtered lookup at (u, v) with derivatives dudx, dvdx, dudy, dvdy, all finite.
  virtual void lookup(const float query[6], float rgba[4]) const = 0;
};

struct PeerSetup {
  int width = 0, height = 0;
  const float* rgba = nullptr;    // level 0, 4 floats per texel, top row first
  bool uint8 = false;             // store the .tx as 8-bit (else float)
  const char* wrap = "periodic";  // "periodic", "clamp" or "mirror"
  bool aniso = true;              // MipModeAniso (else trilinear)
  int max_aniso = 16;
  std::string tx_path;  // where the tiled, MIP-mapped .tx is written
};

class Plugin {
 public:
  virtual ~Plugin() = default;
  // OpenImageIO's version, as the plugin was built against ("2.4.7").
  virtual std::string version() const = 0;
  // Opens `path` for reading; null with the reason in `error` when OpenImageIO cannot.
  virtual std::unique_ptr<ImageReader> open(const std::string& path, std::string* error) = 0;
  // Writes 8-bit pixels (channels per pixel, top row first) to `path` in the format OpenImageIO
  // picks from the extension of `format_from`. `fast`: the quickest compression the format has.
  virtual bool write_uint8(const std::string& path, const std::string& format_from, int width,
                           int height, int channels, const uint8_t* pixels, bool fast,
                           std::string* error) = 0;
  // Makes the .tx and opens a private TextureSystem on it; null with the reason on failure.
  virtual std::unique_ptr<TexturePeer> make_peer(const PeerSetup& setup, std::string* error) = 0;
};

}  // namespace texsim::oiio

// The plugin's one exported symbol: its Plugin for ABI `abi`, or null for another ABI.
extern "C" texsim::oiio::Plugin* texsim_oiio_plugin(int abi);
