/* Onboard gravity-gradient map tile and its interpolation (see gmap.h). */
#include "ggins/gmap.h"

#include <string.h>

#include "ggins/ggmath.h"

/* tolerance of the tile-edge test, in grid cells */
#define GMAP_EDGE_EPS 1.0e-9L

static int geometry_ok(int32_t nlat, int32_t nlon, double lat0, double lon0, double dlat,
                       double dlon, double h0, double hr)
{
    if ((nlat < 4) || (nlon < 4) || (nlat > GG_GMAP_MAX_NODES) || (nlon > GG_GMAP_MAX_NODES)) {
        return 0;
    }
    if (((int64_t)nlat * (int64_t)nlon) > (int64_t)GG_GMAP_MAX_NODES) {
        return 0;
    }
    if (!GG_ISFINITE(lat0) || !GG_ISFINITE(lon0) || !GG_ISFINITE(dlat) || !GG_ISFINITE(dlon) ||
        !GG_ISFINITE(h0) || !GG_ISFINITE(hr)) {
        return 0;
    }
    if ((dlat < GG_GMAP_SPACING_MIN_RAD) || (dlon < GG_GMAP_SPACING_MIN_RAD) || (hr < 0.0) || (hr > 1.0e5) || (h0 < -1.2e4) ||
        (h0 > 1.0e6)) {
        return 0;
    }
    const int32_t nlat1 = nlat - 1;
    const int32_t nlon1 = nlon - 1;
    const double lat1 = lat0 + (dlat * (double)nlat1);
    const double lon1 = lon0 + (dlon * (double)nlon1);
    if ((lat0 < -GG_LIM_LAT_MAX_RAD) || (lat1 > GG_LIM_LAT_MAX_RAD) || (lon0 < -(double)GG_PI) ||
        (lon0 > (double)GG_PI) || (!((lon1 - lon0) < (2.0 * (double)GG_PI)))) {
        return 0;
    }
    return 1;
}

/* lon - lon0 of a tile, rad, taken across +-pi where the point lies on the tile's side of
 * it: the offset brought within pi of the tile's centre (a tile may span the antimeridian;
 * its span is below 2 pi). A point whose offset needs no wrap keeps lon - lon0 exactly. */
static gg_real_t gmap_dlon(const gg_gmap_tile_t *t, gg_real_t lon)
{
    const int32_t nlon1 = t->nlon - 1;
    const gg_real_t half = 0.5L * (gg_real_t)t->dlon_rad * (gg_real_t)nlon1;
    const gg_real_t two_pi = 2.0L * (gg_real_t)GG_PI;
    gg_real_t d = lon - (gg_real_t)t->lon0_rad;
    if (d < (half - (gg_real_t)GG_PI)) {
        d += two_pi;
    } else if (d >= (half + (gg_real_t)GG_PI)) {
        d -= two_pi;
    } else {
        /* within pi of the centre: as it is */
    }
    return d;
}

