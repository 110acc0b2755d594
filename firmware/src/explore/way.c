/* SPDX-License-Identifier: MIT */
/* Walls mode: the way to the nearest frontier the robot can reach, when none is in sight.
 * The tick asks (explore_way_ask()) and reads the answer (explore_way_answer()); the
 * background loop works it out a slice a call (explore_way_work()). */
#include "way.h"

#include <string.h>

#define EXPLORE_WAY_CELL_UM 250000u  /* a way cell's side, about: wider than the body */
#define EXPLORE_WAY_READS 6000u      /* grid cells one call reads, about (a row, a sight) */
#define EXPLORE_WAY_NEAR 1u          /* a frontier this near (way cells) was looked at */
#define EXPLORE_WAY_STRIKES 2u       /* times put off before it is given up */
#define EXPLORE_WAY_OFF_TICKS 12000u /* a frontier put off is left alone two minutes */

/* The background loop's phases. */
enum { WAY_IDLE = 0u, WAY_GROW, WAY_BACK };

/* What a way cell is, from its grid cells. */
typedef enum { WAY_PASSABLE, WAY_BLOCKED, WAY_UNKNOWN } way_class_t;

void explore_way_init(explore_way_t *w, const explore_cfg_t *cfg)
{
    memset(w, 0, sizeof *w);
    uint32_t k = (EXPLORE_WAY_CELL_UM + cfg->cell_um / 2u) / cfg->cell_um;
    uint32_t ka = (cfg->grid_a + EXPLORE_WAY_A - 1u) / EXPLORE_WAY_A;
    uint32_t kb = (cfg->grid_b + EXPLORE_WAY_B - 1u) / EXPLORE_WAY_B;
    k = k > ka ? k : ka;
    k = k > kb ? k : kb;
    k = k < 1u ? 1u : k;
    w->k = (uint8_t)(k > UINT8_MAX ? UINT8_MAX : k);
    w->na = (uint16_t)((cfg->grid_a + w->k - 1u) / w->k);
    w->nb = (uint16_t)((cfg->grid_b + w->k - 1u) / w->k);
}

/* ---- the tick's side ------------------------------------------------------------------ */

void explore_way_ask(explore_way_t *w, const odom_pose_t *pose, uint32_t now)
{
    w->ask_x_um = pose->x_um;
    w->ask_y_um = pose->y_um;
    w->ask_now = now;
    w->asked++;
}

bool explore_way_answer(const explore_way_t *w, explore_way_result_t *result, int32_t *x_um,
                        int32_t *y_um)
{
    if (w->answered != w->asked) {
        return false;
    }
    *result = (explore_way_result_t)w->result;
    *x_um = w->x_um;
    *y_um = w->y_um;
    return true;
}

/* ---- bit planes ----------------------------------------------------------------------- */

/* A way cell's label: its distance mod 3, plus 1; 0 when the search has not reached it. */
static uint32_t label(const explore_way_t *w, uint32_t a, uint32_t b)
{
    return (explore_bit(w->label[0][b], a) ? 1u : 0u) | (explore_bit(w->label[1][b], a) ? 2u : 0u);
}

static void set_label(explore_way_t *w, uint32_t a, uint32_t b, uint32_t v)
{
    explore_put_bit(w->label[0][b], a, (v & 1u) != 0u);
    explore_put_bit(w->label[1][b], a, (v & 2u) != 0u);
}

static uint32_t label_of_distance(uint32_t d)
{
    return d % 3u + 1u;
}

/* Byte j of row b's cells labelled v (1..3). */
static uint8_t labelled(const explore_way_t *w, uint32_t b, uint32_t j, uint32_t v)
{
    uint8_t p0 = w->label[0][b][j];
    uint8_t p1 = w->label[1][b][j];
    uint8_t m0 = (v & 1u) != 0u ? p0 : (uint8_t)~p0;
    uint8_t m1 = (v & 2u) != 0u ? p1 : (uint8_t)~p1;
    return (uint8_t)(m0 & m1);
}

/* ---- way cells ------------------------------------------------------------------------ */

