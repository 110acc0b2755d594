/* SPDX-License-Identifier: MIT */
/* After a run: scores of every post-processing step, metrics.json, the summary, the figure. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "host_sim.h"
#include "slam/postprocess.h"

#ifndef SLAM_SOURCE_DIR
#define SLAM_SOURCE_DIR "."
#endif

static const double PI = HOST_SIM_PI;

/* Scores a map after each post-processing step; leaves the final map in out. */
void score_chain(const run_t *r, const uint8_t *om, const slam_config_t *cfg, uint8_t *out,
                 uint8_t *scratch, chain_scores_t *s)
{
    const map_geom_t *g = &r->geom;
    size_t n = (size_t)g->a * g->b;
    /* The raw map: every cell the mode calls occupied. */
    memcpy(out, om, n);
    post_threshold(out, g->a, g->b, grid_threshold_byte(cfg->om_mode, 0u), cfg->om_max);
    score_map(g, out, r->truth, r->observable, &s->raw);
    /* A step that is off leaves the map as it was, and so its score (the default on the
     * evidence map: every step off). */
    s->threshold = s->raw;
    if (cfg->post_threshold != 0u) {
        memcpy(out, om, n);
        post_threshold(out, g->a, g->b, grid_threshold_byte(cfg->om_mode, cfg->post_threshold),
                       cfg->om_max);
        score_map(g, out, r->truth, r->observable, &s->threshold);
    }
    s->templ = s->threshold;
    if (cfg->post_template_k > 0u) {
        post_template(out, g->a, g->b, cfg->post_template_k, scratch);
        score_map(g, out, r->truth, r->observable, &s->templ);
    }
    s->insert = s->templ;
    if (cfg->post_insert != 0u) {
        post_insert(out, g->a, g->b, cfg->om_max, scratch);
        score_map(g, out, r->truth, r->observable, &s->insert);
    }
}

static void json_score(FILE *f, const char *name, const score_t *s, bool comma)
{
    fprintf(f,
            "      \"%s\": {\"precision\": %.4f, \"recall\": %.4f, \"f1\": %.4f, "
            "\"mapped\": %u, \"true_positive\": %u, \"observable\": %u, \"matched\": %u}%s\n",
            name, s->precision, s->recall, s->f1, s->mapped, s->true_pos, s->observable, s->matched,
            comma ? "," : "");
}

static void json_chain(FILE *f, const char *name, const chain_scores_t *c, bool comma)
{
    fprintf(f, "    \"%s\": {\n", name);
    json_score(f, "raw", &c->raw, true);
    json_score(f, "threshold", &c->threshold, true);
    json_score(f, "template", &c->templ, true);
    json_score(f, "insert", &c->insert, false);
    fprintf(f, "    }%s\n", comma ? "," : "");
}

static void json_time(FILE *f, const char *name, double t, bool comma)
{
    if (t < 0.0) {
        fprintf(f, "    \"%s\": null%s\n", name, comma ? "," : "");
    } else {
        fprintf(f, "    \"%s\": %.2f%s\n", name, t, comma ? "," : "");
    }
}

void sweep_post(const run_t *r, const uint8_t *om, const slam_config_t *cfg, uint8_t *out,
                uint8_t *scratch, post_sweep_t *ps)
{
    /* Every TH a count can take; the first log-odds thresholds of an evidence map (a hit
     * is worth om_hit, so a few hits' worth). */
    ps->th_count = cfg->om_mode == OM_MODE_COUNT ? cfg->om_max : SWEEP_EVIDENCE_TH;
    double best = -1.0;
    for (uint8_t th = 0; th < ps->th_count; th++) {
        for (uint8_t k = 0; k < SWEEP_K; k++) {
            post_params_t pp = {.threshold = grid_threshold_byte(cfg->om_mode, th),
                                .om_max = cfg->om_max,
                                .k = k,
                                .insert = cfg->post_insert};
            (void)post_run(om, out, r->geom.a, r->geom.b, &pp, scratch);
            score_map(&r->geom, out, r->truth, r->observable, &ps->s[th][k]);
            if (ps->s[th][k].f1 > best) {
                best = ps->s[th][k].f1;
                ps->best_th = th;
                ps->best_k = k;
            }
        }
    }
}

