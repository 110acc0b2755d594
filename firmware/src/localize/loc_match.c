/* SPDX-License-Identifier: MIT */
/* A match of the pose correction: the window's hits against OM's wall lines by an iterated
 * sequential Kalman update, gated, and applied or refused. */
#include "loc_match.h"

#include "loc_filter.h"
#include "loc_hold.h"
#include "loc_walls.h"

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

/* Each window hit's wall, from one pass to the next. Scratch of one match, so outside
 * loc_t: the background loop runs one match at a time, and nothing in it outlives the
 * match (it is forgotten when the next begins). */
static loc_assoc_t loc_match_assoc[LOC_WINDOW];

/* One pass: every hit of the window, linearised at lin, updates (d, p) from the prior. */
static uint32_t match_pass(const loc_t *l, const grid_t *g, int32_t cx, int32_t cy,
                           const lkf_state_t *lin, lkf_state_t *d, lkf_cov_t *p)
{
    q1_30_t c = fix_cos(loc_bam_of_urad(lin->v[LKF_T]));
    q1_30_t s = fix_sin(loc_bam_of_urad(lin->v[LKF_T]));
    /* At no increment (the first pass) cos is exactly one and sin zero: the points stay. */
    bool moved = lin->v[LKF_X] != 0 || lin->v[LKF_Y] != 0 || lin->v[LKF_T] != 0;
    uint32_t used = 0;
    unsigned first = l->hold.count - LOC_WINDOW;
    for (unsigned i = first; i < l->hold.count; i++) {
        int32_t mx;
        int32_t my;
        int32_t qx;
        int32_t qy;
        loc_hold_point(&l->hold, g, &l->filter.corr, i, &mx, &my);
        if (moved) {
            loc_move_point(mx, my, cx, cy, lin->v[LKF_X], lin->v[LKF_Y], c, s, &qx, &qy);
        } else {
            qx = mx;
            qy = my;
        }
        int32_t wx;
        int32_t wy;
        int32_t j[3];
        if (!loc_wall_near(g, qx, qy, &loc_match_assoc[i - first], &wx, &wy, &j[0], &j[1])) {
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
        if (loc_unseen_face(g, cx, cy, qx, qy, wx, wy, j, h)) {
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

static bool same_state(const lkf_state_t *a, const lkf_state_t *b)
{
    for (unsigned i = 0; i < LKF_N; i++) {
        if (a->v[i] != b->v[i]) {
            return false;
        }
    }
    return true;
}

/* A state's entry in units of @p unit, saturated to int16 (loc_match_t's last_step). */
static int16_t step_of(int64_t v, int64_t unit)
{
    v = fix_div_s64(v, unit);
    return (int16_t)(v > INT16_MAX ? INT16_MAX : v < INT16_MIN ? INT16_MIN : v);
}

static void match(loc_t *l, const grid_t *g, const odom_pose_t *odom_now)
{
    loc_match_t *mt = &l->match;
    loc_count(&mt->tried);
    odom_pose_t now = loc_apply(&l->filter.corr, odom_now);
    lkf_state_t lin = {{0}};
    lkf_state_t d = {{0}};
    lkf_cov_t *p = &mt->work;
    uint32_t used = 0;
    /* OM stands still while the passes run, but not from one match to the next. */
    for (unsigned k = 0; k < LOC_WINDOW; k++) {
        loc_assoc_forget(&loc_match_assoc[k]);
    }
    for (unsigned pass = 0; pass < LOC_PASSES; pass++) {
        d = (lkf_state_t){{0}};
        *p = l->filter.cov;
        used = match_pass(l, g, now.x_um, now.y_um, &lin, &d, p);
        if (same_state(&d, &lin)) {
            /* The pass ended where it was linearised (no wall moved it, say): the next
             * would start from the same state, prior and map, and repeat it exactly. */
            break;
        }
        lin = d;
    }
    mt->last_points = used;
    mt->last_step[0] = step_of(d.v[LKF_X], 100);
    mt->last_step[1] = step_of(d.v[LKF_Y], 100);
    mt->last_step[2] = step_of(d.v[LKF_T], 10);
    int64_t step2 = d.v[LKF_X] * d.v[LKF_X] + d.v[LKF_Y] * d.v[LKF_Y];
    int64_t max_th = (int64_t)LOC_MAX_STEP_MDEG * 17453 / 1000; /* µrad */
    if (used < LOC_MIN_POINTS || step2 > (int64_t)LOC_MAX_STEP_UM * LOC_MAX_STEP_UM ||
        d.v[LKF_T] > max_th || d.v[LKF_T] < -max_th) {
        loc_count(&mt->refused);
        return;
    }
    loc_count(&mt->applied);
    /* About the robot: turn by dθ, then shift by (dx, dy); the drift estimates move on. */
    loc_filter_correct(&l->filter, now.x_um, now.y_um, &d, p);
}

void loc_match_hit(loc_t *l, grid_t *g, const odom_pose_t *ping)
{
    /* A match sees OM without the halves (the minute just seen would hold the pose where
     * it drew them); they go back where the new correction puts them. */
    if (++l->match.since >= LOC_EVERY && l->hold.count >= LOC_WINDOW) {
        l->match.since = 0u;
        loc_hold_halves(&l->hold, g, &l->filter.corr, true);
        match(l, g, ping);
        loc_hold_halves(&l->hold, g, &l->filter.corr, false);
    }
}