/*
 * From the grid cells it covers: blocked when occupied cells span it (in all rows but one,
 * or all columns but one: a wall across it, though a few of the wall's cells are unknown;
 * a wall's end or a stray echo does not block it); unknown when the robot has not been in
 * it and three quarters of its cells are unknown; else passable. Beyond the grid: blocked.
 */
static way_class_t classify(const explore_way_t *w, const grid_t *g, uint32_t ca, uint32_t cb)
{
    const uint32_t k = w->k;
    uint32_t rows = 0u;
    uint32_t cols = 0u;
    uint32_t unknown = 0u;
    bool been = false;
    uint32_t span = k > 1u ? k - 1u : 1u;
    for (uint32_t j = 0; j < k; j++) {
        uint32_t b = cb * k + j;
        bool row_hit = false;
        for (uint32_t i = 0; i < k; i++) {
            uint32_t a = ca * k + i;
            if (a >= g->a_cells || b >= g->b_cells) {
                return WAY_BLOCKED;
            }
            uint32_t idx = b * g->a_cells + a;
            grid_state_t st = grid_state(g, idx);
            if (st == GRID_OCCUPIED) {
                row_hit = true;
                cols |= 1u << (i & 31u);
            }
            unknown += st == GRID_UNKNOWN ? 1u : 0u;
            been = been || g->tm[idx] != 0u;
        }
        rows += row_hit ? 1u : 0u;
    }
    uint32_t ncols = 0u;
    for (; cols != 0u; cols &= cols - 1u) {
        ncols++;
    }
    if (rows >= span || ncols >= span) {
        return WAY_BLOCKED;
    }
    return !been && 4u * unknown >= 3u * k * k ? WAY_UNKNOWN : WAY_PASSABLE;
}

/* A way cell's centre, in µm of the world. */
static void centre(const explore_way_t *w, const grid_t *g, uint32_t cell, int32_t *x, int32_t *y)
{
    uint32_t side = (uint32_t)w->k * g->cell_um;
    *x = g->origin_x_um + (int32_t)((cell % w->na) * side + side / 2u);
    *y = g->origin_y_um + (int32_t)((cell / w->na) * side + side / 2u);
}

/* ---- the frontiers given up and put off ------------------------------------------------ */

static bool dead(const explore_way_t *w, uint32_t cell)
{
    return explore_bit(w->dead[cell / w->na], cell % w->na);
}

static void give_up(explore_way_t *w, uint32_t cell)
{
    explore_put_bit(w->dead[cell / w->na], cell % w->na, true);
}

/* The slot of a frontier put off, or EXPLORE_WAY_SLOTS. */
static uint32_t put_off_slot(const explore_way_t *w, uint32_t cell)
{
    for (uint32_t i = 0; i < EXPLORE_WAY_SLOTS; i++) {
        if (w->off[i] == cell + 1u) {
            return i;
        }
    }
    return EXPLORE_WAY_SLOTS;
}

/* Answered twice in a row: put off for a while, and given up after EXPLORE_WAY_STRIKES
 * times. */
static void strike(explore_way_t *w, uint32_t cell)
{
    uint32_t i = put_off_slot(w, cell);
    if (i == EXPLORE_WAY_SLOTS) {
        i = w->off_next;
        w->off_next = (uint8_t)((w->off_next + 1u) % EXPLORE_WAY_SLOTS);
        w->off[i] = cell + 1u;
        w->off_n[i] = 0u;
    }
    w->off_at[i] = w->ask_now;
    if (++w->off_n[i] >= EXPLORE_WAY_STRIKES) {
        give_up(w, cell);
        w->off[i] = 0u;
    }
    w->last = UINT32_MAX;
}

/*
 * A cell of the last wave beside an unknown one: the nearest frontier, unless it is given
 * up, was looked at from where the robot stands (given up now), is put off, or is the one
 * answered last (struck: the robot went its way and did not resolve it, whether it did
 * not get there or it lay further on). True when it is the one.
 */
