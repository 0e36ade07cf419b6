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
function(odocal_core_area name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB srcs CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/${name}/*.cpp)
  if(srcs)
    add_library(odocal_${name} STATIC ${srcs})
    target_link_libraries(odocal_${name} PUBLIC odocal_core_headers ${ARG_DEPS})
    # The core's own rules, applied to its sources only (consumers keep their own flags).
    target_compile_options(odocal_${name} PRIVATE -Wdouble-promotion -Wfloat-conversion -Wshadow
                                                  -fno-exceptions -fno-rtti)
  else()
    add_library(odocal_${name} INTERFACE)
    target_link_libraries(odocal_${name} INTERFACE odocal_core_headers ${ARG_DEPS})
  endif()
endfunction()
