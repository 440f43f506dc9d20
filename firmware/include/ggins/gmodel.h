/**
 * @file gmodel.h
 * @brief Onboard gravitation model for the conventional navigation mode:
 *        zonal harmonics (point mass, J2, J4, ...) about the z (polar) axis.
 *
 *   V(r, u) = GM/r [1 - sum_n J_n (a/r)^n P_n(u)],  u = z/r = sin(geocentric latitude)
 *   G = grad V = dV/dr|_u r^ + dV/du|_r (z^ - u r^)/r
 *   dV/dr|_u = -GM/r^2 [1 - sum_n (n+1) J_n (a/r)^n P_n(u)]
 *   dV/du|_r = -GM/r   sum_n J_n (a/r)^n P_n'(u)
 * with Bonnet's recursion n P_n = (2n-1) u P_{n-1} - (n-1) P_{n-2} and
 * P_n' = n (u P_n - P_{n-1}) / (u^2 - 1) avoided at the poles through
 * P_n' = u P_{n-1}' + n P_{n-1}. With all J_n = 0 it is the point mass.
 * Gravitation only (no centrifugal term); frame: Earth-centred, z polar.
 * The coefficients come from the host (e.g. the WGS-84 normal field's
 * J2..J8); the firmware holds no model of its own.
 *
 * "Programmed" anomalies (Rubenstein & Winter, "programming the anomalies in
 * the guidance computer": point masses and an anomaly grid), added to the
 * zonal field when configured:
 *  - up to GG_GMODEL_MAX_PM buried point masses: G += -gm_i (r - p_i)/|r - p_i|^3
 *    (negative gm_i for a mass deficit);
 *  - an anomaly grid over the flight plane (x-z) in polar coordinates about
 *    the Earth's centre: nodes at angle theta_i = th0 + i dth (rad, measured
 *    in the x-z plane from the unit vector e0 = (c0, s0), positive from x
 *    towards z) and radius rho_k = rho0 + k drho (m, the in-plane distance
 *    sqrt(x^2 + z^2)); each node holds the disturbance's tangential and
 *    radial components (dG_t along t^ = (-z, x)/rho, i.e. towards increasing
 *    theta - north on a north flight; dG_r along r^ = (x, z)/rho, outward),
 *    bilinear interpolation in (theta, rho), then
 *      dG_x = dG_r x/rho - dG_t z/rho,  dG_z = dG_r z/rho + dG_t x/rho.
 *    A constant-height arc is a line of constant rho, so a grid a few nodes
 *    deep in rho covers it (an x-z grid would need a square of nodes).
 *    theta = atan2(z', x') with (x', z') = (c0 x + s0 z, -s0 x + c0 z), by
 *    the firmware's gg_atan2 (ggmath.h, no libm); only
 *    |theta| <= 45 deg (x' > 0, |z'| <= x') can be inside a grid.
 *    Outside the grid its contribution is zero and GG_GMODEL_OUTSIDE_GRID is
 *    reported.
 * The model's state holds no copy of the configuration (the grid is large):
 * gg_gmodel_init validates a configuration, gg_gmodel_eval reads the same
 * configuration, which the caller keeps unchanged in between (nav2d keeps it
 * in its own configuration copy).
 */
#ifndef GGINS_GMODEL_H
#define GGINS_GMODEL_H

#include <stdint.h>

#include "ggins/limits.h"
#include "ggins/real.h"
#include "ggins/status.h"

/* array sizes GG_GMODEL_MAX_DEGREE, GG_GMODEL_MAX_PM, GG_GMODEL_GRID_MAX: limits.h */

/** gg_gmodel_eval flags */
#define GG_GMODEL_OUTSIDE_GRID 0x01u

typedef struct {
    int32_t n_th;                          /**< nodes in angle (0: no grid; else >= 2) */
    int32_t n_rho;                         /**< nodes in radius (>= 2 with n_th) */
    gg_real_t c0;                          /**< e0 = (c0, s0): direction of theta = 0 in the */
    gg_real_t s0;                          /**< x-z plane (|e0| = 1 within 1e-9) */
    gg_real_t th0_rad;                     /**< first node's angle from e0, rad (|.| < pi/4) */
    gg_real_t dth_rad;                     /**< node spacing in angle, rad (> 0) */
    gg_real_t rho0_m;                      /**< first node's radius, m */
    gg_real_t drho_m;                      /**< node spacing in radius, m (> 0) */
    double dg[GG_GMODEL_GRID_MAX][2];      /**< node (i, k) at index k * n_th + i: dG_t, dG_r, m/s^2 */
} gg_gmodel_grid_t;

typedef struct {
    gg_real_t gm;                          /**< m^3/s^2 (> 0) */
    gg_real_t a_m;                         /**< reference radius, m (> 0) */
    gg_real_t j[GG_GMODEL_MAX_DEGREE + 1]; /**< J_n, n = 2..max (j[0], j[1] must be 0) */
    int32_t n_pm;                          /**< programmed point masses in use (0..GG_GMODEL_MAX_PM) */
    gg_real_t pm_pos[GG_GMODEL_MAX_PM][3]; /**< their positions, m */
    gg_real_t pm_gm[GG_GMODEL_MAX_PM];     /**< their G*mass, m^3/s^2 (signed) */
    gg_gmodel_grid_t grid;                 /**< programmed anomaly grid (grid.nx = 0: none) */
} gg_gmodel_config_t;

typedef struct {
    int initialized;                       /**< a configuration was validated */
} gg_gmodel_t;

/** Validate cfg (GG_ERR_CONFIG / GG_ERR_RANGE); on success *st is marked
 *  initialized. cfg must then stay unchanged while it is evaluated. */
gg_status_t gg_gmodel_init(gg_gmodel_t *st, const gg_gmodel_config_t *cfg);

/** Gravitation of the configuration cfg (the one gg_gmodel_init validated)
 *  at r (m) -> g (m/s^2). GG_ERR_RANGE inside 0.5 a or within 1 m of a
 *  programmed point mass. flags (may be NULL): GG_GMODEL_*. */
gg_status_t gg_gmodel_eval(const gg_gmodel_t *st, const gg_gmodel_config_t *cfg,
                           const gg_real_t r[3], gg_real_t g[3], uint32_t *flags);

#endif /* GGINS_GMODEL_H */