static bool frontier(explore_way_t *w, uint32_t cell)
{
    if (dead(w, cell)) {
        return false;
    }
    if (w->wave <= EXPLORE_WAY_NEAR) {
        give_up(w, cell);
        return false;
    }
    uint32_t i = put_off_slot(w, cell);
    if (i != EXPLORE_WAY_SLOTS && w->ask_now - w->off_at[i] < EXPLORE_WAY_OFF_TICKS) {
        w->put_off = true;
        return false;
    }
    if (cell == w->last) {
        strike(w, cell);
        w->put_off = w->put_off || !dead(w, cell);
        return false;
    }
    w->at = cell;
    w->at_d = w->wave;
    w->last = cell;
    return true;
}

/* ---- the search ----------------------------------------------------------------------- */

static void answer(explore_way_t *w, explore_way_result_t result, int32_t x_um, int32_t y_um)
{
    w->x_um = x_um;
    w->y_um = y_um;
    w->result = (uint8_t)result;
    w->answered = w->serving; /* last: the tick reads the answer once it sees this */
    w->phase = WAY_IDLE;
}

/* Begin a request: the robot's way cell, at distance 0. */
static void begin(explore_way_t *w, const grid_t *g)
{
    w->serving = w->asked;
    grid_cell_t c;
    if (grid_cell_of(g, w->ask_x_um, w->ask_y_um, &c) != 0) {
        answer(w, EXPLORE_WAY_PUT_OFF, 0, 0); /* off the grid: nothing to tell */
        return;
    }
    memset(w->label, 0, sizeof w->label);
    uint32_t a = (uint32_t)c.a / w->k;
    uint32_t b = (uint32_t)c.b / w->k;
    set_label(w, a, b, label_of_distance(0u));
    w->wave = 0u;
    w->lo = w->hi = (uint16_t)b;
    w->row = (uint16_t)(b > 0u ? b - 1u : 0u);
    w->next_lo = UINT16_MAX;
    w->next_hi = 0u;
    w->put_off = false;
    w->phase = WAY_GROW;
}

/*
 * One row of a wave: the cells beside the wave's own (labelled with its distance) that the
 * search has not reached are classified; the passable ones join the next wave, and an
 * unknown one makes its neighbours of this wave frontiers. Returns the grid cells read.
 */
static uint32_t grow_row(explore_way_t *w, const grid_t *g, uint32_t b)
{
    const uint32_t bytes = (w->na + 7u) / 8u;
    const uint32_t v = label_of_distance(w->wave);
    const uint32_t nv = label_of_distance(w->wave + 1u);
    uint32_t reads = bytes;
    uint8_t prev = 0u;
    uint8_t here = labelled(w, b, 0u, v);
    for (uint32_t j = 0; j < bytes; j++) {
        uint8_t next = j + 1u < bytes ? labelled(w, b, j + 1u, v) : 0u;
        uint8_t near = (uint8_t)((here << 1) | (prev >> 7) | (here >> 1) | (next << 7));
        if (b > 0u) {
            near |= labelled(w, b - 1u, j, v);
        }
        if (b + 1u < w->nb) {
            near |= labelled(w, b + 1u, j, v);
        }
        uint8_t fresh = (uint8_t)(near & ~(w->label[0][b][j] | w->label[1][b][j]));
        for (; fresh != 0u; fresh &= (uint8_t)(fresh - 1u)) {
            uint32_t a = j * 8u + (uint32_t)__builtin_ctz(fresh);
            if (a >= w->na) {
                break;
            }
            reads += (uint32_t)w->k * w->k;
            way_class_t c = classify(w, g, a, b);
            if (c == WAY_PASSABLE) {
                set_label(w, a, b, nv);
                w->next_lo = (uint16_t)(b < w->next_lo ? b : w->next_lo);
                w->next_hi = (uint16_t)(b > w->next_hi ? b : w->next_hi);
            } else if (c == WAY_UNKNOWN) {
                uint32_t cell = b * w->na + a;
                if ((a > 0u && label(w, a - 1u, b) == v && frontier(w, cell - 1u)) ||
                    (a + 1u < w->na && label(w, a + 1u, b) == v && frontier(w, cell + 1u)) ||
                    (b > 0u && label(w, a, b - 1u) == v && frontier(w, cell - w->na)) ||
                    (b + 1u < w->nb && label(w, a, b + 1u) == v && frontier(w, cell + w->na))) {
                    w->phase = WAY_BACK;
                    return reads;
                }
            }
        }
        prev = here;
        here = next;
    }
    return reads;
}

