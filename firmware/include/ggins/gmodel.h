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
 */
#ifndef GGINS_GMODEL_H
#define GGINS_GMODEL_H

#include "ggins/real.h"
#include "ggins/status.h"

#define GG_GMODEL_MAX_DEGREE 8

typedef struct {
    gg_real_t gm;                          /**< m^3/s^2 (> 0) */
    gg_real_t a_m;                         /**< reference radius, m (> 0) */
    gg_real_t j[GG_GMODEL_MAX_DEGREE + 1]; /**< J_n, n = 2..max (j[0], j[1] must be 0) */
} gg_gmodel_config_t;

typedef struct {
    gg_gmodel_config_t cfg;
    int initialized;
} gg_gmodel_t;

gg_status_t gg_gmodel_init(gg_gmodel_t *st, const gg_gmodel_config_t *cfg);

/** Gravitation at r (m) -> g (m/s^2). GG_ERR_RANGE inside 0.5 a. */
gg_status_t gg_gmodel_eval(const gg_gmodel_t *st, const gg_real_t r[3], gg_real_t g[3]);

#endif /* GGINS_GMODEL_H */
