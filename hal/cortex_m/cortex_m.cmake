# SPDX-License-Identifier: MIT
# What every Cortex-M chip folder's CMakeLists.txt includes: the start-up code, critical
# section and text lines each image links, linking and checking an image, and the replay
# self-test image that QEMU runs.
#
# The chip folder provides the rest: cm_chip.h (its interrupts, for the vector table), a
# linker script that names the regions FLASH and RAM and INCLUDEs cm_sections.ld, its HAL
# (the tick, the drivers), and for the self-test image selftest_port.c (selftest_port.h).
include_guard(DIRECTORY)

# This folder, for the including directory; the functions below find it themselves, so
# they work from any directory (tests/<chip> links test images with them).
set(CORTEX_M_DIR ${CMAKE_CURRENT_LIST_DIR})

# Start-up copies .data and clears .bss before anything else may run: keep GCC from
# turning those loops into memcpy/memset calls. Start-up and the text of reports run at
# start-up or in the background loop: built for size (see firmware/).
set_source_files_properties(${CORTEX_M_DIR}/startup.c PROPERTIES
                            COMPILE_OPTIONS -fno-tree-loop-distribute-patterns)
set_property(SOURCE ${CORTEX_M_DIR}/startup.c ${CORTEX_M_DIR}/text.c
             APPEND PROPERTY COMPILE_OPTIONS -Os)

# cortex_m_runtime(<target>): add to <target>, a chip's OBJECT library whose include path
# holds its cm_chip.h, the start-up code (vector table, RAM init, weak handlers, faults),
# the HAL critical section and the text lines.
function(cortex_m_runtime target)
    set(dir ${CMAKE_CURRENT_FUNCTION_LIST_DIR})
    target_sources(${target} PRIVATE ${dir}/startup.c ${dir}/critical.c ${dir}/text.c)
    target_include_directories(${target} PUBLIC ${dir})
endfunction()

# cortex_m_image(<target> LINKER_SCRIPT <file> STACK_BYTES <n> GRID <A> <B>): link with the
# chip's linker script and a main stack of n bytes, then write .bin, .hex, the map file and
# the size report, and refuse soft-float helpers and the heap (check_image.cmake). The
# image's grid, A x B cells, becomes the absolute symbols _grid_a and _grid_b (no byte of
# flash or RAM), so a tool reading the image knows the map its RAM budget is for.
function(cortex_m_image target)
    set(dir ${CMAKE_CURRENT_FUNCTION_LIST_DIR})
    cmake_parse_arguments(I "" "LINKER_SCRIPT;STACK_BYTES" "GRID" ${ARGN})
    list(LENGTH I_GRID _n)
    if(NOT I_LINKER_SCRIPT OR NOT I_STACK_BYTES OR NOT _n EQUAL 2)
        message(FATAL_ERROR "cortex_m_image(${target}) needs LINKER_SCRIPT, STACK_BYTES and GRID A B")
    endif()
    list(GET I_GRID 0 _a)
    list(GET I_GRID 1 _b)
    set_target_properties(${target} PROPERTIES SUFFIX ".elf"
                          LINK_DEPENDS "${I_LINKER_SCRIPT};${dir}/cm_sections.ld")
    target_link_options(${target} PRIVATE
        -T${I_LINKER_SCRIPT}
        -L${dir}
        -Wl,-Map=$<TARGET_FILE_DIR:${target}>/${target}.map
        -Wl,--defsym=_stack_size=${I_STACK_BYTES}
        -Wl,--defsym=_grid_a=${_a} -Wl,--defsym=_grid_b=${_b})
    slam_target_warnings(${target})
    add_custom_command(TARGET ${target} POST_BUILD
        COMMAND ${CMAKE_COMMAND} -DELF=$<TARGET_FILE:${target}> -DNM=${CMAKE_NM}
                -P ${dir}/check_image.cmake
        COMMAND ${CMAKE_OBJCOPY} -O binary $<TARGET_FILE:${target}> $<TARGET_FILE_DIR:${target}>/${target}.bin
        COMMAND ${CMAKE_OBJCOPY} -O ihex $<TARGET_FILE:${target}> $<TARGET_FILE_DIR:${target}>/${target}.hex
        COMMAND ${ARM_NONE_EABI_SIZE} $<TARGET_FILE:${target}>
        VERBATIM)
endfunction()

set(SLAM_SELFTEST_TRACE "" CACHE FILEPATH "A HAL trace for the self-test (empty: the shipped one)")
find_package(Python3 REQUIRED COMPONENTS Interpreter)

# cortex_m_selftest(<target> SOURCES <chip sources>... [CORE <core>]): the self-test image,
# the firmware over the replay HAL and the recorded scenario (selftest/), with the chip's
# selftest_port.c among the sources; link it with the chip's own image function, which calls
# cortex_m_image(). CORE is the core variant of the board's grid (slam_add_core; slam_core
# by default): the host half of the self-test must be built with the same grid. The
# scenario is -DSLAM_SELFTEST_TRACE=FILE, or the trace the tests ship (not cached, so a new
# default reaches existing build trees).
function(cortex_m_selftest target)
    set(dir ${CMAKE_CURRENT_FUNCTION_LIST_DIR})
    cmake_parse_arguments(S "" "CORE" "SOURCES" ${ARGN})
    if(NOT S_CORE)
        set(S_CORE slam_core)
    endif()
    if(SLAM_SELFTEST_TRACE)
        set(trace ${SLAM_SELFTEST_TRACE})
    else()
        set(trace ${PROJECT_SOURCE_DIR}/tests/data/clutter_260s.trace)
    endif()
    set(scenario ${CMAKE_CURRENT_BINARY_DIR}/${target}_scenario.c)
    set(tools ${PROJECT_SOURCE_DIR}/tools)
    add_custom_command(OUTPUT ${scenario}
        COMMAND ${Python3_EXECUTABLE} ${tools}/cortex_m.py trace2c ${trace} ${scenario}
        DEPENDS ${tools}/cortex_m.py ${tools}/slamtools/cortex_m/trace2c.py ${trace}
        COMMENT "Generating the self-test scenario from ${trace}"
        VERBATIM)
    set(st ${dir}/selftest)
    add_executable(${target} ${st}/selftest_main.c ${st}/selftest.c ${st}/hal_replay.c
                             ${st}/semihost.c ${S_SOURCES} ${scenario})
    target_include_directories(${target} PRIVATE ${st} ${PROJECT_SOURCE_DIR}/hal/common/include)
    target_link_libraries(${target} PRIVATE ${S_CORE} hal_unsupported)
endfunction()
