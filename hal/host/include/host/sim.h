/* SPDX-License-Identifier: MIT */
/**
 * @file
 * The simulated world of the host backend: a room, a differential-drive robot with its
 * encoders and motors, SG90-like servos and HC-SR04-like sonars (one of each by default:
 * the paper's), optional bump switches, on a virtual clock.
 *
 * The host backend (hal_host.c) implements every call of hal/hal.h against one attached
 * `sim_t`, faking the wire: encoder counters, echo pulse widths, servo pulses, motor duty.
 * The firmware above it is the robot's, unchanged.
 *
 * Everything is deterministic for a seed: the same room, parameters, error levels, seed
 * and firmware give the same run bit for bit (on one build: x87 and SSE arithmetic may
 * differ in the last bit). Units here are SI (metres, seconds, radians unless a name says
 * degrees); this is host code and uses double. The world frame is the room's: x right,
 * y up, angles counter-clockwise from +x. hal/host/README.md describes the models.
 *
 * Nothing here is thread-safe; one thread drives the world.
 */
#ifndef HOST_SIM_H
#define HOST_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hal/hal.h"

/* ---- rooms --------------------------------------------------------------------------- */

/** The robot body radius the start pose of a room file is checked against, m. */
#define ROOM_BODY_RADIUS_M ((double)0.09)

/** A wall's free end is round, of this radius, m: a panel 10 mm thick (hal/host/README.md,
 *  Rooms). */
#define ROOM_WALL_END_M ((double)0.005)

/** Every coordinate of a room lies within this distance of the origin (10 km), m. */
#define ROOM_MAX_COORD_M 10000.0

/** A wall: a line segment, m. */
typedef struct {
    double x1, y1, x2, y2;
} room_segment_t;

/** A round obstacle (solid), m. */
typedef struct {
    double cx, cy, r;
} room_circle_t;

/** An axis-aligned rectangular obstacle (solid), m; its edges are also in room_t.segs. */
typedef struct {
    double x0, y0, x1, y1; /**< lower-left and upper-right corners */
} room_box_t;

/**
 * A room: vector geometry (segments and circles) and/or a raster of occupied pixels.
 *
 * Boxes and circles are solid: their inside is an obstacle. Walls and polygons are
 * outlines only (a `poly` may surround the robot as the room's outline or stand in the
 * room as an obstacle; the robot can never cross its edges either way). Outside a raster
 * is empty space.
 */
typedef struct {
    room_segment_t *segs; /**< walls, box and polygon edges */
    size_t nsegs;
    room_circle_t *circles;
    size_t ncircles;
    room_box_t *boxes; /**< the solid insides of `box` statements */
    size_t nboxes;
    uint8_t *occ;          /**< raster rooms (ROS maps): 1 = occupied pixel, row 0 at the bottom */
    uint8_t *occ_free;     /**< the same raster: 1 = known free pixel (p < free_thresh) */
    uint32_t occ_w, occ_h; /**< raster size in pixels */
    double occ_res;        /**< raster pixel size, m */
    double occ_x0, occ_y0; /**< world position of the raster's lower-left corner, m */
    double min_x, min_y, max_x, max_y; /**< bounding box of all geometry (occupied pixels
                                            for a raster), m */
    double start_x, start_y, start_th; /**< start pose (m, m, rad) */
    bool has_start;                    /**< the file gave a start pose (ROS maps do not) */
    unsigned start_line;               /**< the line of the file that gave it; 0 */
    struct room_index *index;          /**< the objects by place, for large rooms; NULL (private) */
} room_t;

/** A crop of a building map, in metres of the map's frame. */
typedef struct {
    double x, y, w, h; /**< lower-left corner and size; pixels whose centre lies inside are kept */
} room_crop_t;

/**
 * Load a room: a `.room` text file (DESIGN.md §4) or a ROS map `.yaml` (by its extension,
 * `.yaml` or `.yml`) with the PGM image it names (P5 or P2, 8-bit).
 *
 * A room file needs exactly one `start`, some geometry, and a start pose whose body disc
 * (ROOM_BODY_RADIUS_M) touches nothing. A ROS map gets occupied pixels by ROS map_server
 * rules: p = (maxval − v)/maxval (v/maxval with `negate: 1`), occupied when
 * p > occupied_thresh, known free when p < free_thresh; it has no start pose.
 *
 * Limits, each refused with a message: a room file of 64 MiB, a YAML of 1 MiB, an image of
 * 2^26 pixels or 128 MiB; coordinates within ±ROOM_MAX_COORD_M; pixels of 1 mm to 10 m.
 * A NUL byte in a text file is an error naming its line.
 *
 * @param crop  for a ROS map, the part to keep (NULL: all of it), whose edge pixels become
 *              occupied so the robot stays in it; a crop with a .room file is an error
 * @param err   out: on failure "FILE:LINE: what is wrong" (or "FILE: ...")
 * @return 0, or -1 with err set and @p r untouched
 */
