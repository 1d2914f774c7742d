# Explicit source lists, one library per layer (docs/architecture.md). Every .cc under the
# project's source folders must be listed in some target: a file that no list names is a
# configure error, never a silently skipped source.

# texsim_add_library(NAME SOURCES a.cc b.cc ... DEPS lib ...): sources relative to the calling
# CMakeLists.txt.
function(texsim_add_library name)
  cmake_parse_arguments(A "" "" "SOURCES;DEPS" ${ARGN})
  list(TRANSFORM A_SOURCES PREPEND ${CMAKE_CURRENT_SOURCE_DIR}/)
  add_library(${name} STATIC ${A_SOURCES})
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>)
  target_link_libraries(${name} PUBLIC ${A_DEPS} texsim::deps)
  texsim_set_warnings(${name})
  texsim_listed(${A_SOURCES})
endfunction()

# Marks absolute source paths as belonging to a target.
function(texsim_listed)
  set_property(GLOBAL APPEND PROPERTY TEXSIM_LISTED_SOURCES ${ARGN})
endfunction()

# Fails the configure step if a .cc under the source folders belongs to no target.
function(texsim_check_sources)
  file(GLOB_RECURSE all CONFIGURE_DEPENDS
    ${PROJECT_SOURCE_DIR}/blocks/*.cc ${PROJECT_SOURCE_DIR}/pipeline/*.cc
    ${PROJECT_SOURCE_DIR}/traces/*.cc ${PROJECT_SOURCE_DIR}/rtl_model/*.cc
    ${PROJECT_SOURCE_DIR}/testbench/*.cc)
  get_property(listed GLOBAL PROPERTY TEXSIM_LISTED_SOURCES)
  set(missing "")
  foreach(f ${all})
    if(NOT f IN_LIST listed)
      list(APPEND missing ${f})
    endif()
  endforeach()
  if(missing)
    list(JOIN missing "\n  " text)
    message(FATAL_ERROR "Sources that no target lists (add each to its folder's CMakeLists.txt):\n  ${text}")
  endif()
endfunction()
