/* SPDX-License-Identifier: MIT */
/* host_sim's scenario: the room, the start pose, the robot's errors, the configuration and
 * the world, every part checked before anything is written. */
#include <stdlib.h>
#include <string.h>

#include "host_sim.h"

static const double PI = HOST_SIM_PI;

/* The start pose must lie inside the room: rays in eight directions all meet a wall. */
static int check_enclosed(const options_t *o, const room_t *room, double sx, double sy)
{
    double dir_deg = 0.0;
    if (room_encloses(room, sx, sy, &dir_deg)) {
        return 0;
    }
    char who[1100];
    if (o->has_start) {
        snprintf(who, sizeof who, "--start %g %g", sx, sy);
    } else if (room->start_line != 0u) {
        snprintf(who, sizeof who, "%s:%u: start pose (%g, %g)", o->room, room->start_line, sx, sy);
    } else {
        snprintf(who, sizeof who, "%s: start pose (%g, %g)", o->room, sx, sy);
    }
    fprintf(stderr, "host_sim: %s is outside the room: a ray toward %.0f deg meets no wall\n", who,
            dir_deg);
    return -1;
}

/* The start pose: --start, else the room's, else a free place found in it; inside the room
 * and clear of obstacles for the default body. 0, or EXIT_USAGE with a message. */
static int choose_start(const options_t *o, scenario_t *sc)
{
    const room_t *room = &sc->room;
    sim_params_t params;
    sim_params_default(&params);
    sc->sx = room->start_x;
    sc->sy = room->start_y;
    sc->sth = room->start_th;
    if (o->has_start) {
        sc->sx = o->start_x;
        sc->sy = o->start_y;
        sc->sth = o->start_deg * PI / 180.0;
        if (!room_disc_free(room, sc->sx, sc->sy, params.body_radius_m)) {
            fprintf(stderr, "host_sim: --start %g %g is inside or against an obstacle\n", sc->sx,
                    sc->sy);
            return EXIT_USAGE;
        }
    } else if (!room->has_start && room_find_start(room, params.body_radius_m + 0.05, &sc->sx,
                                                   &sc->sy, &sc->sth) != 0) {
        fprintf(stderr, "host_sim: %s: no free start pose; give one with --start\n", o->room);
        return EXIT_USAGE;
    }
    if (check_enclosed(o, room, sc->sx, sc->sy) != 0) {
        return EXIT_USAGE;
    }
    return 0;
}

/* The error levels (--ideal, or the defaults with the --sonar level, then each --error),
 * and the calibration that goes with them. 0, or EXIT_USAGE with a message. */
static int choose_errors(options_t *o, sim_errors_t *errors)
{
    if (o->ideal) {
        sim_errors_ideal(errors);
    } else {
        sim_errors_default(errors);
        sim_errors_sonar(errors, (sim_sonar_level_t)o->sonar);
    }
    for (size_t i = 0; i < o->nerrors; i++) {
        if (apply_error(errors, o->errors[i]) != 0) {
            return EXIT_USAGE;
        }
    }
    /* The shipped calibration belongs to the default robot: not to an ideal one, nor to
     * one with other wheels. */
    sim_errors_t defaults;
    sim_errors_default(&defaults);
    if (o->calibration == NULL) {
        bool default_robot = !o->ideal && errors->wheel_ratio_ed == defaults.wheel_ratio_ed &&
                             errors->wheel_base_eb == defaults.wheel_base_eb;
        o->calibration = default_robot ? SLAM_SOURCE_DIR HOST_SIM_CALIBRATION : NULL;
    } else if (strcmp(o->calibration, "none") == 0) {
        o->calibration = NULL;
    }
    return 0;
}

