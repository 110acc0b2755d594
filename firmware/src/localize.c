/* SPDX-License-Identifier: MIT */
/* Pose correction, the background loop's side: held-back hits matched against OM by an
 * iterated sequential Kalman update (loc_tick.c holds the tick's side). */
#include "slam/localize.h"

#include <stddef.h>

#include "loc_internal.h"
#include "loc_kf.h"
#include "slam/error.h"
#include "slam/sonar.h"

/* The covariance's units: µm and µrad. 2π·10⁶ µrad is 2^32 binary angle units. */
#define LOC_BAM_PER_URAD_Q16 44797728 /* 683.565 bam per µrad, Q16 */
#define LOC_KAPPA_MAX 20000000         /* ±20 µrad/mm (1.1° a metre), ±2 % of a turn */
#define LOC_URAD_PER_BAM_Q26 98175    /* 0.00146292 µrad per bam, Q26 */

/* A hit's distance from its wall: σ 30 mm, and a Cauchy weight of scale 50 mm against
 * the walls it only seems to touch. µm² and µm. */
#ifndef LOC_SIGMA2_UM2
#define LOC_SIGMA2_UM2 900000000LL
#endif
#ifndef LOC_HUBER_UM
#define LOC_HUBER_UM 50000LL
#endif

/* A hit's lever about the robot, in dh/dθ units (Q12 µm per µrad): at most 8 m, which
 * keeps lkf_update()'s products within 64 bits. Held-back hits lie farther when the robot
 * drove that far between echoes (in a large open space) or when a log's odometry jumps;
 * they are not matched. */
#define LOC_LEVER_MAX 32768

/* A 5×5 block says where a wall runs. */
#ifndef LOC_NORMAL_HALF
#define LOC_NORMAL_HALF 2
#endif
#ifndef LOC_NORMAL_MIN_CELLS
#define LOC_NORMAL_MIN_CELLS 4
#endif
#ifndef LOC_LINEAR_PERCENT
#define LOC_LINEAR_PERCENT 35 /* smaller eigenvalue at most this share of the larger: walls
                                 a few cells thick still count; corners and blobs do not */
#endif

static loc_corr_t corr_of(int32_t tx_um, int32_t ty_um, bam32_t th)
{
    return (loc_corr_t){tx_um, ty_um, th, fix_cos(th), fix_sin(th)};
}

/* A point through a correction. Positions stay far inside ±2^31 µm (slam_config_check
 * keeps the world within 1 km), so the 32 × 30-bit products fit. */
static void apply_xy(const loc_corr_t *c, int32_t x, int32_t y, int32_t *ox, int32_t *oy)
{
    *ox = fix_sat_i32(fix_round_shift((int64_t)x * c->c - (int64_t)y * c->s, 30u) + c->tx_um);
    *oy = fix_sat_i32(fix_round_shift((int64_t)x * c->s + (int64_t)y * c->c, 30u) + c->ty_um);
}

odom_pose_t loc_apply(const loc_corr_t *c, const odom_pose_t *odom)
{
    odom_pose_t p;
    apply_xy(c, odom->x_um, odom->y_um, &p.x_um, &p.y_um);
    p.heading = odom->heading + c->th;
    return p;
}

/* ---- the filter --------------------------------------------------------------------------- */

static bam32_t bam_of_urad(int64_t urad)
{
    return (bam32_t)(uint32_t)(int32_t)((urad * LOC_BAM_PER_URAD_Q16) >> 16);
}

/* A map point moved by an increment about a centre: turned by c, s, then shifted. */
static void move_point(int32_t x, int32_t y, int32_t cx, int32_t cy, int64_t dx, int64_t dy,
                       q1_30_t c, q1_30_t s, int32_t *ox, int32_t *oy)
{
    int64_t rx = (int64_t)x - cx;
    int64_t ry = (int64_t)y - cy;
    *ox = fix_sat_i32(cx + fix_round_shift(rx * c - ry * s, 30u) + dx);
    *oy = fix_sat_i32(cy + fix_round_shift(rx * s + ry * c, 30u) + dy);
}