int room_load(room_t *r, const char *path, const room_crop_t *crop, char *err, size_t errlen);

/**
 * room_load() of a `.room` text held in memory.
 * @param name  the file's name, for messages
 * @param text  @p len bytes (need not end in a NUL)
 */
int room_parse(room_t *r, const char *name, const char *text, size_t len, char *err, size_t errlen);

/**
 * room_load() of a ROS map whose YAML and image are held in memory (the YAML's `image`
 * key is checked, not opened).
 */
int room_parse_ros(room_t *r, const char *yaml_name, const char *yaml, size_t yaml_len,
                   const char *pgm_name, const char *pgm, size_t pgm_len, const room_crop_t *crop,
                   char *err, size_t errlen);

/** Free what room_load() allocated and zero the room. */
void room_free(room_t *r);

/**
 * Distance along a ray to the first obstacle surface. Vector rooms test every segment and
 * circle; rasters walk the pixels (grid DDA). A ray that starts inside a solid obstacle
 * or an occupied pixel hits at 0.
 * @param dir             direction of the ray, rad
 * @param max_m           give up beyond this distance
 * @param cos_incidence   out (may be NULL): |cos| of the angle between the ray and the
 *                        surface normal at the hit (1 = head-on, 0 = grazing). A raster's
 *                        normal is the occupancy gradient around the hit, so a staircase
 *                        of pixels reflects like the straight wall it stands for.
 * @return the distance in m, or a value > max_m when nothing is hit within max_m
 */
double room_ray(const room_t *r, double x, double y, double dir, double max_m,
                double *cos_incidence);

/**
 * Distance from a point to the nearest obstacle boundary (0 inside a solid obstacle or an
 * occupied pixel), looking no further than @p cap_m.
 * @return the distance in m, or @p cap_m when nothing is nearer
 */
double room_clearance(const room_t *r, double x, double y, double cap_m);

/** Whether a disc of radius r_m at (x, y) touches no obstacle (touching exactly is free). */
bool room_disc_free(const room_t *r, double x, double y, double r_m);

/**
 * Whether a point lies inside the room: rays from it toward 0°, 45°, ... 315° all meet an
 * obstacle (within twice the room's diagonal). A room may have doors; a point outside
 * every wall fails.
 * @param open_deg  out (may be NULL): when not, the first direction that meets nothing, deg
 */
bool room_encloses(const room_t *r, double x, double y, double *open_deg);

/**
 * A free start pose for a room without one: the point nearest the middle of the room's
 * bounding box, on a grid of the raster's pixel size (20 mm for vector rooms), with at
 * least clearance_m to every obstacle, enclosed (rays in eight directions all hit
 * something) and, for a raster, on a known free pixel; facing +x.
 * @return 0, or -1 when no such point exists (outputs untouched)
 */
int room_find_start(const room_t *r, double clearance_m, double *x, double *y, double *th);

/**
 * Ground truth at a grid's geometry: out[b·A + a] = 1 when any obstacle boundary passes
 * through cell (a, b), else 0 (DESIGN.md §5): segments (box and polygon edges too),
 * circle outlines, and for a raster every cell that overlaps an occupied pixel.
 * @param origin_x, origin_y  world position of the lower-left corner of cell (0, 0), m
 */
void room_rasterize(const room_t *r, double origin_x, double origin_y, double cell_m,
                    uint32_t a_cells, uint32_t b_cells, uint8_t *out);

/* ---- the simulated robot ------------------------------------------------------------- */

/** The most servos, sonars and bump switches a simulated robot carries. */
#define SIM_SERVOS_MAX 2u
#define SIM_SONARS_MAX 2u
#define SIM_BUMPS_MAX 4u

/**
 * Where a sonar other than the paper's sits on the robot: one row of the robot's sonar
 * instance table (sim_params_t.extra_sonar). The paper's, instance 0, turns on servo 0 at
 * (sonar_x_m, sonar_y_m).
 */