/* Where the robot can go from its start: the grid cells its body fits in (the disc at the
 * cell's centre clear) that no wall passes through, joined side by side. A way from one
 * such cell to the next cannot cross a wall, since a wall between two centres passes
 * through one of the two cells. Eight rays from the start (check_enclosed()) miss a gap
 * between two of them; this finds one the robot fits through wherever it lies (any gap
 * wider than the body and a cell or two), and reaching a cell beyond the room's bounds or
 * the grid's edge means the robot could leave the room: drive off the map and on, as far
 * as the world goes. 0, or EXIT_USAGE with a message. */
static int check_closed(const options_t *o, const scenario_t *sc)
{
    const slam_config_t *cfg = &sc->cfg;
    const room_t *room = &sc->room;
    const uint32_t A = grid_cells_a(cfg);
    const uint32_t B = grid_cells_b(cfg);
    const size_t n = (size_t)A * B;
    const double cell = cfg->cell_um * 1e-6;
    /* The grid's origin as grid_init() puts it. */
    const double ox = grid_origin_um(cfg->start_x_um, cfg->start_cell_a, cfg->cell_um) * 1e-6;
    const double oy = grid_origin_um(cfg->start_y_um, cfg->start_cell_b, cfg->cell_um) * 1e-6;
    sim_params_t params;
    sim_params_default(&params);
    uint8_t *wall = calloc(n, 1u);
    uint8_t *seen = calloc(n, 1u);
    uint32_t *queue = malloc(n * sizeof *queue);
    if (wall == NULL || seen == NULL || queue == NULL) {
        free(wall);
        free(seen);
        free(queue);
        fprintf(stderr, "host_sim: out of memory\n");
        return EXIT_USAGE;
    }
    room_rasterize(room, ox, oy, cell, A, B, wall);
    size_t head = 0u;
    size_t tail = 0u;
    uint32_t start = (uint32_t)cfg->start_cell_b * A + cfg->start_cell_a;
    seen[start] = 1u;
    queue[tail++] = start;
    bool out = false;
    double wx = 0.0;
    double wy = 0.0;
    while (head < tail && !out) {
        uint32_t c = queue[head++];
        int64_t x = c % A;
        int64_t y = c / A;
        static const int dx[4] = {1, -1, 0, 0};
        static const int dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4 && !out; k++) {
            int64_t nx = x + dx[k];
            int64_t ny = y + dy[k];
            wx = ox + ((double)nx + 0.5) * cell;
            wy = oy + ((double)ny + 0.5) * cell;
            if (nx < 0 || ny < 0 || nx >= (int64_t)A || ny >= (int64_t)B) {
                out = true; /* a cell at the grid's edge, and the robot fits beyond it */
                break;
            }
            uint32_t nc = (uint32_t)ny * A + (uint32_t)nx;
            if (seen[nc] || wall[nc] || !room_disc_free(room, wx, wy, params.body_radius_m)) {
                continue;
            }
            seen[nc] = 1u;
            queue[tail++] = nc;
            out = wx < room->min_x || wx > room->max_x || wy < room->min_y || wy > room->max_y;
        }
    }
    free(wall);
    free(seen);
    free(queue);
    if (!out) {
        return 0;
    }
    char who[1100];
    if (o->has_start) {
        snprintf(who, sizeof who, "--start %g %g", sc->sx, sc->sy);
    } else if (room->start_line != 0u) {
        snprintf(who, sizeof who, "%s:%u: start pose (%g, %g)", o->room, room->start_line, sc->sx,
                 sc->sy);
    } else {
        snprintf(who, sizeof who, "%s: start pose (%g, %g)", o->room, sc->sx, sc->sy);
    }
    /* A building map often has a doorway out of its image: the run goes on, warned, and a
     * crop (whose edges are walls) closes it. A room file says where every wall is. */
    bool map = room->occ != NULL;
    fprintf(stderr,
            "host_sim: %s%s: the %s is not closed: the robot (radius %g m) can drive out of it "
            "through a gap, as far as (%.2f, %.2f), beyond its walls (%.2f .. %.2f, %.2f .. "
            "%.2f m); %s\n",
            map ? "warning: " : "", who, map ? "map" : "room", params.body_radius_m, wx, wy,
            room->min_x, room->max_x, room->min_y, room->max_y,
            map ? "--crop closes it" : "close the gap");
    return map ? 0 : EXIT_USAGE;
}

