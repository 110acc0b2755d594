# SPDX-License-Identifier: MIT
# Warning flags for the project's own targets: every warning is an error.

set(SLAM_WARNING_FLAGS
    -Wall -Wextra -Werror
    -Wconversion -Wsign-conversion -Wshadow
    -Wpointer-arith -Wcast-align -Wstrict-prototypes -Wmissing-prototypes
    -Wundef -Wvla -Wdouble-promotion -Wformat=2 -Wimplicit-fallthrough)

# slam_target_warnings(<target>...): apply the project's warning flags.
function(slam_target_warnings)
    foreach(t IN LISTS ARGN)
        target_compile_options(${t} PRIVATE ${SLAM_WARNING_FLAGS})
    endforeach()
endfunction()
