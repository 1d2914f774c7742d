# RTL blocks under Verilator (docs/rtl/blocks.md): the parameter generator, one static library
# per Verilated block, the harness, the lockstep tests and the C++-vs-RTL benchmark. Verilator
# is used when found; without it these targets are skipped with a message and nothing fails.

set(TEXSIM_RTL_DIR ${PROJECT_SOURCE_DIR}/rtl_model/rtl)
set(TEXSIM_RTL_GEN ${PROJECT_BINARY_DIR}/rtl_model/params)
set(TEXSIM_RTL_TESTS ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_vd.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_lerp.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_uv.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_rect_scan.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_rect_control.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_rect_raster.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_sampler.cc
  ${PROJECT_SOURCE_DIR}/testbench/rtl/test_rtl_iverilog_trace.cc)
set(TEXSIM_RTL_BENCH ${PROJECT_SOURCE_DIR}/testbench/rtl/bench_rtl_vs_cpp.cc)
set(TEXSIM_RTL_CC ${PROJECT_SOURCE_DIR}/rtl_model/params/gen_rtl_params.cc
  ${PROJECT_SOURCE_DIR}/rtl_model/verilator/rtl_harness.cc)
# The virtual board's RTL blocks (rtl_model/verilator/vd_rtl_block.h): the Verilated V(d)
# blocks, or without Verilator a stand-in that says so. `texsim` links one of the two.
set(TEXSIM_RTL_BOARD_CC ${PROJECT_SOURCE_DIR}/rtl_model/verilator/vd_rtl_block.cc)
set(TEXSIM_RTL_BOARD_ABSENT_CC ${PROJECT_SOURCE_DIR}/rtl_model/verilator/vd_rtl_block_absent.cc)
set(TEXSIM_RTL_BOARD_TEST ${PROJECT_SOURCE_DIR}/testbench/cosim/test_rtl_board.cc)
# The Verilated sampler behind the virtual board (rtl_model/verilator/sampler_rtl_block.h).
set(TEXSIM_RTL_SAMPLER_BOARD_CC ${PROJECT_SOURCE_DIR}/rtl_model/verilator/sampler_rtl_block.cc
  ${PROJECT_SOURCE_DIR}/rtl_model/verilator/lerp_rtl_block.cc)
set(TEXSIM_RTL_SAMPLER_BOARD_TEST ${PROJECT_SOURCE_DIR}/testbench/cosim/test_rtl_sampler_board.cc)
texsim_listed(${TEXSIM_RTL_TESTS} ${TEXSIM_RTL_BENCH} ${TEXSIM_RTL_CC} ${TEXSIM_RTL_BOARD_CC}
  ${TEXSIM_RTL_BOARD_ABSENT_CC} ${TEXSIM_RTL_BOARD_TEST} ${TEXSIM_RTL_SAMPLER_BOARD_CC}
  ${TEXSIM_RTL_SAMPLER_BOARD_TEST})

find_package(verilator 5 QUIET HINTS $ENV{VERILATOR_ROOT} /usr/share/verilator)
if(NOT verilator_FOUND OR NOT VERILATOR_BIN)
  message(STATUS "Verilator not found: RTL blocks, lockstep tests and RTL benchmark skipped; "
    "the virtual board runs the C++ models only")
  add_library(texsim_rtl_board STATIC ${TEXSIM_RTL_BOARD_ABSENT_CC})
  target_link_libraries(texsim_rtl_board PUBLIC texsim_link)
  texsim_set_warnings(texsim_rtl_board)
  target_link_libraries(texsim_app PUBLIC texsim_rtl_board)
  return()
endif()
message(STATUS "Verilator ${verilator_VERSION}: RTL lockstep tests enabled")

# Parameters: rtl_params.h (C++) -> texsim_params.vh and one -G file per block.
set(TEXSIM_RTL_BLOCKS vd_p2 vd_p1 bilinear_lerp uv_incremental rect_scan_stepper
  rect_scan_control rect_scan_raster texsim_sampler)
add_executable(gen_rtl_params ${PROJECT_SOURCE_DIR}/rtl_model/params/gen_rtl_params.cc)
target_link_libraries(gen_rtl_params PRIVATE texsim_blocks)
texsim_set_warnings(gen_rtl_params)
set(gen_outputs ${TEXSIM_RTL_GEN}/texsim_params.vh ${TEXSIM_RTL_GEN}/texsim_sampler_log2.v)
foreach(b ${TEXSIM_RTL_BLOCKS})
  list(APPEND gen_outputs ${TEXSIM_RTL_GEN}/${b}.vc)
