# TI C2000 (cl2000) toolchain for the TMS320F2812. TI's compiler is not packaged for Debian
# and is not installed here; when it is absent this file leaves the host compiler in place and
# sets DTC_CL2000_FOUND=OFF, and the top-level CMakeLists.txt prints that and configures nothing.
# Point C2000_CGT_ROOT at an installed "ti-cgt-c2000_<ver>" folder to use it.
set(C2000_CGT_ROOT "$ENV{C2000_CGT_ROOT}" CACHE PATH "TI C2000 code generation tools root")
find_program(DTC_CL2000 cl2000 HINTS "${C2000_CGT_ROOT}/bin" NO_CACHE)
set(DTC_TARGET_F2812 ON CACHE BOOL "" FORCE)
if(DTC_CL2000)
  set(DTC_CL2000_FOUND ON CACHE BOOL "" FORCE)
  set(CMAKE_SYSTEM_NAME Generic)
  set(CMAKE_SYSTEM_PROCESSOR c2000)
  set(CMAKE_C_COMPILER "${DTC_CL2000}")
  set(CMAKE_C_COMPILER_ID TI)
  find_program(CMAKE_AR ar2000 HINTS "${C2000_CGT_ROOT}/bin")
  set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
  set(CMAKE_C_FLAGS_INIT "-v28 -ml -mt --abi=coffabi --c99")
  set(DTC_FIRMWARE_ONLY ON CACHE BOOL "" FORCE)
else()
  set(DTC_CL2000_FOUND OFF CACHE BOOL "" FORCE)
  set(DTC_FIRMWARE_ONLY ON CACHE BOOL "" FORCE)
endif()
