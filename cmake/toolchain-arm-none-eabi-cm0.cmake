# Portability proxy: the firmware library built freestanding for a Cortex-M0 (no FPU, no
# hardware divide). Any float, double or division in the firmware shows up as a call to a
# libgcc helper (__aeabi_f*, __aeabi_d*, __aeabi_*div*), which tests/rules/ rejects.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_C_FLAGS_INIT "-mcpu=cortex-m0 -mthumb -ffreestanding -fno-common -ffunction-sections -fdata-sections -fstack-usage")
set(DTC_FIRMWARE_ONLY ON CACHE BOOL "" FORCE)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