static void json_sweep(FILE *f, const post_sweep_t *ps)
{
    const char *what[3] = {"precision", "recall", "f1"};
    fprintf(f, "  \"post_sweep\": {\n    \"threshold\": [0");
    for (unsigned th = 1; th < ps->th_count; th++) {
        fprintf(f, ", %u", th);
    }
    fprintf(f, "],\n    \"k\": [0, 1, 2, 3, 4, 5, 6, 7, 8],\n");
    for (int w = 0; w < 3; w++) {
        fprintf(f, "    \"%s\": [", what[w]);
        for (unsigned th = 0; th < ps->th_count; th++) {
            fprintf(f, "%s[", th ? ", " : "");
            for (unsigned k = 0; k < SWEEP_K; k++) {
                const score_t *s = &ps->s[th][k];
                double v = w == 0 ? s->precision : w == 1 ? s->recall : s->f1;
                fprintf(f, "%s%.4f", k ? ", " : "", v);
            }
            fprintf(f, "]");
        }
        fprintf(f, "],\n");
    }
    const score_t *b = &ps->s[ps->best_th][ps->best_k];
    fprintf(f,
            "    \"best\": {\"threshold\": %u, \"k\": %u, \"precision\": %.4f, "
            "\"recall\": %.4f, \"f1\": %.4f}\n  },\n",
            ps->best_th, ps->best_k, b->precision, b->recall, b->f1);
}

/* The incidence limit: one number when it is flat, else the curve's [range m, deg] knots. */
static void json_grazing(FILE *f, const sim_errors_t *e)
{
    const sim_grazing_curve_t *c = &e->grazing_curve;
    if (c->n == 0u) {
        fprintf(f, "%.6g", e->grazing_deg);
        return;
    }
    fprintf(f, "[");
    for (uint32_t i = 0; i < c->n; i++) {
        fprintf(f, "%s[%.6g, %.6g]", i ? ", " : "", c->range_m[i], c->deg[i]);
    }
    fprintf(f, "]");
}

/* What became of the pings, and the walls of the perfect-odometry map readings lowered. */
static void json_pings(FILE *f, const sim_t *sim, const run_t *r)
{
    static const char *const kinds[SIM_PING_KINDS] = {
        [SIM_PING_ECHO] = "echo",       [SIM_PING_MULTIPATH] = "multipath",
        [SIM_PING_GHOST] = "ghost",     [SIM_PING_LATE] = "late",
        [SIM_PING_DROPOUT] = "dropout", [SIM_PING_GRAZING] = "grazing",
        [SIM_PING_NOTHING] = "nothing", [SIM_PING_STUCK] = "stuck"};
    uint32_t counts[SIM_PING_KINDS];
    sim_ping_counts(sim, counts);
    fprintf(f, "  \"pings\": {");
    for (int k = 1; k < (int)SIM_PING_KINDS; k++) {
        fprintf(f, "\"%s\": %u, ", kinds[k], counts[k]);
    }
    fprintf(f, "\"walls_lowered\": {\"multipath\": %u, \"other\": %u}},\n", r->walls_lowered[0],
            r->walls_lowered[1]);
}

/* Grid cells an MCU would need to hold this room, plus a cell of margin each side. In
 * whole micrometres: a quotient of doubles rounds differently with x87 (-m32). */
static uint32_t cells_needed(double span_m, uint32_t cell_um)
{
    uint64_t span_um = (uint64_t)llround(span_m * 1e6);
    return (uint32_t)((span_um + cell_um - 1u) / cell_um) + 2u;
}