/* The correction turned by dth about a map point, then shifted: the robot standing there
 * keeps its place and changes its heading. */
static void correct_about(loc_t *l, int32_t cx, int32_t cy, bam32_t dth, int64_t dx, int64_t dy)
{
    int32_t tx;
    int32_t ty;
    move_point(l->corr.tx_um, l->corr.ty_um, cx, cy, dx, dy, fix_cos(dth), fix_sin(dth), &tx, &ty);
    l->corr = corr_of(tx, ty, l->corr.th + dth);
}

/* A move between two readings: the covariance grows, and the correction turns by the drift
 * learned so far, about where the robot now is. */
static void propagate(loc_t *l, const odom_pose_t *odom)
{
    if (!l->have_last) {
        l->have_last = true;
        l->last_odom = *odom;
        return;
    }
    int32_t dxo = (int32_t)((uint32_t)odom->x_um - (uint32_t)l->last_odom.x_um);
    int32_t dyo = (int32_t)((uint32_t)odom->y_um - (uint32_t)l->last_odom.y_um);
    int32_t turned = fix_bam_diff(odom->heading, l->last_odom.heading);
    /* Driven: the move along the heading it began with (backwards is negative). */
    int64_t ds_um = fix_round_shift((int64_t)dxo * fix_cos(l->last_odom.heading) +
                                        (int64_t)dyo * fix_sin(l->last_odom.heading),
                                    30u);
    l->last_odom = *odom;
    /* The move in the map frame is odometry's turned by the correction. */
    int64_t dx = fix_round_shift((int64_t)dxo * l->corr.c - (int64_t)dyo * l->corr.s, 30u);
    int64_t dy = fix_round_shift((int64_t)dxo * l->corr.s + (int64_t)dyo * l->corr.c, 30u);
    int64_t turn_urad = ((int64_t)turned * LOC_URAD_PER_BAM_Q26) >> 26;
    lkf_predict(&l->cov, fix_div_s64(dx, 1000), fix_div_s64(dy, 1000), fix_div_s64(ds_um, 1000),
                turn_urad);
    /* The learned drift, whole µrad at a time (the rest waits for the next move). */
    lkf_state_t k = {{0, 0, 0, l->kappa_prad_per_mm, l->kappa_ppb}};
    l->drift_nrad += lkf_drift_nrad(&k, ds_um, turn_urad);
    int64_t urad = fix_div_s64(l->drift_nrad, 1000);
    if (urad != 0) {
        l->drift_nrad -= urad * 1000;
        odom_pose_t at = loc_apply(&l->corr, odom);
        correct_about(l, at.x_um, at.y_um, bam_of_urad(urad), 0, 0);
    }
}
/* ---- walls in OM ------------------------------------------------------------------------- */

/* Whether OM holds the cell of (x, y) free by more than one beam's pass: a wall that one
 * beam grazed past is not yet free. Off the grid counts as free: nothing is mapped there.
 * On the grid, *cell is the cell's index. */
static bool known_free(const grid_t *g, int32_t x, int32_t y, uint32_t *cell)
{
    grid_cell_t k;
    if (grid_cell_of(g, x, y, &k) != SLAM_OK) {
        return true;
    }
    uint32_t i = grid_index(k);
    *cell = i;
    return g->mode == OM_MODE_EVIDENCE ? (uint32_t)g->om[i] + g->miss < GRID_EVIDENCE_ZERO
                                       : grid_state(g, i) == GRID_FREE;
}

static bool occupied(const grid_t *g, int32_t a, int32_t b)
{
    return (uint32_t)a < SLAM_GRID_A && (uint32_t)b < SLAM_GRID_B &&
           grid_state(g, (uint32_t)b * SLAM_GRID_A + (uint32_t)a) == GRID_OCCUPIED;
}

/* The normal of the wall through cell (a, b), Q12, from the occupied cells of the 5×5
 * block around it: the direction of least spread, when the cells lie along a line. */
