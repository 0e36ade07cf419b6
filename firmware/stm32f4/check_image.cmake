# Checks a firmware image: no heap, no exception machinery, no printf family, within budget; the
# robot image (-DNO_DOUBLE=ON) also links no double-precision arithmetic (libgcc's soft double).
# cmake -DELF=… -DNM=… -DSIZE=… -DFLASH_BUDGET=bytes -DRAM_BUDGET=bytes -P check_image.cmake
# RAM_BUDGET bounds static RAM (.data + .bss) plus the stack the linker script reserves.
execute_process(COMMAND ${NM} --defined-only ${ELF} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "nm failed on ${ELF}")
endif()
set(forbidden
    malloc _malloc_r free _free_r calloc _calloc_r realloc _realloc_r _sbrk _sbrk_r
    __cxa_throw __cxa_allocate_exception __cxa_begin_catch __gxx_personality_v0
    _Unwind_RaiseException _Unwind_Resume __cxa_atexit atexit
    printf _printf_r vfprintf _vfprintf_r _svfprintf_r sprintf snprintf _vfiprintf_r)
set(found "")
foreach(sym ${forbidden})
  string(REGEX MATCH "[0-9a-fA-F]+ [A-Za-z] ${sym}\n" hit "${symbols}")
  if(hit)
    list(APPEND found ${sym})
  endif()
endforeach()
if(found)
  message(FATAL_ERROR "${ELF}: links ${found} (no heap, no exceptions, no printf in the image)")
endif()
set(double_note "")
if(NO_DOUBLE)
  foreach(sym __aeabi_dadd __aeabi_dsub __aeabi_dmul __aeabi_ddiv __aeabi_f2d __aeabi_d2f
              __aeabi_dcmplt __aeabi_i2d __aeabi_d2iz __aeabi_uldivmod __aeabi_ldivmod)
    string(REGEX MATCH "[0-9a-fA-F]+ [A-Za-z] ${sym}\n" hit "${symbols}")
    if(hit)
      list(APPEND found ${sym})
    endif()
  endforeach()
  if(found)
    message(FATAL_ERROR "${ELF}: links ${found} (the robot image does no double arithmetic and "
                        "no 64-bit division: see core/include/odocal/math/numeric.hpp)")
  endif()
  set(double_note "/double/64-bit division")
endif()

# Flash = everything loaded from flash (vectors, code, constants, .data's initial values);
# static RAM = .data + .bss (the stack is reserved separately by the linker script).
execute_process(COMMAND ${SIZE} -A ${ELF} OUTPUT_VARIABLE sections RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "size failed on ${ELF}")
endif()
string(REPLACE "\n" ";" lines "${sections}")
set(flash 0)
set(ram 0)
set(stack 0)
foreach(line ${lines})
  if(line MATCHES "^(\\.[A-Za-z_.]+) +([0-9]+) +([0-9]+)")
    set(section ${CMAKE_MATCH_1})
    set(bytes ${CMAKE_MATCH_2})
    if(section MATCHES "^\\.(isr_vector|text|rodata|ARM\\.exidx|init_array)$")
      math(EXPR flash "${flash} + ${bytes}")
    elseif(section STREQUAL ".data")
      math(EXPR flash "${flash} + ${bytes}")
      math(EXPR ram "${ram} + ${bytes}")
    elseif(section STREQUAL ".bss")
      math(EXPR ram "${ram} + ${bytes}")
    elseif(section STREQUAL ".stack")
      set(stack ${bytes})
    endif()
  endif()
endforeach()
get_filename_component(image ${ELF} NAME)
math(EXPR ram_total "${ram} + ${stack}")
message(STATUS "${image}: flash ${flash} B of budget ${FLASH_BUDGET}; RAM ${ram_total} B "
               "(static ${ram} + stack ${stack}) of budget ${RAM_BUDGET}; "
               "no malloc/exceptions/printf${double_note} linked")
if(flash GREATER FLASH_BUDGET)
  message(FATAL_ERROR "${image}: flash ${flash} B is over its budget of ${FLASH_BUDGET} B")
endif()
if(ram_total GREATER RAM_BUDGET)
  message(FATAL_ERROR "${image}: RAM ${ram_total} B (static ${ram} + stack ${stack}) is over its "
                      "budget of ${RAM_BUDGET} B")
endif()
