#pragma once
// A draw trace turned into a fragment trace (traces/FORMAT.md): the texture look-ups the draw
// renderer sends to the texture unit, in its order, with their exact coordinates and
// derivatives. The fragment trace's texture table names each texture as
// "draws:PATH#ID" (texture ID of the draw trace PATH, with its own levels), which a run of the
// fragment trace loads from the draw trace (DrawTextureCache). The sampler state of the draws
// is not carried (the fragment format has none): a run of the trace alone uses its default
// material. docs/cli.md, `trace gen`.
#include <cstdint>
#include <map>
#include <memory>
#include <string>

#include "blocks/texture/memory/texture_memory.h"
#include "traces/draw_trace.h"

namespace texsim {

// Frames first..last (capture numbers) of the draw trace `draws` rendered functionally; every
// look-up written to `out` (.csv text, otherwise binary). Returns the fragments written.
uint64_t generate_draws_trace(const std::string& draws, uint32_t first, uint32_t last,
                              const std::string& out);

// Loads "draws:PATH#ID" textures; each draw trace is read once. PATH relative to `dir`.
class DrawTextureCache {
 public:
  Texture load(const std::string& source, const std::string& dir);
  // The draw trace file a source names (resolved against dir), for the run's provenance.
  static std::string path_of(const std::string& source, const std::string& dir);

 private:
  std::map<std::string, std::unique_ptr<DrawTrace>> traces_;
};

}  // namespace texsim
