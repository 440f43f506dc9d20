/**
 * @file hal.h
 * @brief Hardware abstraction the navigation task runs on.
 *
 * The firmware holds no implementation of it: hal_sim/ implements it over
 * LCM for host-in-the-loop runs; a target board implements it over its
 * drivers; unit tests implement it with mocks. It is an operations table
 * (no link-time globals), passed to the task by the caller.
 */
#ifndef GGINS_HAL_H
#define GGINS_HAL_H

#include <stdint.h>
#include "ggins/frame.h"
#include "ggins/gmap.h"
#include "ggins/status.h"

struct gg_nav3d_output_s; /* nav3d.h */

/** Onboard map storage: the tiles of the gradient maps (gmap.h) the computer
 *  carries (flash, a file system), paged by the navigation task as it flies.
 *  An aid asks for the tile of its kind (GG_GMAP_KIND_TENSOR: the map UKF;
 *  GG_GMAP_KIND_GZZ: the cold-atom particle filter) covering its estimated
 *  position at each measurement and reads it through gg_gmap_eval. A map may
 *  hold several height layers of the same area (tiles of one grid at different
 *  h0_m): the storage chooses, among the tiles of that kind covering (lat, lon),
 *  those whose height band |h - h0_m| <= h_range_m holds h, and among them the
 *  one whose edge is farthest from the point (equal margins: the nearest h0_m);
 *  when no covering tile holds h, the covering tile with the farthest edge (the
 *  aid then sees h outside the tile's band and refuses the tile). */
typedef struct {
    void *ctx; /**< implementation's own state */
    /** The tile of the kind asked for covering geodetic (lat, lon), rad, at
     *  ellipsoidal height h_m: GG_OK with *tile set (valid until the next call),
     *  GG_ERR_RANGE when no tile of that kind covers the point horizontally. */
    gg_status_t (*tile_at)(void *ctx, uint32_t kind, double lat_rad, double lon_rad, double h_m,
                           const gg_gmap_t **tile);
} gg_hal_map_t;

typedef struct {
    void *ctx; /**< implementation's own state */
    /** Deliver the next sensor frame. GG_OK with *frame filled, or
     *  GG_ERR_NO_DATA when none is ready. */
    gg_status_t (*read_frame)(void *ctx, gg_frame_t *frame);
    /** Publish one navigation output. */
    gg_status_t (*write_output)(void *ctx, const gg_nav_output_t *out);
    /** Free-running 32-bit cycle counter (target: DWT CYCCNT; host: a
     *  monotonic clock in ns). Differences are taken modulo 2^32. May be NULL. */
    uint32_t (*cycle_count)(void *ctx);
    /** Counter ticks per second (for deadline checks). */
    uint32_t cycles_per_second;
    /** Publish one 3-D navigation output (gg_nav3d_output_t, nav3d.h); NULL
     *  when the implementation serves the 2-D task only. */
    gg_status_t (*write_output3d)(void *ctx, const struct gg_nav3d_output_s *out);
    /** Onboard map storage (the 3-D task's map aid); NULL when the computer
     *  carries no map. */
    const gg_hal_map_t *map;
} gg_hal_t;

#endif /* GGINS_HAL_H */