typedef struct {
    double x_m;     /**< the sensor (or the axis of the servo it turns on) ahead of the axle
                         centre */
    double y_m;     /**< to the left of it */
    double yaw_deg; /**< its beam from the heading, counter-clockwise (90: looking left),
                         with the servo it turns on at 90°; -360..360 */
    int32_t servo;  /**< the servo it turns on, or -1: fixed */
} sim_sonar_mount_t;

/** A bump switch: it closes while the body touches something within its arc. */
typedef struct {
    double from_deg; /**< the arc, counter-clockwise from the heading: from_deg .. to_deg, */
    double to_deg;   /**< -360 <= from_deg < to_deg <= 360 (the ends included) */
} sim_bump_t;

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
    double sonar_min_m;        /**< 0.02: nearer surfaces read as this */
    double sonar_max_m;        /**< 4.0: farther surfaces give no echo */
    double sonar_timeout_us;   /**< 38000 */
    double sound_mps;          /**< 343 */
    double sonar_ring_us;      /**< how long a ping's sound keeps bouncing between the sensor
                                    and the surface it echoed from: a trigger sooner than
                                    this after the last may read the last one's late echo;
                                    60000 (the HC-SR04 datasheet's measurement cycle);
                                    0 = never */
    /* The instance tables: the paper's servo and sonar (instance 0) always, the others and
       the bump switches only when asked for. Every servo and sonar is the same model
       (the fields above); the fault episodes of sim_errors_t act on instance 0 alone. */
    uint32_t servos;       /**< servos fitted, 1..SIM_SERVOS_MAX; 1 */
    uint32_t extra_sonars; /**< sonars fitted besides the paper's, 0..SIM_SONARS_MAX - 1;
                                0 */
    sim_sonar_mount_t extra_sonar[SIM_SONARS_MAX - 1u]; /**< sonar i + 1's mount; [0]: a fixed
                                    sensor on the left side looking left, (0, 0.06) at 90° */
    uint32_t bumps;                 /**< bump switches fitted, 0..SIM_BUMPS_MAX; 0 */
    sim_bump_t bump[SIM_BUMPS_MAX]; /**< switch i's arc: front left (0..90°), front right
                                    (-90..0°), back left, back right; two switches at the
                                    front both close for a touch straight ahead */
} sim_params_t;

/**
 * How much of what real HC-SR04s do at oblique incidence the sonar shows: three levels
 * from the spread of published measurements (hal/host/README.md names each source and
 * the figure taken from it). sim_errors_sonar() sets a level's sonar fields.
 */
typedef enum {
    SIM_SONAR_OPTIMISTIC = 0, /**< the kind end: a surface answers up to 45° at every range,
                                   and a ray beyond that is lost (the model before issue 28) */
    SIM_SONAR_TYPICAL,        /**< the middle of the sources: the limit narrows with range,
                                   and a ray beyond it reflects on (multipath) */
    SIM_SONAR_PESSIMISTIC,    /**< the lowest measured limits, multipath as typical */
    SIM_SONAR_LEVELS
} sim_sonar_level_t;

/** The level of sim_errors_default(). */
#define SIM_SONAR_DEFAULT SIM_SONAR_TYPICAL

/** Knots of a grazing curve at most. */
#define SIM_GRAZING_KNOTS 8u

/**
 * The incidence up to which a surface answers a ray, by the distance the sound has
 * travelled to it: straight lines between knots, flat before the first and after the last.
 * Incidence is the angle between the ray and the surface normal; every ray of the cone is
 * judged alone, so a flat surface turned by θ from the beam's axis answers while
 * θ − half the cone is within the limit.
 */
typedef struct {
    uint32_t n;                        /**< knots in use; 0: grazing_deg at every range */
    double range_m[SIM_GRAZING_KNOTS]; /**< ascending, m */
    double deg[SIM_GRAZING_KNOTS];     /**< the limit there, 0 < deg <= 90 */
} sim_grazing_curve_t;

