#include "pipeline/render/draw_fragment_trace.h"

#include <filesystem>
#include <string_view>

#include "blocks/base/input_error.h"
#include "pipeline/render/draw_renderer.h"
#include "traces/trace_tools.h"

namespace texsim {

namespace {

// PATH resolved against dir (relative to the fragment trace), and ID.
std::string resolve(const std::string& source, const std::string& dir, uint32_t& id) {
  std::string path;
  split_draws_source(source, path, id);
  const std::filesystem::path p(path);
  return p.is_absolute() || dir.empty() ? path : (std::filesystem::path(dir) / p).string();
}

}  // namespace

std::string DrawTextureCache::path_of(const std::string& source, const std::string& dir) {
  uint32_t id = 0;
  return resolve(source, dir, id);
}

Texture DrawTextureCache::load(const std::string& source, const std::string& dir) {
  uint32_t id = 0;
  const std::string path = resolve(source, dir, id);
  auto& trace = traces_[path];
  if (!trace) trace = std::make_unique<DrawTrace>(read_draw_trace(path));
  for (const DrawTexture& t : trace->textures)
    if (t.id == id) return texture_of_draw(t);
  throw InputError(path, "has no texture " + std::to_string(id) + " (named by \"" + source + "\")");
}

uint64_t generate_draws_trace(const std::string& draws, uint32_t first, uint32_t last,
                              const std::string& out) {
  const DrawTrace trace = read_draw_trace(draws);
  std::vector<size_t> frames;
  for (size_t i = 0; i < trace.frames.size(); ++i)
    if (trace.frames[i].number >= first && trace.frames[i].number <= last) frames.push_back(i);
  if (frames.empty()) {
    throw InputError(draws,
                     "no frame numbered " + std::to_string(first) + ".." + std::to_string(last));
  }
  static const toml::table kNoPipeline;
  const PipelineSetup setup = PipelineSetup::from_toml(kNoPipeline, draws);
  DrawRenderer renderer(trace, frames, setup, TechTable::defaults(), false, draws);
  // Texture i of the renderer is trace.textures[i] (its fragments' tex); absolute paths so the
  // fragment trace can be moved away from the draw trace.
  TraceHeader h;
  const std::string abs = std::filesystem::absolute(draws).string();
  for (size_t i = 0; i < trace.textures.size(); ++i) {
    const DrawTexture& t = trace.textures[i];
    h.textures.push_back({static_cast<uint32_t>(i), t.name.empty() ? "texture" : t.name,
                          draws_source(abs, t.id), t.width, t.height});
  }
  return write_trace(out, h, [&](auto& w) {
    renderer.set_lookup_observer([&](const Fragment& f) { w.write(f); });
    for (size_t i : frames) renderer.render(i);
  });
}

}  // namespace texsim