endforeach()
# The generator rewrites only the files whose text changed, so a stamp is the rule's output
# and the files are byproducts: a block is re-verilated only when its own parameters change.
add_custom_command(OUTPUT ${TEXSIM_RTL_GEN}/params.stamp
  BYPRODUCTS ${gen_outputs}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${TEXSIM_RTL_GEN}
  COMMAND gen_rtl_params ${TEXSIM_RTL_GEN}
  COMMAND ${CMAKE_COMMAND} -E touch ${TEXSIM_RTL_GEN}/params.stamp
  DEPENDS gen_rtl_params
  COMMENT "Generating RTL parameters from rtl_model/params/rtl_params.h" VERBATIM)
# One target owns the generated files, so parallel builds run the generator once.
add_custom_target(texsim_rtl_params DEPENDS ${TEXSIM_RTL_GEN}/params.stamp)

# The Verilator runtime, compiled once for every block.
add_library(texsim_verilated STATIC
  ${VERILATOR_ROOT}/include/verilated.cpp
  ${VERILATOR_ROOT}/include/verilated_threads.cpp
  ${VERILATOR_ROOT}/include/verilated_vcd_c.cpp)
target_include_directories(texsim_verilated SYSTEM PUBLIC
  ${VERILATOR_ROOT}/include ${VERILATOR_ROOT}/include/vltstd)
target_compile_definitions(texsim_verilated PUBLIC VM_TRACE=1 VM_TRACE_VCD=1 VM_COVERAGE=0 VM_SC=0)
target_compile_options(texsim_verilated PRIVATE -w)
target_link_libraries(texsim_verilated PUBLIC Threads::Threads)

# texsim_verilate(TOP SOURCES f.v ... [GENERATED paths] [NAME name] [ARGS verilator-args]):
# verilates module TOP (sources in rtl_model/rtl, and generated ones by their path) with its
# generated -G file into the static library texsim_rtl_NAME
# (header <VNAME.h>; NAME defaults to TOP, another NAME builds the same design with other
# Verilator arguments). Verilator's C++ output has names that depend on the design, so one
# includer file (VNAME__all.cpp) collects it for the compiler.
function(texsim_verilate top)
  cmake_parse_arguments(A "" "NAME" "SOURCES;GENERATED;ARGS" ${ARGN})
  if(NOT A_NAME)
    set(A_NAME ${top})
  endif()
  list(TRANSFORM A_SOURCES PREPEND ${TEXSIM_RTL_DIR}/)
  list(APPEND A_SOURCES ${A_GENERATED})
  set(mdir ${PROJECT_BINARY_DIR}/rtl_model/verilated/${A_NAME})
  add_custom_command(OUTPUT ${mdir}/V${A_NAME}__all.cpp
    COMMAND ${CMAKE_COMMAND} -E rm -rf ${mdir}
    COMMAND ${CMAKE_COMMAND} -E make_directory ${mdir}
    COMMAND ${VERILATOR_BIN} --cc --trace -O3 --x-assign fast --x-initial fast -Wno-fatal
      -Wno-DECLFILENAME ${A_ARGS} --top-module ${top} --prefix V${A_NAME} --Mdir ${mdir}
      -f ${TEXSIM_RTL_GEN}/${top}.vc -I${TEXSIM_RTL_GEN} ${A_SOURCES}
    COMMAND ${CMAKE_COMMAND} -DDIR=${mdir} -DPREFIX=V${A_NAME}
      -P ${PROJECT_SOURCE_DIR}/cmake/TexsimVerilatorIncluder.cmake
    DEPENDS ${A_SOURCES} ${TEXSIM_RTL_GEN}/${top}.vc
    COMMENT "Verilating ${A_NAME}" VERBATIM)
  add_library(texsim_rtl_${A_NAME} STATIC ${mdir}/V${A_NAME}__all.cpp)
  target_include_directories(texsim_rtl_${A_NAME} SYSTEM PUBLIC ${mdir})
  target_link_libraries(texsim_rtl_${A_NAME} PUBLIC texsim_verilated)
  target_compile_options(texsim_rtl_${A_NAME} PRIVATE -w)
  add_dependencies(texsim_rtl_${A_NAME} texsim_rtl_params)
endfunction()

set(rtl_common texsim_pipe.v texsim_round_sat.v texsim_op_counters.v texsim_mul_rs.v
  texsim_add_sat.v texsim_mul_tree.v)
texsim_verilate(vd_p2 SOURCES vd_p2.v ${rtl_common})
texsim_verilate(vd_p1 SOURCES vd_p1.v ${rtl_common})
texsim_verilate(bilinear_lerp SOURCES bilinear_lerp.v ${rtl_common})
texsim_verilate(rect_scan_stepper SOURCES rect_scan_stepper.v ${rtl_common})
texsim_verilate(rect_scan_control SOURCES rect_scan_control.v ${rtl_common})
texsim_verilate(rect_scan_raster SOURCES rect_scan_raster.v rect_scan_stepper.v
  rect_scan_control.v ${rtl_common})