/** Error sources, each with a level; sim_errors_ideal() turns all off (--ideal). */
typedef struct {
    double wheel_ratio_ed; /**< E_d: actual right/left wheel diameter (mean stays nominal);
                                1.0 = none */
    double wheel_base_eb;  /**< E_b: actual/nominal wheel base; 1.0 = none */
    double slip_per_mps2;  /**< wheel slip fraction per m/s² of wheel acceleration beyond
                                slip_free_mps2 (the ground moves that much less than the
                                wheel): traction holds for gentle accelerations and gives
                                way to hard ones */
    double slip_free_mps2; /**< wheel accelerations up to this roll without slipping */
    double wheel_noise;    /**< relative random error of each wheel's ground travel per tick
                                (one standard deviation) */
    double sonar_noise_m;  /**< standard deviation of the range noise */
    double sonar_dropout;  /**< probability that a ping gets no echo */
    double sonar_ghost;    /**< probability of a ghost echo at a random range */
    double grazing_deg;    /**< a ray hitting a surface beyond this incidence returns no
                                direct echo (at every range); 0 = off; grazing_curve
                                replaces it when it has knots */
    sim_grazing_curve_t grazing_curve; /**< the limit by range (n = 0: grazing_deg) */
    uint32_t multipath; /**< reflections a ray that met a surface beyond the limit may
                             make, mirror-like, before it reaches one that answers or
                             passes the receiver: the echo then reads half the path;
                             0 = none (the ray is lost, as at the optimistic level) */
    /* Faults of the wiring and the timing, each off (0) by default. An episode lasts
       0.5..3 s (uniform) and a new one may begin once it is over. */
    double echo_stuck_per_s;   /**< episodes a second in which the echo line sticks high: every
                                    ping in one times out (SIM_PING_STUCK) */
    double servo_lag;          /**< share of the servo's speed lost (0 none .. 0.95): it
                                    reaches each stop late, and the sweep pings early */
    double servo_stall_per_s;  /**< episodes a second in which the servo horn stalls where it
                                    is, whatever the pulse says */
    double tick_miss;          /**< probability that a control tick is lost: the world moves
                                    on 10 ms, the firmware does not run (an overrun) */
    double encoder_stop_per_s; /**< episodes a second in which one encoder (either, at random)
                                    stops counting: the counter holds, then goes on from there */
} sim_errors_t;

void sim_params_default(sim_params_t *p);
void sim_errors_default(sim_errors_t *e); /**< the realistic levels of the default scenario:
                                               an uncalibrated hobby robot */
void sim_errors_ideal(sim_errors_t *e);   /**< every error source off */

/**
 * Set the sonar's incidence limit and multipath (grazing_deg, grazing_curve, multipath)
 * to a level's; the other fields stay. An unknown level sets SIM_SONAR_DEFAULT's.
 */
void sim_errors_sonar(sim_errors_t *e, sim_sonar_level_t level);

/** The level's name ("optimistic", "typical", "pessimistic"); NULL for an unknown one. */
const char *sim_sonar_level_name(sim_sonar_level_t level);

/** The level of a name, or -1 for none. */
int sim_sonar_level_of(const char *name);

/**
 * Check parameters and error levels for sim_create().
 * @param field  out (may be NULL): on error the name of the first bad field ("p.motor_tau_s",
 *               "e.sonar_dropout", ...), a static string
 * @return 0, or -1 when a value is out of range or not finite
 */
int sim_params_check(const sim_params_t *p, const sim_errors_t *e, const char **field);

/** What the world knows that the robot does not. */
typedef struct {
    double x, y, th;       /**< true pose of the axle centre, m and rad (th in (-pi, pi]) */
    double servo_deg;      /**< where servo 0 (the sweep's) actually is */
    double wheel_mps[2];   /**< wheel surface speeds (left, right), m/s, before slip */
    uint32_t collisions;   /**< times the robot ran into something and was stopped */
    uint64_t ticks_missed; /**< control ticks lost to the tick_miss fault */
    bool contact;          /**< the body touches an obstacle now */
    uint64_t time_us;      /**< virtual time since sim_create() */
    uint64_t ticks;        /**< control periods run (sim_step() calls) */
} sim_truth_t;

/** What became of a ping. */
typedef enum {
    SIM_PING_NONE = 0,  /**< no ping yet */
    SIM_PING_ECHO,      /**< a real echo from the nearest echoing surface in the cone */
    SIM_PING_GHOST,     /**< a ghost echo at a random range */
    SIM_PING_DROPOUT,   /**< the echo was lost at random: timeout */
    SIM_PING_GRAZING,   /**< surfaces in range, all at grazing incidence: timeout */
    SIM_PING_NOTHING,   /**< no surface within sonar_max_m in the cone: timeout */
    SIM_PING_LATE,      /**< the late echo of the previous ping, read as this one's */
    SIM_PING_STUCK,     /**< the echo line was stuck high (a fault episode): timeout */
    SIM_PING_MULTIPATH, /**< an echo by a mirror path: the nearest surface was met beyond the
                             incidence it answers at, the reflected sound came back from
                             another; the range is half the path */
    SIM_PING_KINDS
} sim_ping_kind_t;