int write_metrics(const options_t *o, const room_t *room, const run_t *r, const slam_config_t *cfg,
                  const sim_errors_t *e, const sim_t *sim, const robot_t *robot,
                  const chain_scores_t *odo, const chain_scores_t *ideal, const post_sweep_t *ps)
{
    FILE *f = open_out(o->out, "metrics.json");
    if (f == NULL) {
        return -1;
    }
    sim_truth_t tr = sim_truth(sim);
    fprintf(f, "{\n  \"scenario\": {\n");
    fprintf(f, "    \"room\": \"%s\",\n", o->room);
    if (o->has_crop) {
        fprintf(f, "    \"crop\": [%.3f, %.3f, %.3f, %.3f],\n", o->crop.x, o->crop.y, o->crop.w,
                o->crop.h);
    } else {
        fprintf(f, "    \"crop\": null,\n");
    }
    fprintf(f, "    \"room_bounds\": [%.3f, %.3f, %.3f, %.3f],\n", room->min_x, room->min_y,
            room->max_x, room->max_y);
    fprintf(f, "    \"start\": [%.3f, %.3f, %.2f],\n", cfg->start_x_um * 1e-6,
            cfg->start_y_um * 1e-6, cfg->start_heading_mdeg / 1000.0);
    fprintf(f, "    \"duration_s\": %.2f,\n    \"seed\": %llu,\n    \"cell_mm\": %.0f,\n",
            o->duration_s, (unsigned long long)o->seed, o->cell_mm);
    fprintf(f, "    \"explore\": \"%s\",\n    \"ideal\": %s,\n", explore_names[o->explore],
            o->ideal ? "true" : "false");
    if (o->ideal) {
        fprintf(f, "    \"sonar\": null,\n");
    } else {
        fprintf(f, "    \"sonar\": \"%s\",\n", sim_sonar_level_name((sim_sonar_level_t)o->sonar));
    }
    fprintf(f, "    \"accel_mm_s2\": %u,\n", cfg->accel_mm_s2);
    if (o->calibration != NULL) {
        fprintf(f, "    \"calibration\": \"%s\",\n", o->calibration);
    } else {
        fprintf(f, "    \"calibration\": null,\n");
    }
    fprintf(f, "    \"cal\": {\"left\": %.9f, \"right\": %.9f, \"base\": %.9f},\n",
            cfg->cal_left / (double)FIX_Q30_ONE, cfg->cal_right / (double)FIX_Q30_ONE,
            cfg->cal_base / (double)FIX_Q30_ONE);
    fprintf(f, "    \"om\": {\"mode\": \"%s\", \"hit\": %u, \"miss\": %u, \"om_max\": %u},\n",
            cfg->om_mode == OM_MODE_COUNT ? "count" : "evidence", cfg->om_hit, cfg->om_miss,
            cfg->om_max);
    fprintf(f, "    \"post\": {\"threshold\": %u, \"k\": %u, \"insert\": %s, \"om_max\": %u},\n",
            cfg->post_threshold, cfg->post_template_k, cfg->post_insert ? "true" : "false",
            cfg->om_max);
    fprintf(f,
            "    \"errors\": {\"ed\": %.6g, \"eb\": %.6g, \"slip\": %.6g, \"slip_free\": %.6g, "
            "\"noise\": %.6g, \"sonar_noise\": %.6g, \"dropout\": %.6g, \"ghost\": %.6g, "
            "\"grazing\": ",
            e->wheel_ratio_ed, e->wheel_base_eb, e->slip_per_mps2, e->slip_free_mps2,
            e->wheel_noise, e->sonar_noise_m, e->sonar_dropout, e->sonar_ghost);
    json_grazing(f, e);
    fprintf(f, ", \"multipath\": %u},\n", e->multipath);
    fprintf(f, "    \"grid\": {\"a\": %u, \"b\": %u, \"origin\": [%.6f, %.6f]}\n  },\n", r->geom.a,
            r->geom.b, r->geom.origin_x, r->geom.origin_y);

    fprintf(f, "  \"maps\": {\n");
    json_chain(f, "odometry", odo, true);
    json_chain(f, "perfect_odometry", ideal, false);
    fprintf(f, "  },\n");
    if (ps != NULL) {
        json_sweep(f, ps);
    }

    fprintf(f,
            "  \"odometry\": {\n    \"final_position_m\": %.4f,\n    \"max_position_m\": %.4f,\n"
            "    \"final_heading_deg\": %.3f,\n    \"max_heading_deg\": %.3f,\n"
            "    \"path_m\": %.3f\n  },\n",
            r->final_pos_err, r->max_pos_err, r->final_th_err * 180.0 / PI,
            r->max_th_err * 180.0 / PI, r->path_m);

    fprintf(f,
            "  \"exploration\": {\n    \"reachable_cells\": %u,\n    \"visited_cells\": %u,\n"
            "    \"coverage\": %.4f,\n",
            r->reachable_cells, r->visited_cells,
            r->reachable_cells ? (double)r->visited_cells / r->reachable_cells : 0.0);
    json_time(f, "time_to_50_s", r->time_to[0], true);
    json_time(f, "time_to_80_s", r->time_to[1], true);
    json_time(f, "time_to_90_s", r->time_to[2], true);
    fprintf(f, "    \"series\": [");
    for (size_t i = 0; i < r->nseries; i++) {
        fprintf(f, "%s[%.1f, %.4f]", i ? ", " : "", r->series[i][0], r->series[i][1]);
    }
    fprintf(f,
            "],\n    \"wall_cells\": %u,\n    \"walls_covered\": %u,\n"
            "    \"wall_coverage\": %.4f,\n",
            r->wall_cells, r->walls_covered,
            r->wall_cells ? (double)r->walls_covered / r->wall_cells : 0.0);
    json_time(f, "wall_time_to_50_s", r->wall_time_to[0], true);
    json_time(f, "wall_time_to_80_s", r->wall_time_to[1], true);
    json_time(f, "wall_time_to_90_s", r->wall_time_to[2], true);
    fprintf(f, "    \"wall_series\": [");
    for (size_t i = 0; i < r->nseries; i++) {
        fprintf(f, "%s[%.1f, %.4f]", i ? ", " : "", r->series[i][0], r->series[i][2]);
    }
    fprintf(f, "],\n    \"min_clearance_m\": %.4f,\n", r->min_clearance);
    fprintf(f,
            "    \"longest_without_progress_s\": %.2f,\n    \"without_progress_from_s\": %.2f,\n",
            r->stuck_s, r->stuck_from_s);
    json_time(f, "explored_at_s", r->explored_at_s, true);
    double longest = r->touch_recovery_max_s;
    if (r->touching && robot->ticks * TICK_S - r->touch_from_t > longest) {
        longest = robot->ticks * TICK_S - r->touch_from_t;
    }
    json_time(f, "longest_touch_recovery_s", r->touches > 0u ? longest : -1.0, true);
    fprintf(f, "    \"touch_recovery_s\": [");
    for (uint32_t i = 0; i < r->touches && i < TOUCHES_LISTED; i++) {
        if (r->touch_recovery_s[i] < 0.0) {
            fprintf(f, "%snull", i ? ", " : "");
        } else {
            fprintf(f, "%s%.2f", i ? ", " : "", r->touch_recovery_s[i]);
        }
    }
    fprintf(f, "],\n");
    if (r->touch_t < 0.0) {
        fprintf(f, "    \"first_touch\": null\n  },\n");
    } else {
        fprintf(f,
                "    \"first_touch\": {\"t_s\": %.2f, \"x_m\": %.4f, \"y_m\": %.4f, "
                "\"heading_deg\": %.2f, \"bearing_deg\": %.0f, \"position_error_m\": %.4f, "
                "\"heading_error_deg\": %.2f}\n  },\n",
                r->touch_t, r->touch_x, r->touch_y, r->touch_th * 180.0 / PI,
                r->touch_bearing * 180.0 / PI, r->touch_pos_err, r->touch_th_err * 180.0 / PI);
    }

    const sweep_t *sw = &robot->sweep;
    const mapper_t *m = &robot->mapper;
    fprintf(f,
            "  \"robot\": {\"ticks\": %u, \"pings\": %u, \"echoes\": %u, \"timeouts\": %u, "
            "\"om_hits\": %u, \"beyond_rc\": %u, \"too_close\": %u, \"outside_grid\": %u, "
            "\"collisions\": %u, \"turns\": %u, \"avoidances\": %u, \"stalls\": %u, "
            "\"walls_left\": %u, \"openings_passed\": %u, \"frontier_targets\": %u, "
            "\"escapes\": %u, \"ways\": %u, \"bumped_ticks\": %u, \"sonar1_readings\": %u, "
            "\"sonar1_echoes\": %u},\n",
            robot->ticks, sw->pings, sw->echoes, sw->timeouts, m->hits, m->far, m->near, m->outside,
            tr.collisions, robot->explore.count.turns, robot->explore.count.avoidances,
            robot->explore.count.stalls, robot->explore.count.leaves, robot->explore.count.doors,
            robot->explore.count.seeks, robot->explore.count.escapes, robot->explore.count.ways,
            robot->bumped, robot->sonar1.readings, robot->sonar1.echoes);
    json_pings(f, sim, r);
    const loc_t *lo = &robot->loc;
    fprintf(f,
            "  \"localization\": {\"on\": %s, \"tried\": %u, \"applied\": %u, "
            "\"refused\": %u, \"dropped\": %u, \"late\": %u},\n",
            lo->on ? "true" : "false", lo->match.tried, lo->match.applied, lo->match.refused,
            robot->readq.dropped, robot->readq.late);

    double span_x = room->max_x - room->min_x;
    double span_y = room->max_y - room->min_y;
    uint32_t na = cells_needed(span_x, cfg->cell_um);
    uint32_t nb = cells_needed(span_y, cfg->cell_um);
    size_t state = sizeof(robot_t) - 2u * (size_t)SLAM_GRID_CELLS;
    fprintf(f,
            "  \"ram\": {\"grid_a\": %u, \"grid_b\": %u, \"maps_bytes\": %lu, "
            "\"state_bytes\": %zu, \"total_bytes\": %lu}\n}\n",
            na, nb, 2ul * na * nb, state, 2ul * na * nb + state);
    return close_out(f, o->out, "metrics.json");
}

