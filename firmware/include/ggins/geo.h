/**
 * @file geo.h
 * @brief WGS-84 geometry of the firmware: the ellipsoid's constants, ECEF <->
 *        geodetic coordinates, the local north-east-down frame, the meridian
 *        and prime-vertical radii, and normal gravity.
 *
 * Constants: NIMA TR8350.2 (3rd ed., 2000), Table 3.1 (defining: a, 1/f,
 * omega) and Table 3.3 / 3.4 (derived: the equatorial normal gravity, the
 * Somigliana constant k, m = omega^2 a^2 b / GM); the first eccentricity
 * squared e^2 = f (2 - f) from the defining flattening (GG_WGS84_E2) and as
 * Table 3.3 tabulates it to 12 digits (GG_WGS84_E2_TAB, 2.0e-13 relative
 * below the exact value; the filters' radii and normal gravity use it).
 * Standard gravity g0 = 9.80665 m/s^2 (CGPM 1901) sets the Schuler frequency
 * of the filters' error models (w_s^2 = g0 / R).
 *
 * Precision: the navigation path (nav3d) in gg_real_t (ECEF <-> geodetic,
 * local frame); the aiding filters' linearisations (aid_mmukf, pf) in double
 * (radii, normal gravity), their state's type.
 *
 * ECEF -> geodetic: Bowring's iteration on the parametric latitude beta
 * (tan beta = (1 - f) tan phi), carried as the vector (cos beta, sin beta),
 * GG_GEO_BOWRING_ITER times, without trigonometric functions (error
 * < 1e-15 rad, 1e-9 m below 1e5 m altitude); no point within
 * GG_GEO_R_MIN_M of the centre (GG_ERR_RANGE).
 * Radii (Gao et al. eqs. 9-10): R_N = a / W, R_M = R_N (1 - e^2) / W^2,
 * W^2 = 1 - e^2 sin^2 lat. Normal gravity: Somigliana's closed formula
 * (TR8350.2 eq. 4-1) and its height series to second order (eq. 4-3).
 */
#ifndef GGINS_GEO_H
#define GGINS_GEO_H

#include "ggins/real.h"
#include "ggins/status.h"

/** WGS-84 defining constants (TR8350.2 Table 3.1). */
#define GG_WGS84_A_M 6378137.0L              /**< semi-major axis, m */
#define GG_WGS84_INV_F 298.257223563L        /**< inverse flattening 1/f */
#define GG_WGS84_F (1.0L / GG_WGS84_INV_F)   /**< flattening */
#define GG_WGS84_GM_M3PS2 3.986004418e14L    /**< GM incl. the atmosphere, m^3/s^2 */
#define GG_WGS84_OMEGA_IE 7.292115e-5L       /**< Earth rotation rate, rad/s */

/** First eccentricity squared from the flattening, e^2 = f (2 - f). */
#define GG_WGS84_E2 (GG_WGS84_F * (2.0L - GG_WGS84_F))
/** e^2 as TR8350.2 Table 3.3 tabulates it (12 digits). */
#define GG_WGS84_E2_TAB 6.69437999014e-3L

/** Normal gravity (TR8350.2 Tables 3.3-3.4). */
#define GG_WGS84_GAMMA_E_MPS2 9.7803253359L  /**< at the equator, m/s^2 */
#define GG_WGS84_SOMIGLIANA_K 0.00193185265241L
#define GG_WGS84_M 0.00344978650684L         /**< omega^2 a^2 b / GM */

/** Standard gravity, m/s^2 (the filters' Schuler frequency). */
#define GG_G0_STD_MPS2 9.80665L

/** Bowring iterations of gg_geo_ecef_to_geodetic. */
#define GG_GEO_BOWRING_ITER 4U

/** Geodetic latitude, longitude (rad, (-pi, pi]) and height (m) of an ECEF
 *  point. GG_ERR_NONFINITE, GG_ERR_RANGE within GG_GEO_R_MIN_M of the
 *  centre (outputs untouched). */
gg_status_t gg_geo_ecef_to_geodetic(const gg_real_t r_e[3], gg_real_t *lat, gg_real_t *lon,
                                    gg_real_t *h);

/** ECEF point of geodetic latitude, longitude (rad) and height (m). */
gg_status_t gg_geo_geodetic_to_ecef(gg_real_t lat, gg_real_t lon, gg_real_t h, gg_real_t r_e[3]);

/** Geodetic height and the local frame at an ECEF point: the rows of C_e_n
 *  are the north, east and down axes in ECEF (the up unit vector, the
 *  ellipsoid normal, is minus the third row). Errors as
 *  gg_geo_ecef_to_geodetic. */
gg_status_t gg_geo_local_frame(const gg_real_t r_e[3], gg_real_t *h, gg_real_t c_e_n[3][3]);

/** Meridian (*rm) and prime-vertical (*rn) radii of curvature, m, at the
 *  geodetic latitude whose sine is sin_lat (|sin_lat| <= 1). */
void gg_geo_radii(double sin_lat, double *rm, double *rn);

/** Normal gravity, m/s^2 (positive down), at geodetic latitude lat (rad) and
 *  height h (m). */
gg_status_t gg_geo_normal_gravity(double lat, double h, double *g);

#endif /* GGINS_GEO_H */