static bool wall_normal(const grid_t *g, int32_t a, int32_t b, int32_t *nx, int32_t *ny)
{
    int32_t n = 0;
    int32_t sx = 0;
    int32_t sy = 0;
    int32_t sxx = 0;
    int32_t syy = 0;
    int32_t sxy = 0;
    for (int32_t j = -LOC_NORMAL_HALF; j <= LOC_NORMAL_HALF; j++) {
        for (int32_t i = -LOC_NORMAL_HALF; i <= LOC_NORMAL_HALF; i++) {
            if (occupied(g, a + i, b + j)) {
                n++;
                sx += i;
                sy += j;
                sxx += i * i;
                syy += j * j;
                sxy += i * j;
            }
        }
    }
    if (n < LOC_NORMAL_MIN_CELLS) {
        return false;
    }
    /* n² times the covariance of the cells: small integers. */
    int64_t cxx = (int64_t)n * sxx - (int64_t)sx * sx;
    int64_t cyy = (int64_t)n * syy - (int64_t)sy * sy;
    int64_t cxy = (int64_t)n * sxy - (int64_t)sx * sy;
    int64_t diff = cxx - cyy;
    int64_t disc = lkf_isqrt((uint64_t)(diff * diff + 4 * cxy * cxy)); /* λ1 − λ2 */
    int64_t tr = cxx + cyy;                                           /* λ1 + λ2 */
    /* λ2 <= p·λ1: (tr − disc)·100 <= p·(tr + disc). */
    if (tr <= 0 || (tr - disc) * 100 > LOC_LINEAR_PERCENT * (tr + disc)) {
        return false;
    }
    /* The line's direction, the eigenvector of λ1 = (tr + disc) / 2: (2·cxy, disc − diff)
     * or, where that vanishes (a line along x), (disc + diff, 2·cxy). */
    int64_t vx = 2 * cxy;
    int64_t vy = disc - diff;
    if (vx == 0 && vy == 0) {
        vx = disc + diff;
        vy = 2 * cxy;
    }
    int64_t len = lkf_isqrt((uint64_t)(vx * vx + vy * vy));
    if (len == 0) {
        return false;
    }
    *nx = (int32_t)fix_div_s64(-vy * LKF_J_ONE, len);
    *ny = (int32_t)fix_div_s64(vx * LKF_J_ONE, len);
    return true;
}

/* The cells within LOC_ASSOC_CELLS (3) cells of a point's cell, nearest first, and among
 * equals in row order: the first occupied one is the nearest (Euclidean, in cells). */
static const int8_t loc_assoc_order[][2] = {
    {0, 0},   {0, -1},  {-1, 0}, {1, 0},  {0, 1},  {-1, -1}, {1, -1}, {-1, 1}, {1, 1},  {0, -2},
    {-2, 0},  {2, 0},   {0, 2},  {-1, -2}, {1, -2}, {-2, -1}, {2, -1}, {-2, 1}, {2, 1}, {-1, 2},
    {1, 2},   {-2, -2}, {2, -2}, {-2, 2}, {2, 2},  {0, -3},  {-3, 0}, {3, 0},  {0, 3},
};
_Static_assert(LOC_ASSOC_CELLS == 3, "loc_assoc_order holds the cells within 3");
_Static_assert(LOC_WINDOW <= LOC_HOLD && LOC_HOLD % 32u == 0u && LOC_HOLD <= UINT16_MAX,
               "win_shadowed holds a bit per held-back hit");

/* The wall a point lies on: the nearest occupied cell within LOC_ASSOC_CELLS cells, its
 * centre and normal. */
static bool wall_near(const grid_t *g, int32_t x_um, int32_t y_um, int32_t *wx, int32_t *wy,
                      int32_t *nx, int32_t *ny)
{
    grid_cell_t c;
    if (grid_cell_of(g, x_um, y_um, &c) != SLAM_OK) {
        return false;
    }
    size_t k = 0;
    const size_t n = sizeof loc_assoc_order / sizeof loc_assoc_order[0];
    while (k < n && !occupied(g, c.a + loc_assoc_order[k][0], c.b + loc_assoc_order[k][1])) {
        k++;
    }
    if (k == n) {
        return false;
    }
    int32_t ba = c.a + loc_assoc_order[k][0];
    int32_t bb = c.b + loc_assoc_order[k][1];
    if (!wall_normal(g, ba, bb, nx, ny)) {
        return false;
    }
    int32_t half = (int32_t)(g->cell_um / 2u);
    *wx = g->origin_x_um + ba * (int32_t)g->cell_um + half;
    *wy = g->origin_y_um + bb * (int32_t)g->cell_um + half;
    return true;
}