set(sampler_sources texsim_sampler.v texsim_sampler_lod.v texsim_sampler_addr.v bilinear_lerp.v
  ${rtl_common})
texsim_verilate(texsim_sampler SOURCES ${sampler_sources}
  GENERATED ${TEXSIM_RTL_GEN}/texsim_sampler_log2.v)
texsim_verilate(uv_incremental SOURCES uv_incremental.v texsim_fixed_div.v texsim_udiv_pipe.v
  ${rtl_common})

add_library(texsim_rtl_harness STATIC ${PROJECT_SOURCE_DIR}/rtl_model/verilator/rtl_harness.cc)
target_include_directories(texsim_rtl_harness PUBLIC ${PROJECT_SOURCE_DIR})
target_link_libraries(texsim_rtl_harness PUBLIC texsim_blocks texsim_verilated)
texsim_set_warnings(texsim_rtl_harness)
set(TEXSIM_RTL_LIBS texsim_rtl_harness)
foreach(b ${TEXSIM_RTL_BLOCKS})
  list(APPEND TEXSIM_RTL_LIBS texsim_rtl_${b})
endforeach()

# The Verilated V(d) blocks behind the virtual board of `texsim cosim --board rtl`.
add_library(texsim_rtl_board STATIC ${TEXSIM_RTL_BOARD_CC} ${TEXSIM_RTL_SAMPLER_BOARD_CC})
target_link_libraries(texsim_rtl_board PUBLIC texsim_link texsim_rtl_harness texsim_rtl_vd_p2
  texsim_rtl_vd_p1 texsim_rtl_texsim_sampler texsim_rtl_bilinear_lerp)
texsim_set_warnings(texsim_rtl_board)
target_link_libraries(texsim_app PUBLIC texsim_rtl_board)

if(TEXSIM_BUILD_TESTS)
  find_package(GTest REQUIRED)
  include(GoogleTest)
  foreach(src ${TEXSIM_RTL_TESTS})
    get_filename_component(name ${src} NAME_WE)
    add_executable(${name} ${src})
    target_link_libraries(${name} PRIVATE ${TEXSIM_RTL_LIBS} GTest::gtest GTest::gtest_main)
    texsim_set_warnings(${name})
    gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
  endforeach()
  # The whole rasteriser's lockstep also draws a shipped scene's faces.
  target_link_libraries(test_rtl_rect_raster PRIVATE texsim_pipeline)
  target_compile_definitions(test_rtl_rect_raster PRIVATE
    TEXSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  # The sampler's lockstep runs the shipped scenes' fragments through the texture unit too.
  target_link_libraries(test_rtl_sampler PRIVATE texsim_pipeline)
  target_compile_definitions(test_rtl_sampler PRIVATE TEXSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  # Icarus Verilog replays the Verilated blocks' cycle traces (testbench/rtl/iverilog/).
  target_compile_definitions(test_rtl_iverilog_trace PRIVATE
    TEXSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}" TEXSIM_RTL_PARAMS_DIR="${TEXSIM_RTL_GEN}")
  add_executable(test_rtl_board ${TEXSIM_RTL_BOARD_TEST})
  target_link_libraries(test_rtl_board PRIVATE texsim_rtl_board GTest::gtest GTest::gtest_main)
  texsim_set_warnings(test_rtl_board)
  gtest_discover_tests(test_rtl_board DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
  # A scene's fixed-arithmetic materials through the link to the virtual board's RTL sampler.
  add_executable(test_rtl_sampler_board ${TEXSIM_RTL_SAMPLER_BOARD_TEST})
  target_link_libraries(test_rtl_sampler_board PRIVATE texsim_rtl_board texsim_app
    GTest::gtest GTest::gtest_main)
  target_compile_definitions(test_rtl_sampler_board PRIVATE
    TEXSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  texsim_set_warnings(test_rtl_sampler_board)
  gtest_discover_tests(test_rtl_sampler_board DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 600)
endif()
if(TEXSIM_BUILD_TESTS AND TEXSIM_BUILD_BENCH AND EXISTS ${TEXSIM_RTL_BENCH})
  find_package(benchmark REQUIRED)
  # The sampler also verilated with --threads 2, for the benchmark only.
  texsim_verilate(texsim_sampler NAME texsim_sampler_mt SOURCES ${sampler_sources}
    GENERATED ${TEXSIM_RTL_GEN}/texsim_sampler_log2.v ARGS --threads 2)
  add_executable(bench_rtl_vs_cpp ${TEXSIM_RTL_BENCH})
  target_link_libraries(bench_rtl_vs_cpp PRIVATE ${TEXSIM_RTL_LIBS} texsim_rtl_texsim_sampler_mt
    texsim_pipeline benchmark::benchmark)
  target_compile_definitions(bench_rtl_vs_cpp PRIVATE TEXSIM_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  texsim_set_warnings(bench_rtl_vs_cpp)
endif()
