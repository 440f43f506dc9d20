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
 *  - a regular grid of gravitation disturbance vectors over the x-z plane of
 *    the 2-D system (nodes x0 + i dx, z0 + j dz; values dG_x, dG_z), bilinear
 *    interpolation; outside the grid its contribution is zero and
 *    GG_GMODEL_OUTSIDE_GRID is reported.
 */
#ifndef GGINS_GMODEL_H
#define GGINS_GMODEL_H

#include <stdint.h>

#include "ggins/real.h"
#include "ggins/status.h"

#define GG_GMODEL_MAX_DEGREE 8
#define GG_GMODEL_MAX_PM 32      /**< programmed point-mass anomalies */
#define GG_GMODEL_GRID_MAX 512   /**< anomaly grid nodes (nx * nz); 8 KiB of doubles */

/** gg_gmodel_eval flags */
#define GG_GMODEL_OUTSIDE_GRID 0x01u

typedef struct {
    int32_t nx;                            /**< nodes along x (0: no grid; else >= 2) */
    int32_t nz;                            /**< nodes along z (>= 2 with nx) */
    gg_real_t x0_m;                        /**< first node, m */
    gg_real_t z0_m;
    gg_real_t dx_m;                        /**< node spacing, m (> 0) */
    gg_real_t dz_m;
    double dg[GG_GMODEL_GRID_MAX][2];      /**< node (i, j) at index j * nx + i: dG_x, dG_z, m/s^2 */
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
    gg_gmodel_config_t cfg;
    int initialized;
} gg_gmodel_t;

gg_status_t gg_gmodel_init(gg_gmodel_t *st, const gg_gmodel_config_t *cfg);

/** Gravitation at r (m) -> g (m/s^2). GG_ERR_RANGE inside 0.5 a or within
 *  1 m of a programmed point mass. flags (may be NULL): GG_GMODEL_*. */
gg_status_t gg_gmodel_eval(const gg_gmodel_t *st, const gg_real_t r[3], gg_real_t g[3],
                           uint32_t *flags);

#endif /* GGINS_GMODEL_H */