/* ---- the match --------------------------------------------------------------------------- */

/* Held-back hit i (0 the oldest) where correction c puts it in the map, µm. */
static void held_under(const loc_t *l, const grid_t *g, const loc_corr_t *c, unsigned i,
                       int32_t *x, int32_t *y)
{
    const loc_point_t *p = &l->win[(l->win_first + i) % LOC_HOLD];
    /* In the odometry frame, modulo 2^32 as grid.c's cells: the point came from an int32_t
     * within the reach. */
    unsigned k = l->point_shift;
    int32_t ox = (int32_t)((uint32_t)g->origin_x_um + ((uint32_t)(int32_t)p->x << k));
    int32_t oy = (int32_t)((uint32_t)g->origin_y_um + ((uint32_t)(int32_t)p->y << k));
    apply_xy(c, ox, oy, x, y);
}

/* Whether held-back hit i goes into OM at all: not when it lay just behind a wall. */
static bool held_mapped(const loc_t *l, unsigned i)
{
    unsigned slot = (l->win_first + i) % LOC_HOLD;
    return ((l->win_shadowed[slot / 32u] >> (slot % 32u)) & 1u) == 0u;
}

/* A point of the odometry frame as a loc_point_t, rounded to its unit; false when it lies
 * beyond a loc_point_t's reach (a grid's length and more off the grid). */
static bool to_point(const loc_t *l, const grid_t *g, int32_t x, int32_t y, loc_point_t *p)
{
    /* The differences modulo 2^32, as grid.c's: points and origin lie within 1 km. Halved
     * last, so that the rounding cannot overflow. */
    unsigned half = l->point_shift - 1u;
    int32_t u = (((int32_t)((uint32_t)x - (uint32_t)g->origin_x_um) >> half) + 1) >> 1;
    int32_t v = (((int32_t)((uint32_t)y - (uint32_t)g->origin_y_um) >> half) + 1) >> 1;
    if ((((uint32_t)u + 32768u) | ((uint32_t)v + 32768u)) > UINT16_MAX) {
        return false; /* one of them outside int16_t */
    }
    *p = (loc_point_t){(int16_t)u, (int16_t)v};
    return true;
}

/* Whether hit q, associated with wall cell w (normal n, Q12; h the hit's offset along it),
 * lies on a face of that wall never seen from the robot's side: the wall cell lies more than
 * a cell beyond the hit as the robot at c sees it, and the cell next to it on the hit's side
 * is not known free, as known_free() tells. The far face of a thin wall, first seen through
 * a door, is then not matched to the face mapped from the other room, a wall's thickness
 * away. */
static bool unseen_face(const grid_t *g, int32_t cx, int32_t cy, int32_t qx, int32_t qy,
                        int32_t wx, int32_t wy, const int32_t n[2], int64_t h)
{
    /* Differences modulo 2^32, as grid.c's: exact, since every position lies within the
     * 1 km world slam_config_check() allows; their products fit 64 bits. */
    int32_t ax = (int32_t)((uint32_t)wx - (uint32_t)qx);
    int32_t ay = (int32_t)((uint32_t)wy - (uint32_t)qy);
    int32_t bx = (int32_t)((uint32_t)qx - (uint32_t)cx);
    int32_t by = (int32_t)((uint32_t)qy - (uint32_t)cy);
    int32_t cell = (int32_t)g->cell_um;
    if ((int64_t)ax * bx + (int64_t)ay * by <= 0 ||
        (int64_t)ax * ax + (int64_t)ay * ay <= (int64_t)cell * cell) {
        return false;
    }
    int32_t side = h < 0 ? -cell : cell;
    uint32_t k;
    return !known_free(g, wx + (int32_t)(((int64_t)n[0] * side) >> LKF_J_SHIFT),
                       wy + (int32_t)(((int64_t)n[1] * side) >> LKF_J_SHIFT), &k);
}

