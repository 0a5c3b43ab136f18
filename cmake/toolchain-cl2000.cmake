# TI C2000 code generation tools (cl2000) for the TMS320F2812: the `f2812` preset.
#
# TI's compiler is not packaged for Debian and is not installed here. When it is absent this file
# leaves the host compiler in place and sets DTC_CL2000_FOUND=OFF; the top-level CMakeLists.txt then
# prints that and configures nothing (a clean exit, not an error).
#
# To use it, install TI's "C2000 Code Generation Tools" (ti-cgt-c2000_<version>, stand-alone or
# inside Code Composer Studio) and point C2000_CGT_ROOT at that folder, e.g.
#     C2000_CGT_ROOT=/opt/ti/ti-cgt-c2000_22.6.1.LTS cmake --preset f2812
#     cmake --build --preset f2812        # -> build/f2812/bin/dtc_f2812.out (+ dtc_f2812.hex)
# DTC_F2812_IMAGE=FLASH (default) or RAM selects linker/f2812_flash.cmd or linker/f2812_ram.cmd.
#
# Facts used (../shared/reference/f2812-facts.md 6.1-6.6): CMake knows cl2000 as compiler id "TI"
# (architecture TMS320C28x) and generates the --compile_only/--run_linker rules itself; the archiver
# is ar2000; the F281x libraries are COFF, large memory model (rts2800_ml.lib); there is no FPU.
# Not run end-to-end here (no compiler): see docs/f2812.md for what was and was not verified.

set(C2000_CGT_ROOT "$ENV{C2000_CGT_ROOT}" CACHE PATH "TI C2000 code generation tools root (ti-cgt-c2000_<ver>)")
set(DTC_TARGET_F2812 ON CACHE BOOL "" FORCE)
set(DTC_FIRMWARE_ONLY ON CACHE BOOL "" FORCE)

# Search the given root first, then the usual stand-alone and CCS install locations.
file(GLOB _dtc_cgt_guesses LIST_DIRECTORIES true
  /opt/ti/ti-cgt-c2000_* /opt/ti/ccs*/ccs/tools/compiler/ti-cgt-c2000_*
  $ENV{HOME}/ti/ti-cgt-c2000_* $ENV{HOME}/ti/ccs*/ccs/tools/compiler/ti-cgt-c2000_*)
set(_dtc_cgt_hints)
foreach(_d IN LISTS C2000_CGT_ROOT _dtc_cgt_guesses)
  if(_d)
    list(APPEND _dtc_cgt_hints "${_d}/bin")
  endif()
endforeach()
find_program(DTC_CL2000 cl2000 HINTS ${_dtc_cgt_hints} NO_CACHE)

if(NOT DTC_CL2000)
  set(DTC_CL2000_FOUND OFF CACHE BOOL "" FORCE)
  return()
endif()

set(DTC_CL2000_FOUND ON CACHE BOOL "" FORCE)
get_filename_component(_dtc_cgt_bin "${DTC_CL2000}" DIRECTORY)
get_filename_component(_dtc_cgt_root "${_dtc_cgt_bin}" DIRECTORY)
if(NOT C2000_CGT_ROOT)
  set(C2000_CGT_ROOT "${_dtc_cgt_root}" CACHE PATH "" FORCE)
endif()

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR c2000)
set(CMAKE_C_COMPILER "${DTC_CL2000}")
set(CMAKE_ASM_COMPILER "${DTC_CL2000}")   # f2812_codestart.asm goes through the same driver
find_program(CMAKE_AR ar2000 HINTS "${_dtc_cgt_bin}" REQUIRED)
find_program(DTC_HEX2000 hex2000 HINTS "${_dtc_cgt_bin}")
# Compiler detection only compiles (no .cmd file is needed to link a test program).
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# -v28: C28x; -ml: large memory model (all F281x libraries; ignored by newer compilers, where it is
# always on); -mt: unified program/data memory (true on the F281x); COFF ABI to match
# rts2800_ml.lib and the _X symbol names in linker/*.cmd; C99 for the firmware. No --float_support:
# the F2812 has no FPU and the firmware has no floating point.
set(CMAKE_C_FLAGS_INIT "-v28 -ml -mt --abi=coffabi --c99 --diag_wrap=off --display_error_number")
set(CMAKE_ASM_FLAGS_INIT "-v28 -ml -mt --abi=coffabi")
set(CMAKE_C_FLAGS_RELEASE_INIT "-O2 --opt_for_speed=5")
set(CMAKE_C_FLAGS_DEBUG_INIT "-g -Od")

set(CMAKE_C_STANDARD_INCLUDE_DIRECTORIES "${C2000_CGT_ROOT}/include")

# Linker options for the image (used by hal/f2812/CMakeLists.txt with linker/*.cmd):
# --rom_model: C auto-initialisation at run time from .cinit (needed in flash);
# stack 0x400 words in M0/M1; no heap; warn about sections the .cmd does not place.
set(DTC_CL2000_LINK_FLAGS
  --rom_model --stack_size=0x400 --heap_size=0 --warn_sections --reread_libs
  "--search_path=${C2000_CGT_ROOT}/lib" "--search_path=${C2000_CGT_ROOT}/include"
  --library=rts2800_ml.lib)

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
