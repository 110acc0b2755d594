# SPDX-License-Identifier: MIT
# Proves that hal/defaults' weak definitions (hal_unsupported.c) give way to a backend's,
# whichever side of the backend's archive the defaults' archive is linked on, and answer
# where the backend has none, with one compiler and its linker:
#   cmake -DCC=cc ["-DCFLAGS=-mcpu=cortex-m4 -mthumb"] -DAR=ar -DNM=nm -DSRC=<repository>
#         -DOUT=dir -P weak_link_order.cmake
# The programs are linked without a C library (entry main) and never run: nm tells which
# definition each took (T: the backend's, W: the weak default).

foreach(v CC AR NM SRC OUT)
    if(NOT ${v})
        message(FATAL_ERROR "weak_link_order: -D${v}=... is missing")
    endif()
endforeach()
separate_arguments(CFLAGS UNIX_COMMAND "${CFLAGS}")
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
set(probe ${CMAKE_CURRENT_LIST_DIR}/link_probe.c)

function(compile obj src)
    execute_process(COMMAND ${CC} ${CFLAGS} -std=c11 -O2 -I${SRC}/hal/include ${ARGN}
                            -c ${src} -o ${OUT}/${obj}
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "weak_link_order: ${CC} did not compile ${obj}:\n${err}")
    endif()
endfunction()

function(archive lib obj)
    execute_process(COMMAND ${AR} rcs ${OUT}/${lib} ${OUT}/${obj}
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "weak_link_order: ${AR} failed on ${lib}:\n${err}")
    endif()
endfunction()

# link(<program> <main object> <archives>...), then expect the symbol kinds that follow
# the archives as SYMBOL=KIND pairs.
function(link_expect prog main)
    set(archives "")
    set(expect "")
    foreach(a IN LISTS ARGN)
        if(a MATCHES "=")
            list(APPEND expect ${a})
        else()
            list(APPEND archives ${OUT}/${a})
        endif()
    endforeach()
    execute_process(COMMAND ${CC} ${CFLAGS} -nostdlib -Wl,-e,main -o ${OUT}/${prog}
                            ${OUT}/${main} ${archives}
                    RESULT_VARIABLE rc ERROR_VARIABLE err)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "weak_link_order: ${prog} did not link:\n${err}")
    endif()
    execute_process(COMMAND ${NM} ${OUT}/${prog} OUTPUT_VARIABLE syms RESULT_VARIABLE rc)
    if(NOT rc EQUAL 0)
        message(FATAL_ERROR "weak_link_order: ${NM} failed on ${prog}")
    endif()
    foreach(e IN LISTS expect)
        string(REPLACE "=" ";" e "${e}")
        list(GET e 0 sym)
        list(GET e 1 kind)
        if(NOT syms MATCHES "[0-9a-fA-F]+ ${kind} ${sym}\n")
            message(FATAL_ERROR "weak_link_order: in ${prog} (${archives}) ${sym} is not "
                                "of kind ${kind}:\n${syms}")
        endif()
    endforeach()
endfunction()

compile(defaults.o ${SRC}/hal/defaults/hal_unsupported.c)
compile(core.o ${probe} -DPROBE_CORE)
compile(backend.o ${probe} -DPROBE_BACKEND -DPROBE_STORAGE)
compile(backend_bare.o ${probe} -DPROBE_BACKEND)
compile(main.o ${probe} -DPROBE_MAIN)
compile(main_storage.o ${probe} -DPROBE_MAIN -DPROBE_STORAGE)
archive(libdefaults.a defaults.o)
archive(libcore.a core.o)
archive(libbackend.a backend.o)
archive(libbackend_bare.a backend_bare.o)

# A backend in one file with storage (the template's shape): its storage, the default read.
link_expect(after.elf main.o libcore.a libbackend.a libdefaults.a
            hal_storage_size=T hal_storage_begin=T hal_uart_read=W hal_init=T)
link_expect(before.elf main.o libcore.a libdefaults.a libbackend.a
            hal_storage_size=T hal_storage_begin=T hal_uart_read=W hal_init=T)
# A backend without storage: the defaults answer, on either side.
link_expect(bare_after.elf main.o libcore.a libbackend_bare.a libdefaults.a
            hal_storage_size=W hal_storage_begin=W hal_uart_read=W)
link_expect(bare_before.elf main.o libcore.a libdefaults.a libbackend_bare.a
            hal_storage_size=W hal_storage_begin=W hal_uart_read=W)
# Storage in the program's own file (the bench's and the replay HAL's shape).
link_expect(own_after.elf main_storage.o libcore.a libbackend_bare.a libdefaults.a
            hal_storage_size=T hal_storage_begin=T hal_uart_read=W)
link_expect(own_before.elf main_storage.o libcore.a libdefaults.a libbackend_bare.a
            hal_storage_size=T hal_storage_begin=T hal_uart_read=W)
message(STATUS "weak_link_order: ${CC}: a backend's definitions win on either side of "
               "hal_unsupported, and its weak ones answer where a backend has none")