/* One pass: every held-back hit, linearised at lin, updates (d, p) from the prior. */
static uint32_t match_pass(const loc_t *l, const grid_t *g, int32_t cx, int32_t cy,
                           const lkf_state_t *lin, lkf_state_t *d, lkf_cov_t *p)
{
    q1_30_t c = fix_cos(bam_of_urad(lin->v[LKF_T]));
    q1_30_t s = fix_sin(bam_of_urad(lin->v[LKF_T]));
    uint32_t used = 0;
    for (unsigned i = l->win_count - LOC_WINDOW; i < l->win_count; i++) {
        int32_t mx;
        int32_t my;
        int32_t qx;
        int32_t qy;
        held_under(l, g, &l->corr, i, &mx, &my);
        move_point(mx, my, cx, cy, lin->v[LKF_X], lin->v[LKF_Y], c, s, &qx, &qy);
        int32_t wx;
        int32_t wy;
        int32_t j[3];
        if (!wall_near(g, qx, qy, &wx, &wy, &j[0], &j[1])) {
            continue;
        }
        int64_t h = ((int64_t)j[0] * ((int64_t)qx - wx) + (int64_t)j[1] * ((int64_t)qy - wy)) >>
                    LKF_J_SHIFT;
        /* dh/dθ: the normal against the point's lever about the centre, µm per µrad. */
        j[2] = (int32_t)fix_div_s64(
            (int64_t)j[1] * ((int64_t)qx - cx) - (int64_t)j[0] * ((int64_t)qy - cy), 1000000);
        if (j[2] > LOC_LEVER_MAX || j[2] < -LOC_LEVER_MAX) {
            continue; /* heard more than 8 m from where the robot now is */
        }
        if (unseen_face(g, cx, cy, qx, qy, wx, wy, j, h)) {
            continue;
        }
        /* Each hit is matched LOC_WINDOW / LOC_EVERY times: count it once in all. */
        int64_t r = LOC_SIGMA2_UM2 * (int64_t)(LOC_WINDOW / LOC_EVERY);
        r += fix_div_s64(r, LOC_HUBER_UM * LOC_HUBER_UM) * h * h;
        lkf_update(d, p, lin, h, j, r);
        used++;
    }
    return used;
}

static int32_t clamp_kappa(int64_t v)
{
    return (int32_t)(v < -LOC_KAPPA_MAX ? -LOC_KAPPA_MAX : v > LOC_KAPPA_MAX ? LOC_KAPPA_MAX : v);
}

static void match(loc_t *l, const grid_t *g, const odom_pose_t *odom_now)
{
    loc_count(&l->tried);
    odom_pose_t now = loc_apply(&l->corr, odom_now);
    lkf_state_t lin = {{0}};
    lkf_state_t d = {{0}};
    lkf_cov_t *p = &l->work;
    uint32_t used = 0;
    for (unsigned pass = 0; pass < LOC_PASSES; pass++) {
        d = (lkf_state_t){{0}};
        *p = l->cov;
        used = match_pass(l, g, now.x_um, now.y_um, &lin, &d, p);
        lin = d;
    }
    l->last_points = used;
    int64_t step2 = d.v[LKF_X] * d.v[LKF_X] + d.v[LKF_Y] * d.v[LKF_Y];
    int64_t max_th = (int64_t)LOC_MAX_STEP_MDEG * 17453 / 1000; /* µrad */
    if (used < LOC_MIN_POINTS || step2 > (int64_t)LOC_MAX_STEP_UM * LOC_MAX_STEP_UM ||
        d.v[LKF_T] > max_th || d.v[LKF_T] < -max_th) {
        loc_count(&l->refused);
        return;
    }
    loc_count(&l->applied);
    /* About the robot: turn by dθ, then shift by (dx, dy); the drift estimates move on. */
    correct_about(l, now.x_um, now.y_um, bam_of_urad(d.v[LKF_T]), d.v[LKF_X], d.v[LKF_Y]);
    l->kappa_prad_per_mm = clamp_kappa(l->kappa_prad_per_mm + d.v[LKF_KD]);
    l->kappa_ppb = clamp_kappa(l->kappa_ppb + d.v[LKF_KT]);
    lkf_sane(p);
    l->cov = *p;
}

