/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The entry point every fuzz target defines: libFuzzer's, so the same file builds as a
 * libFuzzer binary (clang, `make fuzz`) and as a corpus runner (run_corpus.c, any
 * compiler, in `make test`). A target returns 0 and aborts on a property it finds broken.
 */
#ifndef SLAM_FUZZ_H
#define SLAM_FUZZ_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/** A broken property: say which, and abort so the fuzzer keeps the input. */
#define FUZZ_CHECK(cond)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: property broken: %s\n", __FILE__, __LINE__, #cond);            \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

#endif /* SLAM_FUZZ_H */
