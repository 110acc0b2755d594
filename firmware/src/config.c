/* SPDX-License-Identifier: MIT */
/* The paper's default configuration and the range check of every field. */
#include "slam/config.h"

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "slam/config_fields.h"
#include "slam/error.h"
#include "slam/grid.h"

/* Static storage: the padding bytes are zero too, so equal configurations compare equal
 * byte for byte. */
static const slam_config_t slam_config_defaults = {
#define CFG_DEFAULT(name, type, dflt, lo, hi, rule, id, live, words) .name = dflt,
    SLAM_CONFIG_FIELDS(CFG_DEFAULT)
#undef CFG_DEFAULT
};

void slam_config_default(slam_config_t *cfg)
{
    memcpy(cfg, &slam_config_defaults, sizeof *cfg);
}

void slam_config_paper(slam_config_t *cfg)
{
    cfg->om_mode = OM_MODE_COUNT;
    cfg->localize = 0u;
    cfg->post_threshold = 3u;
    cfg->post_template_k = 1u;
    cfg->post_insert = 1u;
    cfg->sweep_first_mdeg = 65000;
    cfg->sweep_last_mdeg = 155000;
    cfg->sweep_stops = 6u;
}

/* How a field is stored (two bits); a Q1.30 factor is an int32_t. */
enum { CFG_U8, CFG_U16, CFG_U32, CFG_I32, CFG_Q30 = CFG_I32 };

/* What a field must hold besides its range: each names the fields it is compared with. */
enum {
    RULE_NONE,
    RULE_CELL,            /* cell_um · the longer grid side stays within 1 km */
    RULE_ABOVE_MIN,       /* confidence_radius_um > range_min_um */
    RULE_STOPS,           /* one stop only where sweep_first_mdeg == sweep_last_mdeg */
    RULE_PULSES,          /* servo_pulse_180deg_us != servo_pulse_0deg_us */
    RULE_THRESHOLD,       /* post_threshold below OMmax (counting) or the evidence limit */
    RULE_TOP_SPEED,       /* no faster than top_speed_mm_s */
    RULE_ABOVE_CLEARANCE, /* follow_um > clearance_um */
    RULE_CORRIDOR,        /* clearance_um · the corridor ahead fits SLAM_CORRIDOR_CELLS_MAX */
    RULE_GRID,            /* grid_a, grid_b: 0 (the capacity) or at least 3 cells */
    RULE_IN_GRID_A,       /* start_cell_a below the grid's A (grid_a, or the capacity) */
    RULE_IN_GRID_B        /* start_cell_b below the grid's B */
};
_Static_assert(RULE_IN_GRID_B < 64, "a rule fits the six bits above a field's storage");

/* What a row of config_fields.h must agree with: its member exists and has the row's type
 * (a compile error names the member otherwise), rows follow the members' order (so the
 * check and the text configuration go through the struct in order), no two rows share an
 * id, and the default lies within the range. A struct built from the rows must be
 * slam_config_t's size: a member without a row shows, unless it fits into padding
 * (tests/sim/test_tools_telemetry.py matches members and rows by name). */
#define CFG_CTYPE_U8 uint8_t
#define CFG_CTYPE_U16 uint16_t
#define CFG_CTYPE_U32 uint32_t
#define CFG_CTYPE_I32 int32_t
#define CFG_CTYPE_Q30 q1_30_t
/* clang-format off */
#define CFG_MEMBER_TYPE(name)                                                                      \
    _Generic(((const slam_config_t *)NULL)->name, uint8_t: CFG_U8, uint16_t: CFG_U16,             \
             uint32_t: CFG_U32, int32_t: CFG_I32, default: -1)