/* Rows of waves until the read budget is spent, a frontier found, or none is left. */
static void grow(explore_way_t *w, const grid_t *g)
{
    uint32_t reads = 0u;
    while (reads < EXPLORE_WAY_READS) {
        uint32_t last = w->hi + 1u < w->nb ? w->hi + 1u : w->hi;
        if (w->row > last) {
            if (w->next_lo > w->next_hi) { /* the wave reached no cell */
                answer(w, w->put_off ? EXPLORE_WAY_PUT_OFF : EXPLORE_WAY_NONE, 0, 0);
                return;
            }
            w->wave++;
            w->lo = w->next_lo;
            w->hi = w->next_hi;
            w->row = (uint16_t)(w->lo > 0u ? w->lo - 1u : 0u);
            w->next_lo = UINT16_MAX;
            w->next_hi = 0u;
            continue;
        }
        reads += grow_row(w, g, w->row);
        if (w->phase != WAY_GROW) {
            return;
        }
        w->row++;
    }
}

/* Whether the robot sees a point: no occupied cell on the straight line to it. */
static bool in_sight(const explore_way_t *w, const grid_t *g, int32_t x_um, int32_t y_um,
                     uint32_t *reads)
{
    grid_cell_t from;
    grid_cell_t to;
    if (grid_cell_of(g, w->ask_x_um, w->ask_y_um, &from) != 0 ||
        grid_cell_of(g, x_um, y_um, &to) != 0) {
        return false;
    }
    explore_ray_t r = explore_ray_between(from.a, from.b, to.a, to.b);
    *reads += r.left;
    while (r.left-- > 0u) {
        uint32_t k = explore_ray_next(&r, g->a_cells, g->b_cells);
        if (k == EXPLORE_NO_CELL || grid_state(g, k) == GRID_OCCUPIED) {
            return false;
        }
    }
    return true;
}

/* Back along the way from the frontier: the first of its cells the robot sees, going to
 * the robot, is where it goes; two cells on at the nearest, so that it is never reached
 * where the robot stands. */
static void back(explore_way_t *w, const grid_t *g)
{
    uint32_t reads = 0u;
    while (reads < EXPLORE_WAY_READS) {
        int32_t x;
        int32_t y;
        centre(w, g, w->at, &x, &y);
        if (w->at_d <= 2u || in_sight(w, g, x, y, &reads)) {
            answer(w, EXPLORE_WAY_TO, x, y);
            return;
        }
        uint32_t a = w->at % w->na;
        uint32_t b = w->at / w->na;
        uint32_t v = label_of_distance(w->at_d - 1u);
        if (a > 0u && label(w, a - 1u, b) == v) {
            w->at -= 1u;
        } else if (a + 1u < w->na && label(w, a + 1u, b) == v) {
            w->at += 1u;
        } else if (b > 0u && label(w, a, b - 1u) == v) {
            w->at -= w->na;
        } else if (b + 1u < w->nb && label(w, a, b + 1u) == v) {
            w->at += w->na;
        } else {
            /* The map changed under the search: no way back. Ask again. */
            answer(w, EXPLORE_WAY_PUT_OFF, 0, 0);
            return;
        }
        w->at_d--;
    }
}

void explore_way_work(explore_way_t *w, const grid_t *g)
{
    if (w->k == 0u) {
        return; /* not the walls mode */
    }
    if (w->phase != WAY_IDLE && w->serving != w->asked) {
        w->phase = WAY_IDLE; /* the tick asked afresh: the old request is dropped */
    }
    switch (w->phase) {
    case WAY_IDLE:
        if (w->answered != w->asked) {
            begin(w, g);
        }
        break;
    case WAY_GROW:
        grow(w, g);
        break;
    case WAY_BACK:
        back(w, g);
        break;
    default:
        w->phase = WAY_IDLE;
        break;
    }
}
