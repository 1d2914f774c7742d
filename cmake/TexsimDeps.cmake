# Every dependency comes from a Debian package (scripts/setup-debian.sh installs them).
find_package(PkgConfig REQUIRED)
find_package(glm REQUIRED)
# OpenImageIO: texture files of every format and the OIIO peer, only in the plugin
# libtexsim_oiio.so that texsim opens on first use (pipeline/image_io/oiio_plugin.h): linked,
# its ~260 libraries would cost every process ~0.2 s and ~120 MB at start.
find_package(OpenImageIO REQUIRED)
# Debian's package names /usr/include/opencv4 among its include directories without needing
# it; a target linking OpenImageIO directly is a configure error while that path is missing.
get_target_property(_oiio_dirs OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
set(_oiio_present "")
foreach(_dir IN LISTS _oiio_dirs)
  if(EXISTS "${_dir}")
    list(APPEND _oiio_present "${_dir}")
  endif()
endforeach()
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${_oiio_present}")
# libpng: the PNGs texsim writes and the 8-bit RGB PNGs it reads back (libpng-dev).
find_package(PNG REQUIRED)
# The block encoders of pipeline/image_io (texsim_texture_encode): libsquish (libsquish-dev) and
# NVIDIA Texture Tools (libnvtt-dev). libnvtt carries its own, older copy of squish's classes
# under the same exported names (squish::ColourFit::Compress, ...): with libsquish.so in the
# same process one library runs the other's code and crashes. So libsquish is linked from its
# static archive with its symbols kept out of the dynamic symbol table (--exclude-libs), and
# each library runs its own squish.
find_library(TEXSIM_SQUISH_LIBRARY NAMES libsquish.a)
find_path(TEXSIM_SQUISH_INCLUDE squish.h)
find_library(TEXSIM_NVTT_LIBRARY nvtt)
find_path(TEXSIM_NVTT_INCLUDE nvtt/nvtt.h)
if(NOT TEXSIM_SQUISH_LIBRARY OR NOT TEXSIM_SQUISH_INCLUDE)
  message(FATAL_ERROR "libsquish not found (squish.h, libsquish.a): install libsquish-dev "
    "(scripts/setup-debian.sh)")
endif()
if(NOT TEXSIM_NVTT_LIBRARY OR NOT TEXSIM_NVTT_INCLUDE)
  message(FATAL_ERROR "NVIDIA Texture Tools not found (nvtt/nvtt.h, -lnvtt): install "
    "libnvtt-dev (scripts/setup-debian.sh)")
endif()
pkg_check_modules(TEXSIM_SQUISH_PC QUIET libsquish)  # only for its version, in provenance
find_package(OpenMP REQUIRED COMPONENTS CXX)  # libsquish.a compresses images with OpenMP
# Arm's ASTC codec library (libastcenc-dev): the ASTC encoder, in process.
find_package(astcenc CONFIG QUIET)
if(NOT astcenc_FOUND)
  message(FATAL_ERROR "astcenc's library not found (astcenc.h, astcencConfig.cmake): install "
    "libastcenc-dev (scripts/setup-debian.sh)")
endif()
find_package(CLI11 REQUIRED)
find_package(tomlplusplus REQUIRED)
find_package(Threads REQUIRED)
find_package(ZLIB REQUIRED)
find_package(nlohmann_json REQUIRED)
find_package(tinyobjloader REQUIRED)
# Assimp: the 3-D model formats of [[models]] (glTF, 3DS, OBJ+MTL, MD3; libassimp-dev).
find_package(assimp REQUIRED)
pkg_check_modules(HIDAPI REQUIRED IMPORTED_TARGET hidapi-hidraw)
pkg_check_modules(MPFR REQUIRED IMPORTED_TARGET mpfr)
# Nettle: SHA-1 of the provenance's input digests, SHA-256 of the truth cache's keys.
pkg_check_modules(NETTLE REQUIRED IMPORTED_TARGET nettle)
find_package(SQLite3 REQUIRED)
# Google Highway: SIMD with run-time target dispatch (the batched sampler).
find_package(hwy REQUIRED)
# Optional: Mesa as a peer renderer (pipeline/reference/mesa_peer.h) needs EGL and OpenGL
# (libegl-dev, libgl-dev); without them texsim builds and the Mesa rows are skipped.
find_package(OpenGL COMPONENTS EGL OpenGL)
if(OpenGL_EGL_FOUND AND OpenGL_OpenGL_FOUND)
  set(TEXSIM_HAVE_MESA ON)
  message(STATUS "Mesa peer: EGL and OpenGL found (study filters and bench-peers can use Mesa)")
else()
  set(TEXSIM_HAVE_MESA OFF)
  message(STATUS "Mesa peer: EGL or OpenGL not found (libegl-dev, libgl-dev): building without "
    "it; study filters skips the Mesa rows")
endif()

add_library(texsim_deps INTERFACE)
add_library(texsim::deps ALIAS texsim_deps)
# SYSTEM include paths keep third-party headers out of -Werror.
target_link_libraries(texsim_deps INTERFACE glm::glm CLI11::CLI11
  tomlplusplus::tomlplusplus PkgConfig::HIDAPI PkgConfig::MPFR ZLIB::ZLIB nlohmann_json::nlohmann_json Threads::Threads
  tinyobjloader::tinyobjloader_double SQLite::SQLite3 assimp::assimp)