/** The pose and sonar geometry of the last ping, for logs. */
typedef struct {
    double x, y, th;     /**< true pose at the ping */
    double servo_deg;    /**< actual angle of the servo it turns on at the ping; a fixed
                              sonar's is the angle a servo would point it the same way
                              at (90 - yaw_deg) */
    double bearing;      /**< world direction of the beam axis, rad */
    double true_range_m; /**< distance from the servo axis to the nearest surface in
                              the cone (any incidence); -1 when none within sonar_max_m */
    double range_m;      /**< the range the echo stands for (noise included); 0 without */
    uint32_t echo_us;    /**< the echo width reported; 0 without an echo */
    uint64_t time_us;    /**< virtual time of the trigger */
    sim_ping_kind_t kind;
} sim_ping_t;

typedef struct sim sim_t;

/**
 * Create a world: the robot at the room's start pose, motors off, servos at 90°.
 * The room is borrowed: it must outlive the world.
 * @param seed  the random stream of every error source
 * @return NULL when out of memory, when sim_params_check() refuses @p p or @p e, or when
 *         the body disc (p->body_radius_m) at the start pose touches an obstacle
 */
sim_t *sim_create(const room_t *room, const sim_params_t *p, const sim_errors_t *e, uint64_t seed);
void sim_destroy(sim_t *s);

/** The true state now. */
sim_truth_t sim_truth(const sim_t *s);

/** The true pose and beam of sonar 0's most recent ping. */
sim_ping_t sim_last_ping(const sim_t *s);

/** The same of any sonar; kind SIM_PING_NONE (and all 0) for no ping or no such sonar. */
sim_ping_t sim_last_ping_on(const sim_t *s, uint8_t sonar);

/** Sonar 0's pings since sim_create() by what became of them: counts[kind], SIM_PING_NONE
 *  unused. */
void sim_ping_counts(const sim_t *s, uint32_t counts[SIM_PING_KINDS]);

/**
 * Put the robot somewhere else (tests, scenarios, UMBmark's experimenter carrying it back
 * to the start): wheels stopped, contact cleared; the encoders keep their counts, as when
 * a person lifts the robot and sets it down.
 * @return 0, or -1 when its body disc there touches an obstacle (nothing changes)
 */
int sim_place(sim_t *s, double x, double y, double th);

/* The wires: what the HAL calls. Times are the world's current virtual time. */

/** Motor duty, -HAL_DUTY_MAX..HAL_DUTY_MAX (clamped): target wheel speed duty/1000 · top speed. */
void sim_motor_set(sim_t *s, hal_wheel_t wheel, int16_t duty);

/** The duty in force (after clamping). */
int16_t sim_motor_duty(const sim_t *s, hal_wheel_t wheel);

/** The 16-bit encoder counter: true wheel rotation in counts, wrapping. */
uint16_t sim_encoder_count(const sim_t *s, hal_wheel_t wheel);

/** Servos, sonars and bump switches fitted (sim_params_t.servos, 1 + extra_sonars, bumps). */
uint8_t sim_servo_count(const sim_t *s);
uint8_t sim_sonar_count(const sim_t *s);
uint8_t sim_bump_count(const sim_t *s);

/**
 * Servo command (clamped to 400..2600 µs); the servo slews toward it in sim_step().
 * @retval HAL_OK / HAL_EINVAL (no such servo: nothing changes)
 */
int sim_servo_set_pulse_on(sim_t *s, uint8_t servo, uint16_t pulse_us);

/** The pulse in force of a servo; 0 for no such servo. */
uint16_t sim_servo_pulse_on(const sim_t *s, uint8_t servo);

/** sim_servo_set_pulse_on() and sim_servo_pulse_on() of servo 0, the sweep's. */
void sim_servo_set_pulse(sim_t *s, uint16_t pulse_us);
uint16_t sim_servo_pulse(const sim_t *s);

/**
 * Ping a sonar now, from its mount, along the beam of where its servo actually is (a fixed
 * one along its yaw). The cone is cast at once; the result comes back through
 * sim_sonar_poll_on() after its time of flight (or the timeout). Each sonar has its own
 * ping under way and its own random stream, and hears only its own sound.
 * @retval HAL_OK      the ping is out
 * @retval HAL_EBUSY   the sonar's previous ping's echo or timeout has not come yet
 * @retval HAL_EINVAL  no such sonar
 */
