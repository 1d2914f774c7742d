#pragma once
// Where the shipped scenes are (the studies' defaults): the installed share/texsim/scenes next
// to an installed texsim, else the source tree's scenes/ of the build.
#include <string>

namespace texsim {

const std::string& shipped_scenes_dir();

}  // namespace texsim
