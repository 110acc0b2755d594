# SPDX-License-Identifier: MIT
# Cross toolchain of the stm32f4 board: Debian's arm-none-eabi-gcc and newlib-nano for a
# Cortex-M4 with the FPU left off (the firmware is fixed point). Used by the stm32f4 preset.

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

find_program(ARM_NONE_EABI_GCC arm-none-eabi-gcc)
if(NOT ARM_NONE_EABI_GCC)
    message(FATAL_ERROR "arm-none-eabi-gcc was not found. On Debian: tools/install-deps.sh firmware "
                        "(gcc-arm-none-eabi, libnewlib-arm-none-eabi).")
endif()
get_filename_component(_arm_bin "${ARM_NONE_EABI_GCC}" DIRECTORY)

set(CMAKE_C_COMPILER ${ARM_NONE_EABI_GCC})
set(CMAKE_ASM_COMPILER ${ARM_NONE_EABI_GCC})
set(CMAKE_OBJCOPY ${_arm_bin}/arm-none-eabi-objcopy CACHE FILEPATH "objcopy of the cross toolchain")
set(CMAKE_OBJDUMP ${_arm_bin}/arm-none-eabi-objdump CACHE FILEPATH "objdump of the cross toolchain")
set(CMAKE_NM ${_arm_bin}/arm-none-eabi-nm CACHE FILEPATH "nm of the cross toolchain")
set(ARM_NONE_EABI_SIZE ${_arm_bin}/arm-none-eabi-size CACHE FILEPATH "size of the cross toolchain")

# No program can run without start-up code: test the compiler by building a library.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

# -mfloat-abi=soft: any float or double becomes a call to a soft-float helper, which the
# image check (hal/cortex_m/check_image.cmake) refuses. Every function in its own section
# so the linker drops what is unused; stack use and call graph per function for the
# tick's stack budget (tools/cortex_m.py stack-depth).
set(CMAKE_C_FLAGS_INIT
    "-mcpu=cortex-m4 -mthumb -mfloat-abi=soft -ffunction-sections -fdata-sections -fno-common \
-fno-unwind-tables -fno-asynchronous-unwind-tables -fstack-usage -fcallgraph-info=su")
set(CMAKE_EXE_LINKER_FLAGS_INIT "-mcpu=cortex-m4 -mthumb -mfloat-abi=soft --specs=nano.specs -nostartfiles -Wl,--gc-sections")

set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
