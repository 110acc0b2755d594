# SPDX-License-Identifier: MIT
# Proves the image check works: links a probe with doubles and malloc, runs the check on
# it and passes only if the check refuses it, naming the offending symbols.
#   cmake -DCC=... -DNM=... -DSRC=softfloat_probe.c -DCHECK=check_image.cmake -DOUT=dir -P check_image_probe.cmake

file(MAKE_DIRECTORY ${OUT})
set(elf ${OUT}/softfloat_probe.elf)
execute_process(COMMAND ${CC} -mcpu=cortex-m4 -mthumb -mfloat-abi=soft -O2 --specs=nano.specs
                        --specs=nosys.specs ${SRC} -o ${elf}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the probe did not build, so the check proves nothing:\n${err}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -DELF=${elf} -DNM=${NM} -P ${CHECK}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(rc EQUAL 0)
    message(FATAL_ERROR "the image check accepted a probe that uses double and malloc")
endif()
foreach(sym __aeabi_dmul malloc)
    if(NOT err MATCHES "${sym}")
        message(FATAL_ERROR "the image check refused the probe without naming ${sym}:\n${err}")
    endif()
endforeach()
if(EXISTS ${elf})
    message(FATAL_ERROR "the image check left the refused image in place")
endif()
message(STATUS "the image check refuses soft-float helpers and the heap")
