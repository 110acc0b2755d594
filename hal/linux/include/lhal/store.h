/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Map storage as files: each HAL storage slot is DIR/slotN.bin, replaced atomically.
 *
 * hal_storage_begin() starts a new copy DIR/slotN.tmp filled with 0xFF (like erased
 * flash), writes go into it, and commit makes it durable and visible in one step: fsync
 * the copy, rename it over slotN.bin, fsync the directory. A power cut at any moment
 * leaves either the old slot or the new one, never a torn one; a leftover .tmp from an
 * interrupted rewrite is removed at the next start. A slot never written reads as 0xFF,
 * again like erased flash, and so do bytes beyond a shorter file.
 *
 * Return codes are the HAL's. Not thread-safe: one background thread uses it.
 */
#ifndef LHAL_STORE_H
#define LHAL_STORE_H

#include <stddef.h>
#include <stdint.h>

#include "hal/hal.h"

/** Longest storage directory path. */
#define STORE_DIR_MAX 200u

/** The slots' directory and size, and the rewrites under way. */
typedef struct {
    char dir[STORE_DIR_MAX];
    size_t size;                   /**< bytes in a slot */
    int tmp_fd[HAL_STORAGE_SLOTS]; /**< open copy of a slot being rewritten, or -1 */
} store_t;

/**
 * Use (and create, one level deep) a directory for the slots; remove stale copies.
 * @return 0, or -1 with err saying what failed
 */
int store_open(store_t *s, const char *dir, size_t size, char *err, size_t errlen);

/**
 * Whether store_open() would succeed, without creating or removing anything (--check).
 * @param note  out: on success, "exists" or "will be created"; on failure, why not
 * @return 0, or -1
 */
int store_probe(const char *dir, char *note, size_t notelen);

/** Drop rewrites that were not committed (their copies are removed). */
void store_close(store_t *s);

/** @retval HAL_OK / HAL_EINVAL (no such slot) / HAL_EIO */
int store_begin(store_t *s, uint8_t slot);

/** @retval HAL_OK / HAL_EINVAL (slot not begun, or range beyond the slot) / HAL_EIO */
int store_write(store_t *s, uint8_t slot, uint32_t offset, const void *data, size_t len);

/** @retval HAL_OK / HAL_EINVAL (slot not begun) / HAL_EIO (the old slot is kept) */
int store_commit(store_t *s, uint8_t slot);

/** @retval HAL_OK / HAL_EINVAL (slot, or range beyond the slot) / HAL_EIO */
int store_read(const store_t *s, uint8_t slot, uint32_t offset, void *data, size_t len);

/**
 * Replace DIR/NAME atomically with @p len bytes (write a copy, fsync, rename, fsync DIR).
 * @return 0, or -errno (the old file, if any, is untouched)
 */
int store_write_file(const char *dir, const char *name, const void *data, size_t len);

#endif /* LHAL_STORE_H */
