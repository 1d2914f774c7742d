#pragma once
// Finds and opens libtexsim_oiio.so (oiio_plugin_api.h) the first time OpenImageIO is needed,
// so that a run that reads no texture file and writes only PNGs never loads OpenImageIO.
// Searched, first found wins: the directory of the running executable, the install library
// directory relative to it (bin/../lib), then the configured install library directory;
// $TEXSIM_OIIO_PLUGIN, when set, names the library file and is the only place looked at.
#include <string>
#include <vector>

#include "pipeline/image_io/oiio_plugin_api.h"

namespace texsim {

// The plugin, opened on first use (thread-safe). `needed_for` (e.g. the file to read) goes into
// the InputError thrown when it cannot be loaded, which names the library, every place
// searched and why each failed.
oiio::Plugin& oiio_plugin(const std::string& needed_for);

// True once this process has loaded the plugin (and so OpenImageIO).
bool oiio_plugin_loaded();

// The paths searched, in order.
std::vector<std::string> oiio_plugin_candidates();

}  // namespace texsim