/* clang-format on */
#define CFG_SIGNED_I32 1
#define CFG_SIGNED_Q30 1
#define CFG_SIGNED_U8 0
#define CFG_SIGNED_U16 0
#define CFG_SIGNED_U32 0
#define CFG_ROW_ASSERTS(name, type, dflt, lo, hi, rule, id, live, words)                           \
    _Static_assert(CFG_MEMBER_TYPE(name) == CFG_##type,                                            \
                   #name ": the row's type is not the member's");                                  \
    _Static_assert(offsetof(slam_config_t, name) == offsetof(struct cfg_rows, name),               \
                   #name ": rows follow the order of slam_config_t's members");                    \
    _Static_assert((id) >= 1 && (id) <= 255, #name ": a telemetry key is 1..255");                 \
    _Static_assert(CFG_SIGNED_##type                                                               \
                       ? (int64_t)(lo) <= (int64_t)(dflt) && (int64_t)(dflt) <= (int64_t)(hi)      \
                       : (uint64_t)(lo) <= (uint64_t)(dflt) && (uint64_t)(dflt) <= (uint64_t)(hi), \
                   #name ": the default lies within lo..hi");
#define CFG_ROW_MEMBER(name, type, dflt, lo, hi, rule, id, live, words) CFG_CTYPE_##type name;
struct cfg_rows {
    SLAM_CONFIG_FIELDS(CFG_ROW_MEMBER)
};
_Static_assert(sizeof(struct cfg_rows) == sizeof(slam_config_t),
               "every member of slam_config_t has a row in config_fields.h");
SLAM_CONFIG_FIELDS(CFG_ROW_ASSERTS)
/* Two rows with one id: "redeclaration of enumerator 'CFG_KEY_TAKEN_<id>'". */
#define CFG_KEY_TAKEN(name, type, dflt, lo, hi, rule, id, live, words) CFG_KEY_TAKEN_##id,
enum { SLAM_CONFIG_FIELDS(CFG_KEY_TAKEN) };
#undef CFG_KEY_TAKEN
#undef CFG_ROW_MEMBER
#undef CFG_ROW_ASSERTS

_Static_assert(sizeof(slam_config_t) <= 255u, "field offsets are bytes");

#define CFG_GRID_SIDE (SLAM_GRID_A > SLAM_GRID_B ? SLAM_GRID_A : SLAM_GRID_B)
/* The table as parallel arrays: the names one after another, each ended by its NUL, and a
 * field's storage and rule in one byte (no padding and no pointers in flash). A signed
 * field's bounds are its int32_t values' bits. */
#define CFG_LO(name, type, dflt, lo, hi, rule, id, live, words) (uint32_t)(lo),
#define CFG_HI(name, type, dflt, lo, hi, rule, id, live, words) (uint32_t)(hi),
#define CFG_OFFSET(name, type, dflt, lo, hi, rule, id, live, words)                                \
    (uint8_t) offsetof(slam_config_t, name),
#define CFG_KIND(name, type, dflt, lo, hi, rule, id, live, words)                                  \
    (uint8_t)(CFG_##type | RULE_##rule << 2),
#define CFG_NAME(name, type, dflt, lo, hi, rule, id, live, words) #name "\0"
static const uint32_t cfg_lo[] = {SLAM_CONFIG_FIELDS(CFG_LO)};
static const uint32_t cfg_hi[] = {SLAM_CONFIG_FIELDS(CFG_HI)};
static const uint8_t cfg_offset[] = {SLAM_CONFIG_FIELDS(CFG_OFFSET)};
static const uint8_t cfg_kind[] = {SLAM_CONFIG_FIELDS(CFG_KIND)};
static const char cfg_names[] = SLAM_CONFIG_FIELDS(CFG_NAME);

uint32_t slam_config_field_get(const slam_config_t *cfg, unsigned row)
{
    const uint8_t *field = (const uint8_t *)cfg + cfg_offset[row];
    unsigned type = cfg_kind[row] & 3u;
    if (type == CFG_U8) {
        return *field;
    }
    if (type == CFG_U16) {
        uint16_t v;
        memcpy(&v, field, sizeof v);
        return v;
    }
    uint32_t v;
    memcpy(&v, field, sizeof v); /* an int32_t's bits are its two's complement */
    return v;
}

bool slam_config_field_set(slam_config_t *cfg, unsigned row, uint32_t value)
{
    uint8_t *field = (uint8_t *)cfg + cfg_offset[row];
    unsigned type = cfg_kind[row] & 3u;
    if (type == CFG_U8) {
        if (value > UINT8_MAX) {
            return false;
        }
        *field = (uint8_t)value;
    } else if (type == CFG_U16) {
        if (value > UINT16_MAX) {
            return false;
        }
        uint16_t v = (uint16_t)value;
        memcpy(field, &v, sizeof v);
    } else {
        memcpy(field, &value, sizeof value);
    }
    return true;
}

static bool rule_holds(const slam_config_t *c, unsigned rule, uint32_t v)
{
    switch (rule) {
    case RULE_CELL:
        return v <= (uint32_t)SLAM_CONFIG_WORLD_LIMIT_UM / CFG_GRID_SIDE;
    case RULE_ABOVE_MIN:
        return v > c->range_min_um;
    case RULE_STOPS:
        return v != 1u || c->sweep_first_mdeg == c->sweep_last_mdeg;
    case RULE_PULSES:
        return v != c->servo_pulse_0deg_us;
    case RULE_THRESHOLD:
        return v < (c->om_mode == OM_MODE_COUNT ? c->om_max : GRID_EVIDENCE_MAX);
    case RULE_TOP_SPEED:
        return v <= c->top_speed_mm_s;
    case RULE_ABOVE_CLEARANCE:
        return v > c->clearance_um;
    case RULE_CORRIDOR:
        return slam_corridor_rows(c->cell_um) * slam_corridor_columns(c->cell_um, v) <=
               SLAM_CORRIDOR_CELLS_MAX;
    case RULE_GRID:
        /* Below 3 a grid has no inside cell: the pose correction's wall search needs one. */
        return v == 0u || v >= 3u;
    case RULE_IN_GRID_A:
        return v < grid_cells_a(c);
    case RULE_IN_GRID_B:
        return v < grid_cells_b(c);
    default:
        return true;
    }
}

static const char *first_bad_field(const slam_config_t *c)
{
    const char *name = cfg_names;
    for (size_t i = 0; i < sizeof cfg_lo / sizeof cfg_lo[0]; i++) {
        uint32_t v = slam_config_field_get(c, (unsigned)i);
        bool in_range = (cfg_kind[i] & 3u) == CFG_I32
                            ? (int32_t)v >= (int32_t)cfg_lo[i] && (int32_t)v <= (int32_t)cfg_hi[i]
                            : v >= cfg_lo[i] && v <= cfg_hi[i];
        if (!in_range || !rule_holds(c, cfg_kind[i] >> 2, v)) {
            return name;
        }
        while (*name++ != '\0') {
            /* past this name and its NUL */
        }
    }
    return NULL;
}

int slam_config_check(const slam_config_t *cfg, const char **field)
{
    const char *bad = first_bad_field(cfg);
    if (field != NULL) {
        *field = bad;
    }
    return bad == NULL ? SLAM_OK : SLAM_EINVAL;
}
