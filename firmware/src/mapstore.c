/* SPDX-License-Identifier: MIT */
/* Map persistence: two slots, data first and header last, CRC-checked, a chunk per call. */
#include "slam/mapstore.h"

#include <stddef.h>
#include <string.h>

#include "hal/hal.h"
#include "slam/error.h"

/* tools/plot_run.py reads records from a dump: its header layout is this one. */
_Static_assert(sizeof(mapstore_header_t) == 56u, "mapstore_header_t changed: update plot_run.py");

/* CRC-32 with a 16-entry table: 64 bytes of flash, two lookups per byte. */
static const uint32_t crc_nibble[16] = {
    0x00000000u, 0x1DB71064u, 0x3B6E20C8u, 0x26D930ACu, 0x76DC4190u, 0x6B6B51F4u,
    0x4DB26158u, 0x5005713Cu, 0xEDB88320u, 0xF00F9344u, 0xD6D6A3E8u, 0xCB61B38Cu,
    0x9B64C2B0u, 0x86D3D2D4u, 0xA00AE278u, 0xBDBDF21Cu,
};

uint32_t mapstore_crc32(uint32_t crc, const uint8_t *data, uint32_t len)
{
    crc = ~crc;
    for (uint32_t i = 0; i < len; i++) {
        crc ^= data[i];
        crc = (crc >> 4) ^ crc_nibble[crc & 0xFu];
        crc = (crc >> 4) ^ crc_nibble[crc & 0xFu];
    }
    return ~crc;
}

/* A record holds OM then TM, A·B cells each: its size follows the grid's. */
static uint32_t data_bytes(uint16_t a, uint16_t b)
{
    return 2u * (uint32_t)a * b;
}

static uint32_t header_crc(const mapstore_header_t *h)
{
    return mapstore_crc32(0u, (const uint8_t *)h,
                          (uint32_t)offsetof(mapstore_header_t, header_crc));
}

int mapstore_read_header(uint8_t slot, mapstore_header_t *h)
{
    mapstore_header_t t;
    if (hal_storage_read(slot, 0u, &t, sizeof t) != HAL_OK || t.magic != MAPSTORE_MAGIC ||
        t.version != MAPSTORE_VERSION || t.header_bytes != sizeof t ||
        t.header_crc != header_crc(&t)) {
        return SLAM_EIO;
    }
    *h = t;
    return SLAM_OK;
}

static bool data_good(uint8_t slot, const mapstore_header_t *h);

void mapstore_init(mapstore_t *s, const grid_t *g)
{
    memset(s, 0, sizeof *s);
    s->available =
        hal_storage_size() >= sizeof(mapstore_header_t) + data_bytes(g->a_cells, g->b_cells);
    s->last_slot = HAL_STORAGE_SLOTS - 1u; /* so the first save goes to slot 0 */
    if (!s->available) {
        return;
    }
    /* The newest record whose data checks too, as mapstore_load() picks it: a record
     * whose data rotted under a good header must not draw the next save onto the last
     * intact map. */
    for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
        mapstore_header_t h;
        if (mapstore_read_header(slot, &h) == SLAM_OK &&
            (h.seq > s->last_seq || s->last_seq == 0u) && data_good(slot, &h)) {
            s->last_seq = h.seq;
            s->last_slot = slot;
        }
    }
}

void mapstore_begin(mapstore_t *s, const grid_t *g, const odom_pose_t *pose, uint32_t ticks)
{
    if (s->active || !s->available) {
        return;
    }
    uint8_t slot = (uint8_t)((s->last_slot + 1u) % HAL_STORAGE_SLOTS);
    if (hal_storage_begin(slot) != HAL_OK) {
        s->failures++;
        return;
    }
    s->hdr = (mapstore_header_t){
        .magic = MAPSTORE_MAGIC,
        .version = MAPSTORE_VERSION,
        .header_bytes = sizeof(mapstore_header_t),
        .a = g->a_cells,
        .b = g->b_cells,
        .cell_um = g->cell_um,
        .origin_x_um = g->origin_x_um,
        .origin_y_um = g->origin_y_um,
        .seq = s->last_seq + 1u,
        .ticks = ticks,
        .pose_x_um = pose->x_um,
        .pose_y_um = pose->y_um,
        .pose_heading = pose->heading,
        .om_mode = g->mode,
        .om_hit = g->hit,
        .om_miss = g->miss,
        .om_max = g->om_max,
    };
    s->slot = slot;
    s->offset = 0u;
    s->crc = 0u;
    s->active = true;
}

