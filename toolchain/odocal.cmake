# Project-wide settings shared by every folder: warnings, the Eigen target, and helpers.

# Warnings are errors on every preset.
add_compile_options(-Wall -Wextra -Werror)

# The firmware's flash (docs/stm32f4.md), at compile and at link time (the link-time optimiser
# generates the code):
# - firmware/stm32f4/built_once.hpp zero-fills a large object's bytes before constructing it;
#   with the storage not clobbered at the start of a constructor (-flifetime-dse=1, only an
#   optimisation given up) and dead-store elimination tracking objects of up to 4 KiB (the
#   console is 3.5 KiB), GCC drops the constructors' stores of zeros into them (-228 B);
# - no second instruction scheduling pass: it reorders code for a pipeline the Cortex-M4 hardly
#   has and keeps 16-bit encodings from being chosen (-80 B; the instruction counts are the same).
if(ODOCAL_TARGET STREQUAL "stm32f4")
  set(ODOCAL_FW_SIZE_OPTIONS -flifetime-dse=1 --param=dse-max-object-size=4096
                             -fno-schedule-insns2)
  add_compile_options(${ODOCAL_FW_SIZE_OPTIONS})
  add_link_options(${ODOCAL_FW_SIZE_OPTIONS})
endif()

# Eigen is header-only. On the cross build the find-root rules hide the host's /usr/include, so
# point at Eigen's headers directly (they are target-independent).
if(CMAKE_CROSSCOMPILING)
  find_path(ODOCAL_EIGEN_DIR Eigen/Core PATHS /usr/include/eigen3 NO_CMAKE_FIND_ROOT_PATH REQUIRED)
  add_library(odocal_eigen INTERFACE)
  target_include_directories(odocal_eigen SYSTEM INTERFACE ${ODOCAL_EIGEN_DIR})
else()
  find_package(Eigen3 3.4 REQUIRED NO_MODULE)
  add_library(odocal_eigen INTERFACE)
  target_link_libraries(odocal_eigen INTERFACE Eigen3::Eigen)
endif()
# Fixed-size Eigen only: no allocation, no iostream, no SIMD alignment surprises on the MCU.
target_compile_definitions(odocal_eigen INTERFACE EIGEN_NO_IO EIGEN_DONT_VECTORIZE
                                                  EIGEN_MAX_STATIC_ALIGN_BYTES=0)

# odocal_core_area(NAME [DEPS ...]): a library from core/src/NAME/*.cpp. One library per area so a
# half-written area never breaks the build of another.
# The core's own rules, applied to its sources only (consumers keep their own flags).
set(ODOCAL_CORE_RULES -Wdouble-promotion -Wfloat-conversion -Wshadow -fno-exceptions -fno-rtti)
function(odocal_core_area name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/${name}/*.cpp)
  if(srcs)
    add_library(odocal_${name} STATIC ${srcs})
    target_link_libraries(odocal_${name} PUBLIC odocal_core_headers ${ARG_DEPS})
    target_compile_options(odocal_${name} PRIVATE ${ODOCAL_CORE_RULES})
  else()
    add_library(odocal_${name} INTERFACE)
    target_link_libraries(odocal_${name} INTERFACE odocal_core_headers ${ARG_DEPS})
  endif()
endfunction()

# The simulator's hot path (the firmware's drive core, the plant, the procedure loop) compiled
# for speed, on the host only (the robot images are built by other presets with their own
# flags): -O3 and link-time optimization across the tick, the plant and the loop that calls them
# (docs/simulation.md "Speed"). None of it changes a result bit: no fast-math, FP contraction
# explicitly off (no fused multiply-add), and -fno-math-errno only drops errno writes. The
# libraries keep ordinary object code too (fat LTO objects), so the tests that link them link
# as before. odocal_simulator_speed(TARGET) marks a target of the hot path; each folder marks its
# own (core: odocal_drive; hal: odocal_hal_sim; host_sim: the procedures and the programs;
# tests: odocal-bench). On other presets it does nothing: the robot images have their own flags.
#
# Optional profile-guided optimisation (host_sim/tools/pgo-build.sh runs both stages in
# build/host): ODOCAL_SIM_PGO=generate instruments these targets, a training run writes the
# profile to ODOCAL_SIM_PGO_DIR, and ODOCAL_SIM_PGO=use compiles them with it (about 20 % less
# time per simulated second; the results stay bit-identical, PGO only moves and inlines code).
if(ODOCAL_TARGET STREQUAL "host")
  set(ODOCAL_SIM_PGO "" CACHE STRING "simulator profile-guided optimisation: empty, generate or use")
  set_property(CACHE ODOCAL_SIM_PGO PROPERTY STRINGS "" generate use)
  set(ODOCAL_SIM_PGO_DIR ${CMAKE_BINARY_DIR}/sim-pgo CACHE PATH "simulator PGO profile directory")
  include(CheckIPOSupported)
  check_ipo_supported(RESULT odocal_host_ipo OUTPUT odocal_host_ipo_output LANGUAGES CXX)
  set_property(GLOBAL PROPERTY ODOCAL_HOST_IPO ${odocal_host_ipo})
endif()
function(odocal_simulator_speed target)
  if(NOT ODOCAL_TARGET STREQUAL "host")
    return()
  endif()
  get_property(ipo GLOBAL PROPERTY ODOCAL_HOST_IPO)
  target_compile_options(${target} PRIVATE -O3 -ffp-contract=off -fno-math-errno)
  get_target_property(type ${target} TYPE)
  if(ipo)
    set_property(TARGET ${target} PROPERTY INTERPROCEDURAL_OPTIMIZATION ON)
    if(type STREQUAL "STATIC_LIBRARY")
      target_compile_options(${target} PRIVATE -ffat-lto-objects)
    endif()
  endif()
  set(profile -fprofile-dir=${ODOCAL_SIM_PGO_DIR} -fprofile-prefix-path=${CMAKE_BINARY_DIR})
  if(ODOCAL_SIM_PGO STREQUAL "generate")
    target_compile_options(${target} PRIVATE -fprofile-generate -fprofile-update=single ${profile})
    # Whatever links an instrumented library needs the profiling runtime.
    target_link_options(${target} PUBLIC -fprofile-generate)
  elseif(ODOCAL_SIM_PGO STREQUAL "use")
    # A profile older than the sources only loses speed: no error for a missing or stale one.
    target_compile_options(${target} PRIVATE -fprofile-use -fprofile-partial-training ${profile}
                                             -Wno-missing-profile -Wno-error=coverage-mismatch)
  elseif(NOT ODOCAL_SIM_PGO STREQUAL "")
    message(FATAL_ERROR "ODOCAL_SIM_PGO must be empty, generate or use, not ${ODOCAL_SIM_PGO}")
  endif()
endfunction()

# Unity builds of the host's libraries and programs (host_sim/) and of the fuzz build's host
# library: each batch of 8 sources is compiled as one translation unit, so that the json, fmt,
# CLI11 and Eigen headers every source includes are parsed once per batch, not once per file. A
# name defined twice at file scope in one batch fails to compile, never silently: keep file-local
# helpers unique in a folder, or share them through its header. The tests are compiled file by
# file (their files repeat local names). -DODOCAL_UNITY_BUILD=OFF: file by file everywhere
# (quicker after a one-file change).
option(ODOCAL_UNITY_BUILD "compile the host's large targets in unity batches" ON)
function(odocal_unity target)
  if(ODOCAL_UNITY_BUILD AND ODOCAL_TARGET STREQUAL "host")
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_BATCH_SIZE 8)
  endif()
endfunction()
