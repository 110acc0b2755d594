/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The simulated world of the host backend: a room, a differential-drive robot with its
 * encoders and motors, an SG90-like servo and an HC-SR04-like sonar, on a virtual clock.
 *
 * The host backend (hal_host.c) implements every call of hal/hal.h against one attached
 * `sim_t`, faking the wire: encoder counters, echo pulse widths, servo pulses, motor duty.
 * The firmware above it is the robot's, unchanged.
 *
 * Everything is deterministic for a seed: the same room, parameters, seed and firmware
 * give the same run bit for bit. Units here are SI (metres, seconds, radians); this is
 * host code and uses double.
 */
#ifndef HOST_SIM_H
#define HOST_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* ---- rooms --------------------------------------------------------------------------- */

typedef struct {
    double x1, y1, x2, y2;
} room_segment_t;

typedef struct {
    double cx, cy, r;
} room_circle_t;

/** A room: vector geometry (segments and circles) and/or a raster of occupied pixels. */
typedef struct {
    room_segment_t *segs;  /**< walls, box and polygon edges */
    size_t nsegs;
    room_circle_t *circles;
    size_t ncircles;
    uint8_t *occ;          /**< raster rooms (ROS maps): 1 = occupied pixel, row 0 at the bottom */
    uint32_t occ_w, occ_h; /**< raster size in pixels */
    double occ_res;        /**< raster pixel size, m */
    double occ_x0, occ_y0; /**< world position of the raster's lower-left corner, m */
    double min_x, min_y, max_x, max_y; /**< bounding box of all geometry, m */
    double start_x, start_y, start_th; /**< start pose (m, m, rad) */
    bool has_start;        /**< the file gave a start pose (ROS maps do not) */
} room_t;

/** A crop of a building map, in metres of the map's frame. */
typedef struct {
    double x, y, w, h;
} room_crop_t;

/**
 * Load a room: a `.room` text file (DESIGN.md §4) or a ROS map `.yaml` with its image.
 * @param crop  for a ROS map, the part to keep (NULL: all of it); ignored for .room files
 * @param err   out: on failure "FILE:LINE: what is wrong" (or "FILE: ...")
 * @return 0, or -1 with err set and @p r untouched
 */
int room_load(room_t *r, const char *path, const room_crop_t *crop, char *err, size_t errlen);

/** Free what room_load() allocated. */
void room_free(room_t *r);

/**
 * Distance along a ray to the first obstacle surface.
 * @param max_m           give up beyond this distance
 * @param cos_incidence   out (may be NULL): |cos| of the angle between the ray and the
 *                        surface normal at the hit (1 = head-on, 0 = grazing)
 * @return the distance in m, or a value > max_m when nothing is hit within max_m
 */
double room_ray(const room_t *r, double x, double y, double dir, double max_m,
                double *cos_incidence);

/** Whether a disc of radius r_m at (x, y) touches no obstacle. */
bool room_disc_free(const room_t *r, double x, double y, double r_m);

/**
 * A free start pose for a room without one: the free point nearest the middle of the room
 * with at least clearance_m to every obstacle, facing +x.
 * @return 0, or -1 when no such point exists
 */
int room_find_start(const room_t *r, double clearance_m, double *x, double *y, double *th);

/**
 * Ground truth at a grid's geometry: out[b·A + a] = 1 when any obstacle boundary passes
 * through cell (a, b), else 0 (DESIGN.md §5).
 * @param origin_x, origin_y  world position of the lower-left corner of cell (0, 0), m
 */
void room_rasterize(const room_t *r, double origin_x, double origin_y, double cell_m,
                    uint32_t a_cells, uint32_t b_cells, uint8_t *out);

/* ---- the simulated robot ------------------------------------------------------------- */

