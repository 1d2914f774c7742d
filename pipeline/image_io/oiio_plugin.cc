#include "pipeline/image_io/oiio_plugin.h"

#include <dlfcn.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "blocks/base/input_error.h"

namespace texsim {

namespace {
std::mutex g_mutex;
std::atomic<oiio::Plugin*> g_plugin{nullptr};

// Opens one candidate; null with the reason in `why`.
oiio::Plugin* try_open(const std::string& path, std::string* why) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) {
    *why = "no such file";
    return nullptr;
  }
  // RTLD_LOCAL: OpenImageIO's ~260 libraries stay out of texsim's own symbol look-ups.
  void* lib = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) {
    const char* e = ::dlerror();
    *why = e ? e : "dlopen failed";
    return nullptr;
  }
  using Entry = oiio::Plugin* (*)(int);
  auto entry = reinterpret_cast<Entry>(::dlsym(lib, oiio::kEntryPoint));
  if (!entry) {
    *why = std::string("no symbol ") + oiio::kEntryPoint;
    ::dlclose(lib);
    return nullptr;
  }
  oiio::Plugin* plugin = entry(oiio::kAbi);
  if (!plugin) {
    *why = "built for another version of texsim (plugin ABI differs from " +
           std::to_string(oiio::kAbi) + ")";
    ::dlclose(lib);
    return nullptr;
  }
  return plugin;  // never closed: its objects live until exit
}
}  // namespace

std::vector<std::string> oiio_plugin_candidates() {
  std::vector<std::string> out;
  // Set, it is the only place looked at: a wrong value is an error, not a silent fallback.
  if (const char* env = std::getenv("TEXSIM_OIIO_PLUGIN"); env && *env) return {env};
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    out.push_back((exe.parent_path() / oiio::kLibraryName).string());
    out.push_back((exe.parent_path() / TEXSIM_BIN_TO_LIBDIR / oiio::kLibraryName)
                      .lexically_normal()
                      .string());
  }
  const std::string installed =
      (std::filesystem::path(TEXSIM_INSTALL_LIBDIR) / oiio::kLibraryName).string();
  if (std::find(out.begin(), out.end(), installed) == out.end()) out.push_back(installed);
  return out;
}

oiio::Plugin& oiio_plugin(const std::string& needed_for) {
  if (oiio::Plugin* p = g_plugin.load(std::memory_order_acquire)) return *p;
  const std::lock_guard<std::mutex> lock(g_mutex);
  if (oiio::Plugin* p = g_plugin.load(std::memory_order_acquire)) return *p;
  std::string tried;
  for (const std::string& path : oiio_plugin_candidates()) {
    std::string why;
    if (oiio::Plugin* p = try_open(path, &why)) {
      g_plugin.store(p, std::memory_order_release);
      return *p;
    }
    if (!tried.empty()) tried += "; ";
    tried += path;
    tried += " (";
    tried += why;
    tried += ")";
  }
  throw InputError(needed_for,
                   std::string("needs OpenImageIO, which texsim loads from its plugin ") +
                       oiio::kLibraryName + ", and that cannot be loaded: tried " + tried +
                       ". Build the target texsim_oiio (it is built beside "
                       "texsim) or set TEXSIM_OIIO_PLUGIN to the library");
}

bool oiio_plugin_loaded() { return g_plugin.load(std::memory_order_acquire) != nullptr; }

}  // namespace texsim
