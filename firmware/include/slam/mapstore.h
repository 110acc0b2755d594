/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Saving the maps to persistent storage, a chunk at a time, from the background loop.
 *
 * The HAL offers HAL_STORAGE_SLOTS slots (two flash sectors on the MCU, two files on
 * Linux). A save goes to the slot that does not hold the newest good record, so a power
 * cut in the middle of a save never loses the last good map. A record is
 *
 *     header (mapstore_header_t, 56 bytes) | OM (A·B bytes) | TM (A·B bytes)
 *
 * The data is written first, the header last; the header carries a CRC-32 of the data
 * and one of itself, and a sequence number that grows with every save. A slot is good
 * when both CRCs match; of two good slots the higher sequence number wins.
 *
 * mapstore_step() writes at most MAPSTORE_CHUNK bytes per call, copying each chunk out of
 * the live map before checksumming and writing it, so the tick may keep updating the map
 * while a save is under way (the record is then a snapshot taken over the save's time).
 * Never call it from the tick.
 */
#ifndef SLAM_MAPSTORE_H
#define SLAM_MAPSTORE_H

#include <stdbool.h>
#include <stdint.h>

#include "slam/grid.h"
#include "slam/odometry.h"

#define MAPSTORE_MAGIC 0x4D414C53u /**< "SLAM" in a little-endian dump */
#define MAPSTORE_VERSION 2u
#define MAPSTORE_CHUNK 256u /**< bytes written per mapstore_step() */

/** The header at the start of a slot (all fields little-endian on every target). */
typedef struct {
    uint32_t magic;        /**< MAPSTORE_MAGIC */
    uint16_t version;      /**< MAPSTORE_VERSION */
    uint16_t header_bytes; /**< sizeof(mapstore_header_t): the data starts here */
    uint16_t a, b;         /**< grid size */
    uint32_t cell_um;      /**< L */
    int32_t origin_x_um;   /**< lower-left corner of cell (0, 0) */
    int32_t origin_y_um;
    uint32_t seq;      /**< grows with every save */
    uint32_t ticks;    /**< robot ticks when the save began */
    int32_t pose_x_um; /**< the robot's pose when the save began */
    int32_t pose_y_um;
    uint32_t pose_heading; /**< binary angle */
    uint8_t om_mode;       /**< what an OM cell holds (om_mode_t), so a reader can tell */
    uint8_t om_hit;        /**< OM_MODE_EVIDENCE: the log-odds steps */
    uint8_t om_miss;
    uint8_t om_max;      /**< OM_MODE_COUNT: OMmax */
    uint32_t data_crc;   /**< CRC-32 (IEEE) of OM then TM */
    uint32_t header_crc; /**< CRC-32 of the header bytes before this field */
} mapstore_header_t;

/** Progress of saves. */
typedef struct {
    bool active;           /**< a save is under way */
    bool available;        /**< the HAL has storage large enough for a record */
    uint8_t slot;          /**< the slot being written */
    uint32_t offset;       /**< data bytes written so far */
    uint32_t crc;          /**< running CRC of the data */
    mapstore_header_t hdr; /**< the header of the save under way */
    uint32_t last_seq;     /**< sequence number of the newest good record */
    uint8_t last_slot;     /**< and its slot */
    uint32_t saves;        /**< saves completed */
    uint32_t failures;     /**< saves abandoned because the HAL failed */
} mapstore_t;

/**
 * Find the newest good record (header and data CRCs both match, as mapstore_load()
 * requires), so saves continue its sequence in the other slot and never overwrite it.
 * Reads both slots whole. Saving is available when a slot holds the maps of grid @p g
 * (set by grid_init()): a storage sized for a run's grid serves it. Not ISR-safe.
 */
void mapstore_init(mapstore_t *s, const grid_t *g);

/** Begin a save of the maps and the pose now (ignored while one is under way). */
void mapstore_begin(mapstore_t *s, const grid_t *g, const odom_pose_t *pose, uint32_t ticks);

/**
 * Write the next chunk of a save under way; the header and the commit at the end.
 * @return true while a save is still under way
 */
bool mapstore_step(mapstore_t *s, const grid_t *g);

/**
 * Read the header of a slot and check it (magic, version, header CRC).
 * @retval SLAM_OK      a well-formed header in *h
 * @retval SLAM_EIO     the slot cannot be read, or holds no good header
 */
int mapstore_read_header(uint8_t slot, mapstore_header_t *h);

/**
 * Load the newest record whose header and data check out into a grid of its size: @p g
 * has been through grid_init() with the grid_a and grid_b of the run that saved it (an
 * older good record if the newest is damaged). Not ISR-safe.
 * @retval SLAM_OK       loaded (geometry and maps), pose in *pose if not NULL
 * @retval SLAM_EIO      no good record; the grid is unchanged
 * @retval SLAM_EINVAL   the only good records are of another grid size; unchanged
 */
int mapstore_load(grid_t *g, odom_pose_t *pose);

/** CRC-32 (IEEE 802.3, reflected) of @p len bytes, continuing from @p crc (0 to start). */
uint32_t mapstore_crc32(uint32_t crc, const uint8_t *data, uint32_t len);

#endif /* SLAM_MAPSTORE_H */
