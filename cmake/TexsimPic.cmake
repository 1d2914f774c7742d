# texsim_static_libraries_pic(DIR): every static library defined under DIR compiled as
# position-independent code, so that a shared object (the Python module) can link them.
# -fno-semantic-interposition keeps calls inside a library as direct as in -fPIE code; the
# executables stay -fPIE (GCC's default on Debian).
function(texsim_static_libraries_pic dir)
  get_property(targets DIRECTORY ${dir} PROPERTY BUILDSYSTEM_TARGETS)
  foreach(t ${targets})
    get_target_property(type ${t} TYPE)
    if(type STREQUAL "STATIC_LIBRARY")
      set_target_properties(${t} PROPERTIES POSITION_INDEPENDENT_CODE ON)
      target_compile_options(${t} PRIVATE -fno-semantic-interposition)
    endif()
  endforeach()
  get_property(subdirs DIRECTORY ${dir} PROPERTY SUBDIRECTORIES)
  foreach(d ${subdirs})
    texsim_static_libraries_pic(${d})
  endforeach()
endfunction()
