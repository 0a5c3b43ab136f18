# Strict warnings for the code that runs on the DSP (firmware/ and hal/), as errors.
# -Wconversion/-Wsign-conversion catch silent narrowing that would truncate differently on
# the C28x (16-bit int); -Wdouble-promotion catches a float sneaking into the control path.
set(DTC_FIRMWARE_WARNINGS
  -Wall -Wextra -Wconversion -Wsign-conversion -Wshadow -Wdouble-promotion
  -Wstrict-prototypes -Wmissing-prototypes -Werror)
if(CMAKE_C_COMPILER_ID STREQUAL "TI")
  # cl2000 (f2812 preset) spells it differently and rejects the gcc flags.
  set(DTC_FIRMWARE_WARNINGS --emit_warnings_as_errors)
endif()

function(dtc_firmware_warnings target)
  get_target_property(_type ${target} TYPE)
  if(_type STREQUAL "INTERFACE_LIBRARY")
    return()
  endif()
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:C>:${DTC_FIRMWARE_WARNINGS}>)
endfunction()

# Host-side C++ (model, hal/host, tools, tests) gets the usual warnings, not -Werror on
# third-party headers' behalf.
function(dtc_host_warnings target)
  target_compile_options(${target} PRIVATE
    $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wshadow>
    $<$<COMPILE_LANGUAGE:C>:-Wall -Wextra>)
endfunction()
