#pragma once
// A real library beside the simulated filters: OpenImageIO's TextureSystem answering the same
// queries (u, v and the four derivatives) in its anisotropic mode, on a tiled, MIP-mapped .tx
// made from the same level-0 texels (docs/derivations/anisotropic-filters.md §6). Not a hardware
// block.
#include <memory>
#include <string>

#include "blocks/base/fragment.h"
#include "blocks/texture/memory/texture_memory.h"

namespace texsim {

class OiioPeer {
 public:
  struct Config {
    int max_aniso = 16;                       // TextureOpt::anisotropic
    bool aniso = true;                        // MipModeAniso (else trilinear)
    AddressMode address = AddressMode::Wrap;  // both axes
    std::string tx_dir;                       // where the .tx goes (empty: system temp dir)
  };
  // Writes the texture's level 0 to a temporary .tx (OIIO builds its own MIP chain, box filter)
  // and opens a private TextureSystem on it, through the OpenImageIO plugin (loaded on first
  // use, pipeline/image_io/oiio_plugin.h). Throws InputError if the plugin or OIIO fails.
  OiioPeer(const Texture& tex, const Config& cfg);
  ~OiioPeer();
  OiioPeer(const OiioPeer&) = delete;
  OiioPeer& operator=(const OiioPeer&) = delete;

  // One filtered lookup (RGBA). Non-finite inputs give (0, 0, 0, 0), as OIIO's own failure.
  Rgba lookup(const Fragment& f) const;
  const std::string& tx_path() const { return path_; }
  std::string version() const;  // OpenImageIO's, from the plugin

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
};

}  // namespace texsim
