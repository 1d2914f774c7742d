#pragma once
// texsim's version (the CMake project version), for --version and the reports' provenance.

namespace texsim {

inline constexpr const char* kTexsimVersion = TEXSIM_VERSION;

}  // namespace texsim
