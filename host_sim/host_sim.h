/* SPDX-License-Identifier: MIT */
/**
 * @file
 * Internal interfaces of the host_sim program: map files, scoring against ground truth.
 *
 * Maps here are the grid's arrays: a×b cells, index b·a_cells + a, cell (0, 0) at the
 * grid origin (its lower-left corner, in metres of the world frame).
 */
#ifndef HOST_SIM_HOST_SIM_H
#define HOST_SIM_HOST_SIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/** The geometry shared by every map of a run. */
typedef struct {
    uint32_t a;       /**< cells along x */
    uint32_t b;       /**< cells along y */
    double cell_m;    /**< cell side */
    double origin_x;  /**< world x of the lower-left corner of cell (0, 0), m */
    double origin_y;
} map_geom_t;

/** How a map is scored (DESIGN.md §5). */
typedef struct {
    uint32_t mapped;      /**< occupied cells in the map */
    uint32_t true_pos;    /**< of which within one cell of a truth-occupied cell */
    uint32_t observable;  /**< truth-occupied cells within rc of a sonar position */
    uint32_t matched;     /**< of which within one cell of a mapped cell */
    double precision;
    double recall;
    double f1;
} score_t;

/**
 * Score a map: a cell is occupied when non-zero. Precision = true_pos / mapped, recall =
 * matched / observable (Chebyshev distance <= 1 both ways), F1 their harmonic mean
 * (0 when either is 0).
 */
void score_map(const map_geom_t *g, const uint8_t *map, const uint8_t *truth,
               const uint8_t *observable, score_t *out);

/** Mark every cell whose centre lies within radius_m of (x, y). */
void mark_disc(const map_geom_t *g, uint8_t *marks, double x, double y, double radius_m);

/**
 * Write a map as a binary PGM (row 0 = the top = the largest y) and its ROS map_server
 * YAML next to it: DIR/NAME.pgm and DIR/NAME.yaml. A cell value v of full scale max is
 * drawn as grey 255 - v·255/max (0 = white, max = black).
 * @return 0, or -1 with a message on stderr
 */
int write_map(const char *dir, const char *name, const map_geom_t *g, const uint8_t *cells,
              uint8_t max, double occupied_thresh, double free_thresh);

/**
 * Append v with exactly @p decimals digits after the point (rounded half away from zero)
 * to @p out, then @p sep if it is not 0; returns the new end. What printf's "%.Nf" writes
 * for |v| < 9e8, a tenth of its cost: the logs hold tens of thousands of numbers.
 */
char *fmt_fixed(char *out, double v, int decimals, char sep);

/** Open DIR/NAME for writing; NULL with a message on stderr when it fails. */
FILE *open_out(const char *dir, const char *name);

/** Close a file opened by open_out(); -1 with a message when the write failed. */
int close_out(FILE *f, const char *dir, const char *name);

/** Create a directory and its parents; -1 with a message on stderr. */
int make_dirs(const char *path);

#endif /* HOST_SIM_HOST_SIM_H */
