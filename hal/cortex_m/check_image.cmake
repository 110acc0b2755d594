# SPDX-License-Identifier: MIT
# Fails when an image links a soft-float helper or the heap: cmake -DELF=... -DNM=... -P check_image.cmake
#
# The firmware is fixed point with static memory. With -mfloat-abi=soft any float or double
# turns into calls such as __aeabi_dmul or __floatsidf, and malloc pulls in _sbrk; this
# check looks for them in the linked image and deletes an offending image, so the next
# build links and checks it again instead of calling it up to date.

if(NOT ELF OR NOT NM)
    message(FATAL_ERROR "usage: cmake -DELF=image.elf -DNM=arm-none-eabi-nm -P check_image.cmake")
endif()
execute_process(COMMAND ${NM} --defined-only --format=posix ${ELF}
                OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "check_image: ${NM} failed on ${ELF}")
endif()

set(bad "")
string(REPLACE "\n" ";" lines "${symbols}")
foreach(line IN LISTS lines)
    string(REGEX MATCH "^[^ ]+" sym "${line}")
    if(sym MATCHES "^__aeabi_[fd]"                                   # AEABI soft-float
       OR sym MATCHES "^__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord)[sdt]f[23]$"
       OR sym MATCHES "^__(float|fix|fixuns)[a-z]*[sdt]f[a-z]*$"      # conversions
       OR sym MATCHES "^__(extend|trunc)[sd]f[sd]f2$"
       OR sym MATCHES "^_?(malloc|calloc|realloc|free|_sbrk|sbrk|_malloc_r|_free_r)$")
        list(APPEND bad ${sym})
    endif()
endforeach()

if(bad)
    list(REMOVE_DUPLICATES bad)
    string(REPLACE ";" " " bad "${bad}")
    file(REMOVE ${ELF})
    message(FATAL_ERROR "check_image: ${ELF} links floating point or the heap: ${bad}\n"
                        "The firmware must stay fixed point with static memory (DESIGN.md).")
endif()
message(STATUS "check_image: ${ELF}: no soft-float helper, no heap")
