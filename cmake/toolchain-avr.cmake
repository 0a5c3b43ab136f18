# Portability proxy for the C28x's 16-bit int: on avr-gcc, int is 16 bits, so an
# int16_t * int16_t product is NOT widened to 32 bits, exactly as on the C28x. A missing
# "(int32_t)a * b" widening is then a real overflow the fixed-point tests would see, and
# -Wconversion flags many of them at compile time.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR avr)
set(CMAKE_C_COMPILER avr-gcc)
set(CMAKE_AR avr-ar)
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)
set(CMAKE_C_FLAGS_INIT "-mmcu=atmega2560 -ffreestanding -fno-common -ffunction-sections -fdata-sections")
set(DTC_FIRMWARE_ONLY ON CACHE BOOL "" FORCE)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