/* ---- draining the queue ------------------------------------------------------------------ */

/* The first half of a hit's log-odds step, placed when it leaves the window (half of one
 * in OM_MODE_COUNT is none). */
static uint8_t early_half(const loc_t *l, const grid_t *g, unsigned i)
{
    return i + LOC_WINDOW < l->win_count && g->mode == OM_MODE_EVIDENCE ? g->hit / 2u : 0u;
}

/* The early halves in OM, those of the held-back hits past the window: taken out at
 * l->placed, or put back at the correction now, which becomes l->placed. */
static void halves(loc_t *l, grid_t *g, bool take_back)
{
    if (!take_back) {
        l->placed = l->corr;
    }
    if (g->mode != OM_MODE_EVIDENCE) {
        return; /* no halves */
    }
    for (unsigned i = 0; i + LOC_WINDOW < l->win_count; i++) {
        if (held_mapped(l, i)) {
            int32_t x;
            int32_t y;
            held_under(l, g, &l->placed, i, &x, &y);
            grid_om_part(g, x, y, early_half(l, g, i), take_back);
        }
    }
}

/* The oldest held-back hit leaves the hold: the rest of it enters OM, at the correction now
 * (its half stays where it lies). */
static void hit_enters_map(loc_t *l, mapper_t *m, grid_t *g)
{
    if (held_mapped(l, 0u)) {
        int32_t x;
        int32_t y;
        held_under(l, g, &l->corr, 0u, &x, &y);
        (void)mapper_hit_rest(m, g, x, y, early_half(l, g, 0u));
    }
    l->win_first = (uint16_t)((l->win_first + 1u) % LOC_HOLD);
    l->win_count--;
}

static void drain_one(loc_t *l, mapper_t *m, grid_t *g, const loc_reading_t *rd)
{
    if (l->on) {
        propagate(l, &rd->ping);
    }
    odom_pose_t at = loc_apply(&l->corr, &rd->ping);
    if (!rd->echo) {
        mapper_timeout(m, g, &at);
        return;
    }
    int32_t x;
    int32_t y;
    if (mapper_free(m, g, &at, rd->servo, rd->range_um, &x, &y) != MAPPER_HIT) {
        return;
    }
    if (!l->on) {
        (void)mapper_hit(m, g, x, y); /* the correction is zero: odometry's frame is the map's */
        return;
    }
    /* Held back in the odometry frame; one just behind a wall the map holds is matched
     * (it says where the pose is wrong) but never mapped (mapper.c, faces()). */
    bool shadowed = m->shadowed;
    sonar_obstacle(&m->sonar, &rd->ping, rd->servo, rd->range_um, &x, &y);
    loc_point_t pt;
    if (!to_point(l, g, x, y, &pt)) {
        loc_count(&m->outside); /* a grid's length off the grid: nothing to match or map */
        return;
    }
    if (l->win_count == LOC_HOLD) {
        hit_enters_map(l, m, g);
    }
    unsigned slot = (l->win_first + l->win_count) % LOC_HOLD;
    l->win[slot] = pt;
    uint32_t *word = &l->win_shadowed[slot / 32u];
    *word = (*word & ~(1u << (slot % 32u))) | ((uint32_t)shadowed << (slot % 32u));
    l->win_count++;
    /* The hit that just left the window: half of it enters OM now, with the other halves,
     * so that what exploration reads in OM holds the walls just seen; the rest enters
     * when it leaves the hold, where the correction then puts it. */
    unsigned left = l->win_count - LOC_WINDOW - 1u; /* (wraps when none has left yet) */
    if (l->win_count > LOC_WINDOW && held_mapped(l, left)) {
        held_under(l, g, &l->placed, left, &x, &y);
        grid_om_part(g, x, y, early_half(l, g, left), false);
    }
    /* A match sees OM without the halves (the minute just seen would hold the pose where
     * it drew them); they go back where the new correction puts them. */
    if (++l->since_match >= LOC_EVERY && l->win_count >= LOC_WINDOW) {
        l->since_match = 0u;
        halves(l, g, true);
        match(l, g, &rd->ping);
        halves(l, g, false);
    }
}

