#include "python/oiio_plugin_path.h"

#include <dlfcn.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

#include "pipeline/image_io/oiio_plugin_api.h"

namespace texsim_py {

void point_at_oiio_plugin() {
  const char* set = std::getenv("TEXSIM_OIIO_PLUGIN");
  if (set && *set) return;
  static const int anchor = 0;  // an address inside the module
  Dl_info info{};
  if (!dladdr(&anchor, &info) || !info.dli_fname) return;
  const std::filesystem::path dir = std::filesystem::path(info.dli_fname).parent_path();
  for (const std::filesystem::path& p : {dir / ".." / texsim::oiio::kLibraryName,
                                         dir / TEXSIM_PY_TO_LIBDIR / texsim::oiio::kLibraryName}) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(p, ec)) {
      setenv("TEXSIM_OIIO_PLUGIN", p.lexically_normal().c_str(), 0);
      return;
    }
  }
}

}  // namespace texsim_py