/* Draws figure.png with tools/plot_run.py; a missing Python or matplotlib is a warning. */
void plot_figure(const char *out, bool quiet)
{
    const char *script = SLAM_SOURCE_DIR "/tools/plot_run.py";
    char *argv[] = {"/usr/bin/python3", (char *)script, (char *)out, "--quiet", NULL};
    pid_t pid;
    extern char **environ;
    if (access(argv[0], X_OK) != 0 || access(script, R_OK) != 0 ||
        posix_spawn(&pid, argv[0], NULL, NULL, argv, environ) != 0) {
        fprintf(stderr, "host_sim: cannot run %s; no figure (tools/install-deps.sh sim)\n", script);
        return;
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "host_sim: %s failed; no figure\n", script);
    } else if (!quiet) {
        printf("  figure          %s/figure.png\n", out);
    }
}

void print_summary(const options_t *o, const run_t *r, const chain_scores_t *odo,
                   const chain_scores_t *ideal, const post_sweep_t *ps, double wall_s,
                   uint64_t ticks, const sim_t *sim, const robot_t *robot)
{
    sim_truth_t tr = sim_truth(sim);
    const char *sonar = sim_sonar_level_name((sim_sonar_level_t)o->sonar);
    printf("\nsonarslam host_sim: %s, %.0f s, seed %llu, %.0f mm cells, %s exploration, %s%s\n",
           o->room, o->duration_s, (unsigned long long)o->seed, o->cell_mm,
           explore_names[o->explore], o->ideal ? "ideal" : sonar, o->ideal ? "" : " sonar");
    printf("  simulated %llu ticks in %.2f s of wall time: %.0fx real time\n",
           (unsigned long long)ticks, wall_s, wall_s > 0 ? (double)ticks * TICK_S / wall_s : 0.0);
    printf("\n  map (vs truth)        precision  recall     F1   | perfect odometry F1\n");
    const char *names[4] = {"raw OM", "+ threshold", "+ template", "+ insert (final)"};
    const score_t *a[4] = {&odo->raw, &odo->threshold, &odo->templ, &odo->insert};
    const score_t *b[4] = {&ideal->raw, &ideal->threshold, &ideal->templ, &ideal->insert};
    for (int i = 0; i < 4; i++) {
        printf("  %-20s    %6.3f  %6.3f  %6.3f   |  %6.3f\n", names[i], a[i]->precision,
               a[i]->recall, a[i]->f1, b[i]->f1);
    }
    if (ps != NULL) {
        const score_t *best = &ps->s[ps->best_th][ps->best_k];
        printf("  best TH=%u K=%u          %6.3f  %6.3f  %6.3f\n", ps->best_th, ps->best_k,
               best->precision, best->recall, best->f1);
    }
    const loc_t *lo = &robot->loc;
    printf("\n  pose error      final %.3f m, %.2f deg; max %.3f m, %.2f deg (path %.1f m)\n",
           r->final_pos_err, r->final_th_err * 180.0 / PI, r->max_pos_err,
           r->max_th_err * 180.0 / PI, r->path_m);
    if (lo->on) {
        printf("  pose correction %u of %u matches applied against the map\n", lo->match.applied,
               lo->match.tried);
    } else {
        printf("  pose correction off: the pose is odometry alone\n");
    }
    printf("  coverage        %.1f %% of %u reachable cells visited; collisions %u, "
           "closest %.3f m\n",
           r->reachable_cells ? 100.0 * r->visited_cells / r->reachable_cells : 0.0,
           r->reachable_cells, tr.collisions, r->min_clearance);
    printf("  walls           %.1f %% of %u wall cells inside a ping's confidence sector",
           r->wall_cells ? 100.0 * r->walls_covered / r->wall_cells : 0.0, r->wall_cells);
    const char *marks[3] = {"50", "80", "90"};
    for (int k = 0; k < 3; k++) {
        if (r->wall_time_to[k] >= 0.0) {
            printf("%s %s %% at %.0f s", k ? "," : ";", marks[k], r->wall_time_to[k]);
        }
    }
    printf("\n");
    if (r->explored_at_s >= 0.0) {
        printf("  explored        everything it could reach, at %.0f s: it stood from then on\n",
               r->explored_at_s);
    }
    printf("  calibration     %s\n", o->calibration != NULL ? o->calibration : "none");
    /* A first run is read by someone who has not met the paper's words yet. */
    printf("\n  what these mean (every term: host_sim/GLOSSARY.md)\n"
           "    precision     of the cells the map calls wall, the share that are wall (within "
           "a cell)\n"
           "    recall        of the walls the sonar came within 1 m of, the share the map has\n"
           "    F1            precision and recall in one score: 1 is a perfect map\n"
           "    perfect odometry F1  the map drawn from where the robot really was at each "
           "ping:\n"
           "                  what the sonar alone allows; the difference is the gap\n"
           "    raw OM        the robot's obstacle map; threshold (TH), template (K) and insert "
           "are\n"
           "                  the paper's clean-up steps, off unless --paper%s\n"
           "    pose error    how far the robot's idea of where it is ended from the truth, and "
           "its worst\n"
           "    pose correction  how often the robot lined its last sonar hits up with its map "
           "to fix its pose\n"
           "    coverage      the floor the robot drove over; collisions: touches; closest: its "
           "nearest approach\n"
           "    walls         the walls the sonar looked at from within 1 m (its confidence "
           "sector)\n"
           "    explored      the robot found no frontier it could reach, twice a minute apart, "
           "and stood\n"
           "    calibration   the wheels' correction in use (README.md, Calibration)\n\n",
           ps != NULL ? "; best TH, K: the steps'\n                  settings that would have "
                        "scored best"
                      : "");
    printf("  outputs         %s/\n", o->out);
}
