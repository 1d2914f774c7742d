# What `cmake --install` puts where, the CMake package and `cpack -G DEB` (docs/install.md).
# texsim itself, its OpenImageIO plugin and the bash completion are installed by
# pipeline/CMakeLists.txt, the Python module by python/CMakeLists.txt.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)
set(TEXSIM_INSTALL_DATA_DIR ${CMAKE_INSTALL_DATADIR}/texsim)
set(TEXSIM_INSTALL_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/texsim)

# The man page, made from --help and --version by help2man.
find_program(TEXSIM_HELP2MAN help2man)
if(TEXSIM_HELP2MAN)
  add_custom_command(OUTPUT ${CMAKE_BINARY_DIR}/texsim.1
    COMMAND ${TEXSIM_HELP2MAN} --no-info --section=1
      "--name=cycle-approximate simulator of a hardware texture unit"
      --output=${CMAKE_BINARY_DIR}/texsim.1 $<TARGET_FILE:texsim>
    DEPENDS texsim VERBATIM)
  add_custom_target(texsim_man ALL DEPENDS ${CMAKE_BINARY_DIR}/texsim.1)
  install(FILES ${CMAKE_BINARY_DIR}/texsim.1 DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
else()
  message(STATUS "Man page: skipped (help2man not found)")
endif()

# The shipped scenes and sample traces (share/texsim; the studies find them beside the
# installed binary, pipeline/studies/shipped_scenes.h) and the documentation.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes/ DESTINATION ${TEXSIM_INSTALL_DATA_DIR}/scenes)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/traces/samples/
  DESTINATION ${TEXSIM_INSTALL_DATA_DIR}/traces/samples)
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/traces/FORMAT.md
  ${PROJECT_SOURCE_DIR}/traces/DRAWS.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})

# The block libraries with their headers and the interface target of their dependencies.
set_target_properties(texsim_base PROPERTIES EXPORT_NAME base)
set_target_properties(texsim_blocks PROPERTIES EXPORT_NAME blocks)
set_target_properties(texsim_traces PROPERTIES EXPORT_NAME traces)
set_target_properties(texsim_deps PROPERTIES EXPORT_NAME deps)
install(TARGETS texsim_base texsim_blocks texsim_traces texsim_deps EXPORT texsimTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}/texsim
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/texsim)
foreach(dir blocks rtl_model/number traces)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/texsim/${dir}
    FILES_MATCHING PATTERN "*.h" PATTERN "samples" EXCLUDE)
endforeach()
install(EXPORT texsimTargets NAMESPACE texsim:: DESTINATION ${TEXSIM_INSTALL_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/texsimConfig.cmake.in
  ${CMAKE_BINARY_DIR}/texsimConfig.cmake INSTALL_DESTINATION ${TEXSIM_INSTALL_CMAKE_DIR}
  PATH_VARS CMAKE_INSTALL_INCLUDEDIR TEXSIM_INSTALL_DATA_DIR)
write_basic_package_version_file(${CMAKE_BINARY_DIR}/texsimConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/texsimConfig.cmake ${CMAKE_BINARY_DIR}/texsimConfigVersion.cmake
  DESTINATION ${TEXSIM_INSTALL_CMAKE_DIR})

# The install from this build tree, no rebuild (scripts/test-install.sh): into a temporary
# prefix (an outside project on texsim::blocks, the module, the installed binary) and as a
# .deb. Labelled `install` so CI can run them last (ctest -L install) or leave them out.
if(TEXSIM_BUILD_TESTS)
  if(TEXSIM_HAVE_PYTHON_MODULE)
    set(_with_python python)
  else()
    set(_with_python no-python)
  endif()
  add_test(NAME Install.Prefix COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/test-install.sh prefix
    ${CMAKE_BINARY_DIR} ${_with_python})
  add_test(NAME Install.Deb COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/test-install.sh deb
    ${CMAKE_BINARY_DIR} ${_with_python})
  set_tests_properties(Install.Prefix Install.Deb PROPERTIES LABELS install TIMEOUT 300
    RUN_SERIAL TRUE)
endif()

# cpack -G DEB: one package, installed under /usr; the libraries' run-time dependencies from
# dpkg-shlibdeps, the module's numpy and the headers' -dev packages named explicitly.
set(CPACK_PACKAGE_NAME texsim)
set(CPACK_PACKAGE_VENDOR texsim)
set(CPACK_PACKAGE_CONTACT "texsim maintainers <texsim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
  "cycle-approximate simulator of a hardware texture unit, with its Python module")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_GENERATOR DEB)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "python3 (>= 3.11), python3 (<< 3.12), python3-numpy")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "bash-completion, python3-matplotlib")
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "libglm-dev, libcli11-dev, libtomlplusplus-dev, zlib1g-dev, \
nlohmann-json3-dev, libtinyobjloader-dev, libsqlite3-dev, libassimp-dev, libhwy-dev, \
libhidapi-dev, libmpfr-dev, nettle-dev, libisal-dev, pkg-config")
include(CPack)