/** The robot as built. Defaults: sim_params_default(). */
typedef struct {
    double wheel_diameter_m;   /**< nominal; 0.065 */
    double wheel_base_m;       /**< nominal; 0.130 */
    double counts_per_rev;     /**< encoder counts per wheel turn; 700 */
    double top_speed_mps;      /**< wheel speed at full duty; 0.3 */
    double motor_tau_s;        /**< first-order motor time constant; 0.08 */
    double body_radius_m;      /**< collision disc around the axle centre; 0.09 */
    double sonar_x_m;          /**< servo axis ahead of the axle centre; 0.05 */
    double sonar_y_m;          /**< servo axis to the left; 0 */
    double servo_s_per_60deg;  /**< SG90 slew: 0.1 s per 60° */
    double servo_pulse_0_us;   /**< servo pulse at 0°: 500 */
    double servo_pulse_180_us; /**< servo pulse at 180°: 2500 */
    double sonar_cone_deg;     /**< full beam width; 15 */
    double sonar_min_m;        /**< 0.02 */
    double sonar_max_m;        /**< 4.0 */
    double sonar_timeout_us;   /**< 38000 */
    double sound_mps;          /**< 343 */
} sim_params_t;

/** Error sources, each with a level; sim_errors_ideal() turns all off (--ideal). */
typedef struct {
    double wheel_ratio_ed;   /**< E_d: actual right/left wheel diameter; 1.0 = none */
    double wheel_base_eb;    /**< E_b: actual/nominal wheel base; 1.0 = none */
    double slip_per_mps2;    /**< wheel slip fraction per m/s² of wheel acceleration */
    double wheel_noise;      /**< relative random error of each wheel's travel per tick */
    double sonar_noise_m;    /**< standard deviation of the range noise */
    double sonar_dropout;    /**< probability that a ping gets no echo */
    double sonar_ghost;      /**< probability of a ghost echo at a random range */
    double grazing_deg;      /**< beyond this incidence within 1 m the echo is lost; 0 = off */
} sim_errors_t;

void sim_params_default(sim_params_t *p);
void sim_errors_default(sim_errors_t *e); /**< the realistic levels of the default scenario */
void sim_errors_ideal(sim_errors_t *e);   /**< every error source off */

/** What the world knows that the robot does not. */
typedef struct {
    double x, y, th;          /**< true pose of the axle centre, m and rad */
    double servo_deg;         /**< where the servo actually is */
    uint32_t collisions;      /**< times the robot ran into something and was stopped */
    uint64_t time_us;         /**< virtual time since sim_init() */
    uint64_t ticks;           /**< control ticks run */
} sim_truth_t;

/** The pose and sonar geometry of the last ping, for logs. */
typedef struct {
    double x, y, th;          /**< true pose at the ping */
    double servo_deg;         /**< actual servo angle at the ping */
    double true_range_m;      /**< geometric distance to the nearest surface in the cone */
} sim_ping_t;

typedef struct sim sim_t;

/**
 * Create a world: the robot at the room's start pose, motors off, servo at 90°.
 * @param seed  the random stream of every error source
 * @return NULL when out of memory
 */
sim_t *sim_create(const room_t *room, const sim_params_t *p, const sim_errors_t *e,
                  uint64_t seed);
void sim_destroy(sim_t *s);

/** The true state now. */
sim_truth_t sim_truth(const sim_t *s);

/** The true pose and beam of the most recent ping. */
sim_ping_t sim_last_ping(const sim_t *s);

/* ---- the host backend ---------------------------------------------------------------- */

/** Attach the world the HAL functions act on (exactly one at a time). */
void hal_host_attach(sim_t *s);

/**
 * One control period: run the tick callback registered with hal_tick_start() at the
 * current virtual time (the firmware reads sensors and sets outputs), then advance the
 * world by HAL_TICK_PERIOD_US (motors, servo, sonar flight, collisions).
 */
void hal_host_step(void);

/**
 * Record what the firmware saw at the HAL in every tick from now on, as a trace a replay
 * HAL can play back on another machine (format in hal/host/README or trace.h). NULL stops.
 */
void hal_host_trace(FILE *f);

/** Telemetry: bytes the firmware wrote to the UART go to this file (NULL: discarded). */
void hal_host_uart_sink(FILE *f);

#endif /* HOST_SIM_H */