int sim_sonar_trigger_on(sim_t *s, uint8_t sonar);

/**
 * As hal_sonar_poll(): ECHO/TIMEOUT once the virtual time has reached it, once; then IDLE.
 * @return a hal_sonar_status_t, or HAL_EINVAL for no such sonar
 */
int sim_sonar_poll_on(sim_t *s, uint8_t sonar, uint32_t *echo_us);

/** sim_sonar_trigger_on() and sim_sonar_poll_on() of sonar 0, the paper's. */
int sim_sonar_trigger(sim_t *s);
hal_sonar_status_t sim_sonar_poll(sim_t *s, uint32_t *echo_us);

/**
 * As hal_bump_read(): a switch is pressed while the body is in contact (sim_truth_t.contact)
 * with something within its arc (rays from the axle centre across the arc meet a surface
 * within the body radius and a switch's travel).
 * @retval HAL_OK / HAL_EINVAL (no such switch, or pressed NULL) / HAL_ENOSYS (none fitted)
 */
int sim_bump_read(const sim_t *s, uint8_t bump, bool *pressed);

/**
 * Advance the world by one control period, HAL_TICK_PERIOD_US: motors, wheels, encoders,
 * the pose with its collisions, the servo, the fault episodes, the clock. O(1) away from
 * obstacles.
 */
void sim_step(sim_t *s);

/**
 * Whether the control tick of this period is lost (the tick_miss fault); counted in
 * sim_truth_t.ticks_missed. Called once a period, before the tick would run.
 */
bool sim_tick_lost(sim_t *s);

/** Whether the world loses ticks at all (tick_miss > 0): the HAL asks once, at attach. */
bool sim_ticks_lost(const sim_t *s);

/** The ticks lost so far, sim_truth_t.ticks_missed alone: the HAL's overrun count, asked for
 *  every period. */
uint64_t sim_ticks_missed(const sim_t *s);

/* ---- the host backend ---------------------------------------------------------------- */

/**
 * Attach the world the HAL functions act on (exactly one at a time; NULL detaches). This
 * is a power-up: the tick callback is forgotten and the clock of hal_time_us() restarts
 * at hal_init(). Storage, the UART sink and the trace stay.
 */
void hal_host_attach(sim_t *s);

/**
 * One control period: run the tick callback registered with hal_tick_start() at the
 * current virtual time (the firmware reads sensors and sets outputs), then advance the
 * world by HAL_TICK_PERIOD_US (sim_step()). Without a callback only the world advances.
 */
void hal_host_step(void);

/**
 * Record what the firmware saw at the HAL in every tick from now on, as a HAL trace
 * (hal_common/trace.h) a replay HAL can play back on another machine.
 *
 * The caller writes the header first (trace_write_header() with the firmware's
 * configuration, which the HAL does not know); the HAL writes one tick line per callback
 * run by hal_host_step(). hal_host_trace(NULL), or a call with another file, writes the
 * end line to the file being recorded and stops; closing the file is the caller's.
 * Encoder reads outside a tick (robot_init()) see the counters of the first tick that
 * follows, as long as the world does not step in between.
 */
void hal_host_trace(FILE *f);

/** Telemetry: bytes the firmware wrote to the UART go to this file (NULL: discarded). */
void hal_host_uart_sink(FILE *f);

/** Bytes the UART can hold for hal_uart_read() before it drops them. */
#define HAL_HOST_UART_RX_BYTES 4096u

/**
 * Bytes arriving at the UART (commands to the robot): hal_uart_read() hands them out in
 * order. Returns how many were taken; the rest are dropped, as a full receive buffer
 * drops them.
 */
size_t hal_host_uart_receive(const uint8_t *data, size_t len);

/** The largest storage slot the host offers, bytes. */
#define HAL_HOST_STORAGE_MAX (256u * 1024u)

/**
 * Resize and erase both storage slots (default: 128 KiB, an MCU's flash sector, enough
 * for a 160 x 160 grid); at most HAL_HOST_STORAGE_MAX. Call before robot_init().
 */
void hal_host_storage_resize(size_t bytes);

/**
 * The bytes of a storage slot, as a flash dump or the Linux robot's slot file would hold
 * them (HAL_STORAGE_SLOTS slots of hal_storage_size() bytes); NULL for no such slot.
 */
const uint8_t *hal_host_storage_slot(uint8_t slot);

#endif /* HOST_SIM_H */