static void abandon(mapstore_t *s)
{
    s->active = false;
    s->failures++;
}

bool mapstore_step(mapstore_t *s, const grid_t *g)
{
    if (!s->active) {
        return false;
    }
    const uint32_t cells = grid_cells(g);
    if (s->offset < 2u * cells) {
        /* Copy the chunk out first: the tick may change the map meanwhile, and the CRC
         * must describe exactly the bytes written. */
        uint8_t chunk[MAPSTORE_CHUNK];
        uint32_t n = 2u * cells - s->offset;
        n = n > MAPSTORE_CHUNK ? MAPSTORE_CHUNK : n;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t k = s->offset + i;
            chunk[i] = k < cells ? g->om[k] : g->tm[k - cells];
        }
        if (hal_storage_write(s->slot, sizeof(mapstore_header_t) + s->offset, chunk, n) != HAL_OK) {
            abandon(s);
            return false;
        }
        s->crc = mapstore_crc32(s->crc, chunk, n);
        s->offset += n;
        return true;
    }
    /* All data is down: the header makes the record good, then the commit makes it last. */
    s->hdr.data_crc = s->crc;
    s->hdr.header_crc = header_crc(&s->hdr);
    if (hal_storage_write(s->slot, 0u, &s->hdr, sizeof s->hdr) != HAL_OK ||
        hal_storage_commit(s->slot) != HAL_OK) {
        abandon(s);
        return false;
    }
    s->last_seq = s->hdr.seq;
    s->last_slot = s->slot;
    s->saves++;
    s->active = false;
    return false;
}

/* Whether a slot's data matches the CRC in its header. */
static bool data_good(uint8_t slot, const mapstore_header_t *h)
{
    if (h->a > SLAM_GRID_A || h->b > SLAM_GRID_B) {
        return false; /* no run of this build wrote it; and A·B could pass 32 bits */
    }
    uint32_t crc = 0u;
    const uint32_t bytes = data_bytes(h->a, h->b);
    for (uint32_t off = 0; off < bytes; off += MAPSTORE_CHUNK) {
        uint8_t chunk[MAPSTORE_CHUNK];
        uint32_t n = bytes - off > MAPSTORE_CHUNK ? MAPSTORE_CHUNK : bytes - off;
        if (hal_storage_read(slot, sizeof(mapstore_header_t) + off, chunk, n) != HAL_OK) {
            return false;
        }
        crc = mapstore_crc32(crc, chunk, n);
    }
    return crc == h->data_crc;
}

int mapstore_load(grid_t *g, odom_pose_t *pose)
{
    /* The newest record whose data is intact wins; an older good one is the fallback. */
    mapstore_header_t h[HAL_STORAGE_SLOTS];
    bool ok[HAL_STORAGE_SLOTS];
    for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
        ok[slot] = mapstore_read_header(slot, &h[slot]) == SLAM_OK;
    }
    int wrong_size = 0;
    for (uint8_t tries = 0; tries < HAL_STORAGE_SLOTS; tries++) {
        int best = -1;
        for (uint8_t slot = 0; slot < HAL_STORAGE_SLOTS; slot++) {
            if (ok[slot] && (best < 0 || h[slot].seq > h[best].seq)) {
                best = slot;
            }
        }
        if (best < 0) {
            break;
        }
        ok[best] = false;
        const mapstore_header_t *b = &h[best];
        /* Another size is another run's map (grid_a, grid_b): read into this grid, its rows
         * would fall apart. */
        if (b->a != g->a_cells || b->b != g->b_cells) {
            wrong_size = 1;
            continue;
        }
        const uint32_t cells = grid_cells(g);
        if (!data_good((uint8_t)best, b) ||
            hal_storage_read((uint8_t)best, sizeof(mapstore_header_t), g->om, cells) != HAL_OK ||
            hal_storage_read((uint8_t)best, sizeof(mapstore_header_t) + cells, g->tm, cells) !=
                HAL_OK) {
            continue;
        }
        g->cell_um = b->cell_um;
        grid_set_spans(g);
        g->origin_x_um = b->origin_x_um;
        g->origin_y_um = b->origin_y_um;
        if (pose != NULL) {
            *pose = (odom_pose_t){b->pose_x_um, b->pose_y_um, b->pose_heading};
        }
        return SLAM_OK;
    }
    return wrong_size ? SLAM_EINVAL : SLAM_EIO;
}