gg_status_t gg_gmap_lon_offset(const gg_gmap_t *st, double lon_rad, double *dlon_rad)
{
    if ((st == NULL) || (dlon_rad == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(lon_rad)) {
        return GG_ERR_NONFINITE;
    }
    *dlon_rad = (double)gmap_dlon(&st->tile, (gg_real_t)lon_rad);
    return GG_OK;
}

/* value k of a node may be non-zero in a tile of these flags: every value, or
 * with GG_GMAP_GZZ_ONLY the DD component and its height derivative alone */
static int value_allowed(uint32_t flags, size_t k, double v)
{
    int ok = 1;
    if (((flags & GG_GMAP_GZZ_ONLY) != 0u) && (k != (size_t)GG_GMAP_C_DD) &&
        (k != ((size_t)GG_GMAP_NCOMP + (size_t)GG_GMAP_C_DD)) && (v != 0.0)) {
        ok = 0;
    }
    return ok;
}

static int nodes_of_kind(const double (*node)[GG_GMAP_NVAL], int32_t n, uint32_t flags)
{
    for (int32_t i = 0; i < n; ++i) {
        for (size_t k = 0u; k < (size_t)GG_GMAP_NVAL; ++k) {
            if (value_allowed(flags, k, node[i][k]) == 0) {
                return 0;
            }
        }
    }
    return 1;
}

static int nodes_finite(const double (*node)[GG_GMAP_NVAL], int32_t n)
{
    for (int32_t i = 0; i < n; ++i) {
        for (int k = 0; k < GG_GMAP_NVAL; ++k) {
            if (!GG_ISFINITE(node[i][k]) || (node[i][k] > GG_GMAP_VALUE_MAX) ||
                (node[i][k] < -GG_GMAP_VALUE_MAX)) {
                return 0;
            }
        }
    }
    return 1;
}

gg_status_t gg_gmap_init(gg_gmap_t *st, const gg_gmap_tile_t *tile)
{
    if ((st == NULL) || (tile == NULL)) {
        return GG_ERR_NULL;
    }
    if ((geometry_ok(tile->nlat, tile->nlon, tile->lat0_rad, tile->lon0_rad, tile->dlat_rad,
                     tile->dlon_rad, tile->h0_m, tile->h_range_m) == 0) ||
        ((tile->flags & ~GG_GMAP_FLAGS_KNOWN) != 0u)) {
        return GG_ERR_CONFIG;
    }
    const int32_t n = tile->nlat * tile->nlon;
    if (nodes_finite(tile->node, n) == 0) {
        return GG_ERR_NONFINITE;
    }
    if (nodes_of_kind(tile->node, n, tile->flags) == 0) {
        return GG_ERR_CONFIG;
    }
    if (&st->tile != tile) { /* in-place init (host filled st->tile) needs no copy */
        (void)memcpy(&st->tile, tile, sizeof st->tile);
    }
    st->initialized = 1;
    return GG_OK;
}

/* little-endian readers (the format is little-endian; so are x86-64 and the M7) */
static uint32_t rd_u32(const uint8_t *p, size_t off)
{
    return (uint32_t)p[off] | ((uint32_t)p[off + 1u] << 8) | ((uint32_t)p[off + 2u] << 16) |
           ((uint32_t)p[off + 3u] << 24);
}

static uint64_t rd_u64(const uint8_t *p, size_t off)
{
    return (uint64_t)rd_u32(p, off) | ((uint64_t)rd_u32(p, off + 4u) << 32);
}

static double rd_f64(const uint8_t *p, size_t off)
{
    const uint64_t u = rd_u64(p, off);
    double d;
    /* MISRA 21.15 deviation: the tile format carries IEEE-754 binary64 values;
     * reinterpreting their bit pattern is the purpose of this function. */
    /* cppcheck-suppress misra-c2012-21.15 */
    (void)memcpy(&d, &u, sizeof d);
    return d;
}

static int32_t rd_i32(const uint8_t *p, size_t off)
{
    const uint32_t u = rd_u32(p, off);
    int32_t i;
    if (u <= 0x7FFFFFFFu) {
        i = (int32_t)u;
    } else {
        const uint32_t m = 0xFFFFFFFFu - u;
        i = -((int32_t)m) - 1;
    }
    return i;
}

gg_status_t gg_gmap_load(gg_gmap_t *st, const uint8_t *buf, size_t len)
{
    if ((st == NULL) || (buf == NULL)) {
        return GG_ERR_NULL;
    }
    static const uint8_t kMagic[8] = {0x47u, 0x47u, 0x4Du, 0x41u, 0x50u, 0x30u, 0x30u, 0x31u}; /* GGMAP001 */
    if ((len < GG_GMAP_HEADER_BYTES) || (memcmp(buf, kMagic, sizeof kMagic) != 0)) {
        return GG_ERR_CONFIG;
    }
    const int32_t nlat = rd_i32(buf, 8u);
    const int32_t nlon = rd_i32(buf, 12u);
    const uint32_t flags = rd_u32(buf, 16u);
    const int32_t nmax = rd_i32(buf, 20u);
    const double lat0 = rd_f64(buf, 24u);
    const double lon0 = rd_f64(buf, 32u);
    const double dlat = rd_f64(buf, 40u);
    const double dlon = rd_f64(buf, 48u);
    const double h0 = rd_f64(buf, 56u);
    const double hr = rd_f64(buf, 64u);
    const double noise = rd_f64(buf, 72u);
    const uint64_t seed = rd_u64(buf, 80u);
    if ((geometry_ok(nlat, nlon, lat0, lon0, dlat, dlon, h0, hr) == 0) ||
        ((flags & ~GG_GMAP_FLAGS_KNOWN) != 0u) || !GG_ISFINITE(noise)) {
        return GG_ERR_CONFIG;
    }
    const size_t n = (size_t)nlat * (size_t)nlon;
    if (len != (GG_GMAP_HEADER_BYTES + (n * (size_t)GG_GMAP_NVAL * 8u))) {
        return GG_ERR_CONFIG;
    }
    /* validate every value before touching the state */
    for (size_t i = 0; i < (n * (size_t)GG_GMAP_NVAL); ++i) {
        const double v = rd_f64(buf, GG_GMAP_HEADER_BYTES + (8u * i));
        if (!GG_ISFINITE(v) || (v > GG_GMAP_VALUE_MAX) || (v < -GG_GMAP_VALUE_MAX)) {
            return GG_ERR_NONFINITE;
        }
        if (value_allowed(flags, i % (size_t)GG_GMAP_NVAL, v) == 0) {
            return GG_ERR_CONFIG;
        }
    }
    gg_gmap_tile_t *t = &st->tile;
    t->nlat = nlat;
    t->nlon = nlon;
    t->flags = flags;
    t->nmax = nmax;
    t->lat0_rad = lat0;
    t->lon0_rad = lon0;
    t->dlat_rad = dlat;
    t->dlon_rad = dlon;
    t->h0_m = h0;
    t->h_range_m = hr;
    t->noise_s2 = noise;
    t->seed = seed;
    for (size_t i = 0; i < n; ++i) {
        for (size_t k = 0; k < (size_t)GG_GMAP_NVAL; ++k) {
            t->node[i][k] = rd_f64(buf, GG_GMAP_HEADER_BYTES + (8u * ((i * (size_t)GG_GMAP_NVAL) + k)));
        }
    }
    st->initialized = 1;
    return GG_OK;
}

/* 4-point cubic Lagrange weights at local coordinate u (nodes at 0, 1, 2, 3)
 * and their derivatives d/du. */
static void lagrange4(gg_real_t u, gg_real_t w[4], gg_real_t dw[4])
{
    const gg_real_t a = u;
    const gg_real_t b = u - 1.0L;
    const gg_real_t c = u - 2.0L;
    const gg_real_t d = u - 3.0L;
    w[0] = -(b * c * d) / 6.0L;
    w[1] = (a * c * d) / 2.0L;
    w[2] = -(a * b * d) / 2.0L;
    w[3] = (a * b * c) / 6.0L;
    dw[0] = -((c * d) + (b * d) + (b * c)) / 6.0L;
    dw[1] = ((c * d) + (a * d) + (a * c)) / 2.0L;
    dw[2] = -((b * d) + (a * d) + (a * b)) / 2.0L;
    dw[3] = ((b * c) + (a * c) + (a * b)) / 6.0L;
}

/* Stencil start and local coordinate for grid coordinate t in [0, n-1]. */
static void stencil(gg_real_t t, int32_t n, int32_t *i0, gg_real_t *u)
{
    int32_t i = (int32_t)t; /* t > -1: truncation is floor or 0 */
    if (i > (n - 2)) {
        i = n - 2;
    }
    int32_t s = i - 1;
    if (s < 0) {
        s = 0;
    }
    if (s > (n - 4)) {
        s = n - 4;
    }
    *i0 = s;
    *u = t - (gg_real_t)s;
}

gg_status_t gg_gmap_eval(const gg_gmap_t *st, gg_real_t lat, gg_real_t lon, gg_real_t h,
                         uint32_t mask, int want_grad, gg_gmap_sample_t *out)
{
    if ((st == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (!GG_ISFINITE(lat) || !GG_ISFINITE(lon) || !GG_ISFINITE(h)) {
        return GG_ERR_NONFINITE;
    }
    const gg_gmap_tile_t *t = &st->tile;
    const gg_real_t tl = (lat - (gg_real_t)t->lat0_rad) / (gg_real_t)t->dlat_rad;
    const gg_real_t tn = gmap_dlon(t, lon) / (gg_real_t)t->dlon_rad;
    const gg_real_t dh = h - (gg_real_t)t->h0_m;
    /* MISRA 12.2: false positive on the constant mask macro (shift by 8 of an unsigned) */
    /* cppcheck-suppress misra-c2012-12.2 */
    const gg_real_t hr = ((mask & GG_GMAP_H_EXTRAPOLATE) != 0u) ? 1.0e5L : (gg_real_t)t->h_range_m;
    const int32_t nlat1 = t->nlat - 1;
    const int32_t nlon1 = t->nlon - 1;
    /* edges inclusive, with 1e-9 cell of slack for the rounding of lat0 + i dlat */
    if ((tl < -GMAP_EDGE_EPS) || (tl > ((gg_real_t)nlat1 + GMAP_EDGE_EPS)) ||
        (tn < -GMAP_EDGE_EPS) || (tn > ((gg_real_t)nlon1 + GMAP_EDGE_EPS)) || (dh > hr) || (dh < -hr)) {
        return GG_ERR_RANGE;
    }
    int32_t i0;
    int32_t j0;
    gg_real_t u;
    gg_real_t v;
    stencil(tl, t->nlat, &i0, &u);
    stencil(tn, t->nlon, &j0, &v);
    gg_real_t wu[4];
    gg_real_t dwu[4];
    gg_real_t wv[4];
    gg_real_t dwv[4];
    lagrange4(u, wu, dwu);
    lagrange4(v, wv, dwv);
    gg_gmap_sample_t s;
    (void)memset(&s, 0, sizeof s);
    const gg_real_t inv_dlat = 1.0L / (gg_real_t)t->dlat_rad;
    const gg_real_t inv_dlon = 1.0L / (gg_real_t)t->dlon_rad;
    for (int c = 0; c < GG_GMAP_NCOMP; ++c) {
        if ((mask & (1u << (uint32_t)c)) == 0u) {
            continue;
        }
        gg_real_t val = 0.0L;
        gg_real_t d_u = 0.0L;
        gg_real_t d_v = 0.0L;
        gg_real_t d_h = 0.0L;
        for (int a = 0; a < 4; ++a) {
            gg_real_t row = 0.0L;
            gg_real_t row_dv = 0.0L;
            gg_real_t row_h = 0.0L;
            const int32_t base = ((i0 + a) * t->nlon) + j0;
            for (int b = 0; b < 4; ++b) {
                const double *nd = t->node[base + b];
                const gg_real_t f = (gg_real_t)nd[c] + (dh * (gg_real_t)nd[c + GG_GMAP_NCOMP]);
                row += wv[b] * f;
                row_dv += dwv[b] * f;
                row_h += wv[b] * (gg_real_t)nd[c + GG_GMAP_NCOMP];
            }
            val += wu[a] * row;
            d_u += dwu[a] * row;
            d_v += wu[a] * row_dv;
            d_h += wu[a] * row_h;
        }
        s.gamma[c] = val;
        if (want_grad != 0) {
            s.dgamma[c][0] = d_u * inv_dlat;
            s.dgamma[c][1] = d_v * inv_dlon;
            s.dgamma[c][2] = d_h;
        }
    }
    *out = s;
    return GG_OK;
}

gg_status_t gg_gmap_to_matrix(const gg_real_t g6[GG_GMAP_NCOMP], gg_real_t m[3][3])
{
    if ((g6 == NULL) || (m == NULL)) {
        return GG_ERR_NULL;
    }
    m[0][0] = g6[GG_GMAP_C_NN];
    m[1][1] = g6[GG_GMAP_C_EE];
    m[2][2] = g6[GG_GMAP_C_DD];
    m[0][1] = g6[GG_GMAP_C_NE];
    m[1][0] = g6[GG_GMAP_C_NE];
    m[0][2] = g6[GG_GMAP_C_ND];
    m[2][0] = g6[GG_GMAP_C_ND];
    m[1][2] = g6[GG_GMAP_C_ED];
    m[2][1] = g6[GG_GMAP_C_ED];
    return GG_OK;
}