/* The firmware's configuration, and what the report says from it. 0, or EXIT_USAGE. */
static int choose_config(options_t *o, scenario_t *sc)
{
    if (build_config(o, &sc->room, sc->sx, sc->sy, sc->sth, &sc->cfg) != 0) {
        return EXIT_USAGE;
    }
    /* One source of truth: what the report says is what the firmware runs with. */
    o->cell_mm = sc->cfg.cell_um / 1000.0;
    o->explore = sc->cfg.explore_mode;
    return 0;
}

/* The robot as built matches the firmware's nominal configuration; the error levels make
 * the real one differ. The sensors beyond the paper's are fitted when asked for. */
static void build_params(const options_t *o, const slam_config_t *cfg, sim_params_t *p)
{
    sim_params_default(p);
    p->wheel_diameter_m = cfg->wheel_diameter_left_um * 1e-6;
    p->wheel_base_m = cfg->wheel_base_um * 1e-6;
    p->counts_per_rev = cfg->encoder_counts_per_rev;
    p->top_speed_mps = cfg->top_speed_mm_s * 1e-3;
    p->sonar_x_m = cfg->mount_x_um * 1e-6;
    p->sonar_y_m = cfg->mount_y_um * 1e-6;
    p->servo_pulse_0_us = cfg->servo_pulse_0deg_us;
    p->servo_pulse_180_us = cfg->servo_pulse_180deg_us;
    if (o->has_sonar1) {
        p->extra_sonars = 1u;
        p->extra_sonar[0] = (sim_sonar_mount_t){o->sonar1_x, o->sonar1_y, o->sonar1_deg, -1};
    }
    p->bumps = o->bumpers ? 2u : 0u; /* front left, front right */
}

/* The simulated robot in the room, at the start pose chosen. 0, or EXIT_USAGE. */
static int build_world(const options_t *o, scenario_t *sc)
{
    build_params(o, &sc->cfg, &sc->params);
    /* The world starts the robot at the room's start pose: the one chosen above. */
    sc->room.start_x = sc->sx;
    sc->room.start_y = sc->sy;
    sc->room.start_th = sc->sth;
    const char *bad_param = NULL;
    if (sim_params_check(&sc->params, &sc->errors, &bad_param) != 0) {
        fprintf(stderr, "host_sim: the simulated robot refuses %s\n", bad_param);
        return EXIT_USAGE;
    }
    sc->sim = sim_create(&sc->room, &sc->params, &sc->errors, o->seed);
    if (sc->sim == NULL) {
        fprintf(stderr, "host_sim: the robot does not fit at the start pose (%g, %g)\n", sc->sx,
                sc->sy);
        return EXIT_USAGE;
    }
    return 0;
}

int scenario_load(options_t *o, scenario_t *sc)
{
    char err[1024];
    if (room_load(&sc->room, o->room, o->has_crop ? &o->crop : NULL, err, sizeof err) != 0) {
        fprintf(stderr, "host_sim: %s\n", err);
        return EXIT_USAGE;
    }
    int rc = choose_start(o, sc);
    if (rc == 0) {
        rc = choose_errors(o, &sc->errors);
    }
    if (rc == 0) {
        rc = choose_config(o, sc);
    }
    if (rc == 0) {
        rc = check_closed(o, sc);
    }
    if (rc == 0 && o->commands != NULL) {
        rc = commands_load(o->commands, &sc->commands);
    }
    if (rc == 0) {
        rc = build_world(o, sc);
    }
    return rc;
}

void scenario_free(scenario_t *sc)
{
    sim_destroy(sc->sim);
    sc->sim = NULL;
    room_free(&sc->room);
    commands_free(&sc->commands);
}
