/**
 * @file limits.h
 * @brief Every fixed limit of the firmware's modules in one place: the sizes
 *        of their fixed arrays (no heap) and the ranges their inputs are
 *        validated against. Checked at compile time where a relation between
 *        them must hold (#error, as NASA cFE's platform configuration does).
 *
 * A build may override the array sizes marked "overridable" on the compiler
 * command line (-DGG_PF_MAX=1000); the checks below then reject an
 * inconsistent choice before any code is compiled.
 */
#ifndef GGINS_LIMITS_H
#define GGINS_LIMITS_H

/* ---- geometry (geo.h) ---- */
/** No geodetic conversion within this distance of the Earth's centre, m. */
#define GG_GEO_R_MIN_M 1.0e5L

/* ---- latitude (gmap.h tiles, mmukf.h state) ---- */
/** |geodetic latitude| a tile or a filter state may reach, rad (89 deg:
 *  the local-level frame's east axis is undefined at the pole). */
#define GG_LIM_LAT_MAX_RAD 1.5533430342749532

/* ---- map-matching UKF (mmukf.h) ---- */
#define GG_LIM_MM_H_MIN_M (-1.0e5) /**< state height, m */
#define GG_LIM_MM_H_MAX_M 1.0e6

#endif /* GGINS_LIMITS_H */