/* The obstacle ahead of the robot at ping among the hits OM does not hold yet (the file
 * overview says which), into pt: exploration keeps clear of it as of a wall on the map. */
static void obstacle_ahead(const loc_t *l, const grid_t *g, const odom_pose_t *ping,
                           int32_t pt[2])
{
    odom_pose_t at = loc_apply(&l->corr, ping);
    q1_30_t c = fix_cos(at.heading);
    q1_30_t s = fix_sin(at.heading);
    /* The nearest hit (its cell k1) and the nearest in any other cell, ahead of the axle. */
    int32_t near[2] = {INT32_MAX, INT32_MAX};
    int32_t near_pt[2][2] = {{LOC_AHEAD_NONE, 0}, {LOC_AHEAD_NONE, 0}};
    uint32_t k1 = UINT32_MAX;
    unsigned first = l->win_count > LOC_WINDOW ? l->win_count - LOC_WINDOW : 0u;
    for (unsigned i = first; i < l->win_count; i++) {
        if (!held_mapped(l, i)) {
            continue;
        }
        int32_t x;
        int32_t y;
        uint32_t cell;
        held_under(l, g, &l->corr, i, &x, &y);
        if (known_free(g, x, y, &cell)) {
            continue;
        }
        /* Differences modulo 2^32, exact within the 1 km world slam_config_check() allows;
         * their products with Q30 values fit 64 bits. */
        int32_t dx = (int32_t)((uint32_t)x - (uint32_t)at.x_um);
        int32_t dy = (int32_t)((uint32_t)y - (uint32_t)at.y_um);
        int32_t ahead = (int32_t)(((int64_t)dx * c + (int64_t)dy * s) >> 30);
        int32_t side = (int32_t)(((int64_t)dy * c - (int64_t)dx * s) >> 30);
        if (ahead <= 0 || ahead >= LOC_AHEAD_REACH_UM || side <= -l->clear_um ||
            side >= l->clear_um || (cell == k1 ? ahead >= near[0] : ahead >= near[1])) {
            continue;
        }
        if (ahead < near[0]) {
            if (cell != k1) {
                near[1] = near[0];
                near_pt[1][0] = near_pt[0][0];
                near_pt[1][1] = near_pt[0][1];
            }
            k1 = cell;
            near[0] = ahead;
            near_pt[0][0] = x;
            near_pt[0][1] = y;
        } else {
            near[1] = ahead;
            near_pt[1][0] = x;
            near_pt[1][1] = y;
        }
    }
    pt[0] = near_pt[1][0];
    pt[1] = near_pt[1][1];
}

void loc_idle(loc_t *l, mapper_t *m, grid_t *g)
{
    while (l->tail != l->head) {
        loc_reading_t rd = l->queue[l->tail];
        drain_one(l, m, g, &rd);
        int32_t ahead[2];
        obstacle_ahead(l, g, &rd.ping, ahead);
        l->tail = (uint8_t)((l->tail + 1u) % LOC_QUEUE);
        l->drained++;
        /* Published under a generation count: odd while written, so a tick that comes in
         * between (on an MCU, the interrupt) leaves it alone. */
        l->pub_gen++;
        l->pub = l->corr;
        l->pub_ahead[0] = ahead[0];
        l->pub_ahead[1] = ahead[1];
        l->pub_seq = l->drained;
        l->pub_gen++;
    }
}

void loc_flush(loc_t *l, mapper_t *m, grid_t *g)
{
    while (l->win_count > 0u) {
        hit_enters_map(l, m, g);
    }
}
