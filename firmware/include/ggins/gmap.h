/**
 * @file gmap.h
 * @brief Onboard gravity-gradient map: one fixed-size tile of the gradient
 *        tensor on a geodetic latitude/longitude grid at one altitude, and its
 *        interpolation (value and gradient w.r.t. position).
 *
 * Shared by the map-matching UKF (Gao et al.) and the cold-atom
 * particle filter (Phillips et al., which needs Gamma_DD at candidate positions).
 *
 * Conventions (docs/design.md): Gamma_jk = dG_j/dx_k (s^-2), G the
 * gravitation (no centrifugal term), frame NED (north, east, down) at the
 * node's geodetic latitude/longitude on the WGS-84 ellipsoid. The six
 * independent components are stored in the order of Gao et al. eq. (31):
 *   0 NN, 1 EE, 2 DD, 3 NE, 4 ND, 5 ED   (GG_GMAP_C_*).
 * A tile holds either the total gravitation gradient (flags = 0) or the
 * anomaly, i.e. total minus the WGS-84 normal gravitation (GG_GMAP_ANOMALY);
 * the filter uses the TOTAL field (the gradiometer measures it). Its kind:
 * the whole tensor (the map UKF's map), or Gamma_DD alone (GG_GMAP_GZZ_ONLY:
 * the five other components and their height derivatives zero; the map of a
 * single-axis gradiometer, the cold-atom particle filter's). The map storage
 * (hal.h) serves each aid the tiles of its kind.
 *
 * Nodes: i = 0..nlat-1 (north), j = 0..nlon-1 (east), at
 *   lat_i = lat0 + i dlat,  lon_j = lon0 + j dlon,  height h0,
 * stored at node[i * nlon + j][k]: k = 0..5 the six components at h0 (s^-2),
 * k = 6..11 their derivatives w.r.t. ellipsoidal height at h0 (s^-2/m,
 * d/dh along the ellipsoid normal, i.e. -d/dDown at fixed lat/lon).
 *
 * Interpolation (gg_gmap_eval): horizontally, bicubic LAGRANGE on the 4x4
 * nodes around the point (tensor product of 4-point cubic Lagrange
 * polynomials in lat and lon; the stencil is shifted inward at the tile edge):
 * exact for every polynomial of degree <= 3 in lat times degree <= 3 in lon,
 * error O(d^4) in the node spacing d (C0 across cells). Vertically, first
 * order Taylor: value(h) = value(h0) + (h - h0) d/dh, valid for
 * |h - h0| <= h_range_m (error ~ (h-h0)^2/2 d2Gamma/dh2; measured in
 * docs/map-matching.md). The gradient output is the exact derivative of that
 * interpolant: d/dlat (s^-2/rad), d/dlon (s^-2/rad), d/dh (s^-2/m).
 *
 * Memory: GG_GMAP_MAX_NODES nodes x 12 doubles = 2500 x 96 B = 240000 B
 * (234.4 KiB) per tile, e.g. 50 x 50 nodes (a 245 km square at 0.045 deg).
 * Longer voyages page tiles (the host uploads the next one with gg_gmap_load).
 *
 * Binary tile format ("GGMAP001", little-endian, IEEE-754 doubles), written
 * by `ggins gmap` and read by gg_gmap_load:
 *   offset  0  char[8]  magic "GGMAP001"
 *           8  int32    nlat        12 int32  nlon
 *          16  uint32   flags (GG_GMAP_ANOMALY | GG_GMAP_GZZ_ONLY)
 *                               20 int32  nmax (SH degree, metadata)
 *          24  double   lat0_rad    32 double lon0_rad
 *          40  double   dlat_rad    48 double dlon_rad
 *          56  double   h0_m        64 double h_range_m
 *          72  double   noise_s2 (database noise sigma added, s^-2, metadata)
 *          80  uint64   seed (metadata)
 *          88  double   node[nlat*nlon][12]
 *   total 88 + 96 nlat nlon bytes.
 */
#ifndef GGINS_GMAP_H
#define GGINS_GMAP_H

#include <stddef.h>
#include <stdint.h>

#include "ggins/limits.h"
#include "ggins/real.h"
#include "ggins/status.h"

/* GG_GMAP_MAX_NODES (nodes of one tile): limits.h */
#define GG_GMAP_NCOMP 6
#define GG_GMAP_NVAL 12
#define GG_GMAP_HEADER_BYTES 88u

/* Component indices (Gao et al. eq. 31 order) and mask bits. */
#define GG_GMAP_C_NN 0
#define GG_GMAP_C_EE 1
#define GG_GMAP_C_DD 2
#define GG_GMAP_C_NE 3
#define GG_GMAP_C_ND 4
#define GG_GMAP_C_ED 5
#define GG_GMAP_MASK_ALL 0x3Fu
#define GG_GMAP_MASK_DD (1u << GG_GMAP_C_DD)

/** Mask flag for gg_gmap_eval: accept heights beyond h_range_m and continue
 *  the first-order height term linearly (error grows as (h - h0)^2; for
 *  filters whose sigma points or particles spread beyond the band). */
#define GG_GMAP_H_EXTRAPOLATE (1u << 8)

/** Plausibility of a tile (gg_gmap_init / gg_gmap_load refuse beyond it):
 *  |node value| <= GG_GMAP_VALUE_MAX (s^-2 and s^-2/m; the Earth's gradient is
 *  ~3e-6 s^-2, 1e-2 is far beyond any field) and spacings >= GG_GMAP_SPACING_MIN_RAD
 *  (6 mm): finite nodes on too fine a grid (1e228 s^-2 over 1e-130 rad, found
 *  by fuzzing) made the interpolant's derivatives overflow to Inf. With both,
 *  every value and derivative gg_gmap_eval returns is finite. */
#define GG_GMAP_VALUE_MAX 1.0e-2
#define GG_GMAP_SPACING_MIN_RAD 1.0e-9

/** Tile flag: values are total minus the WGS-84 normal gravitation gradient. */
#define GG_GMAP_ANOMALY 0x1u
/** Tile flag: the tile carries Gamma_DD and its height derivative alone (every
 *  other value zero; gg_gmap_init / gg_gmap_load refuse a tile that says so and
 *  is not). */
#define GG_GMAP_GZZ_ONLY 0x2u
/** The flags a tile may carry. */
#define GG_GMAP_FLAGS_KNOWN (GG_GMAP_ANOMALY | GG_GMAP_GZZ_ONLY)

/** Tile kinds an aid asks the map storage for (hal.h): the whole tensor (tiles
 *  without GG_GMAP_GZZ_ONLY) or Gamma_DD alone (tiles with it). */
#define GG_GMAP_KIND_TENSOR 0u
#define GG_GMAP_KIND_GZZ 1u

typedef struct {
    int32_t nlat;          /**< nodes along latitude (>= 4) */
    int32_t nlon;          /**< nodes along longitude (>= 4), nlat * nlon <= GG_GMAP_MAX_NODES */
    uint32_t flags;        /**< GG_GMAP_ANOMALY, GG_GMAP_GZZ_ONLY or 0 */
    int32_t nmax;          /**< SH degree of the source model (metadata) */
    double lat0_rad;       /**< south-west node, geodetic latitude, rad (|lat| < 89 deg) */
    double lon0_rad;       /**< south-west node, longitude, rad, in [-pi, pi]; the tile spans
                                *   (nlon - 1) dlon_rad < 2 pi eastward and may cross +-pi (a
                                *   point's longitude is taken within pi of the tile's centre) */
    double dlat_rad;       /**< spacing, rad (> 0) */
    double dlon_rad;       /**< spacing, rad (> 0) */
    double h0_m;           /**< altitude of the grid above the ellipsoid, m */
    double h_range_m;      /**< accepted |h - h0|, m (>= 0) */
    double noise_s2;       /**< database noise sigma added by the host, s^-2 (metadata) */
    uint64_t seed;         /**< noise seed (metadata) */
    double node[GG_GMAP_MAX_NODES][GG_GMAP_NVAL]; /**< see file comment */
} gg_gmap_tile_t;

typedef struct {
    gg_gmap_tile_t tile;
    int initialized;
} gg_gmap_t;

/** One interpolated sample. */
typedef struct {
    gg_real_t gamma[GG_GMAP_NCOMP];       /**< NED components, s^-2 (GG_GMAP_C_* order) */
    gg_real_t dgamma[GG_GMAP_NCOMP][3];   /**< d/dlat (s^-2/rad), d/dlon (s^-2/rad), d/dh (s^-2/m) */
} gg_gmap_sample_t;

/** Validate and copy a tile. GG_ERR_CONFIG on bad geometry, an unknown flag or
 *  a GG_GMAP_GZZ_ONLY tile with another value non-zero, GG_ERR_NONFINITE on a
 *  non-finite node value (state untouched on error). */
gg_status_t gg_gmap_init(gg_gmap_t *st, const gg_gmap_tile_t *tile);

/** Parse the binary tile format above from a byte buffer (len bytes) into st.
 *  GG_ERR_CONFIG on a bad magic, size, geometry or flag, or a GG_GMAP_GZZ_ONLY
 *  tile with another value non-zero; GG_ERR_NONFINITE on a non-finite value or
 *  one beyond GG_GMAP_VALUE_MAX; state untouched on error. */
gg_status_t gg_gmap_load(gg_gmap_t *st, const uint8_t *buf, size_t len);

/** Interpolate at geodetic (lat, lon) rad, height h m. mask selects the
 *  components computed (others set to 0; GG_GMAP_MASK_DD for the particle
 *  filter); want_grad != 0 fills dgamma. GG_ERR_RANGE outside the tile or
 *  beyond h_range_m (unless mask has GG_GMAP_H_EXTRAPOLATE; |h - h0| <= 1e5 m
 *  always), GG_ERR_NONFINITE for NaN/Inf input, GG_ERR_NOT_INIT
 *  before init (out untouched on error). */
gg_status_t gg_gmap_eval(const gg_gmap_t *st, gg_real_t lat, gg_real_t lon, gg_real_t h,
                         uint32_t mask, int want_grad, gg_gmap_sample_t *out);

/** The longitude offset lon - lon0_rad of a point from the tile's first column, rad, taken
 *  across +-pi where the tile spans the antimeridian (within pi of the tile's centre): the
 *  offset gg_gmap_eval interpolates at, for the map storage's choice among tiles (hal.h).
 *  GG_ERR_NONFINITE for a NaN/Inf longitude, GG_ERR_NOT_INIT before init. */
gg_status_t gg_gmap_lon_offset(const gg_gmap_t *st, double lon_rad, double *dlon_rad);

/** Expand the six components (GG_GMAP_C_* order) into the symmetric 3x3
 *  tensor m[j][k]. */
gg_status_t gg_gmap_to_matrix(const gg_real_t g6[GG_GMAP_NCOMP], gg_real_t m[3][3]);

#endif /* GGINS_GMAP_H */
