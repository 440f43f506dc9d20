/* WGS-84 geometry (see geo.h). */
#include "ggins/geo.h"

#include <stddef.h>

#include "ggins/ggmath.h"
#include "ggins/limits.h"
#include "ggins/quat.h"

/* Geodetic latitude as (sin, cos), longitude as (sin, cos) and height of an
 * ECEF point, without trigonometric functions (Bowring, see geo.h). */
typedef struct {
    gg_real_t sphi;
    gg_real_t cphi;
    gg_real_t slam;
    gg_real_t clam;
    gg_real_t h;
    gg_real_t pp;   /* (pp, zz): direction of the normal, for atan2 */
    gg_real_t zz;
} geo_t;

static gg_status_t geodetic_core(const gg_real_t r_e[3], geo_t *g)
{
    const gg_real_t a = GG_WGS84_A_M;
    const gg_real_t f = GG_WGS84_F;
    const gg_real_t b = a * (1.0L - f);
    const gg_real_t e2 = GG_WGS84_E2;
    const gg_real_t ep2 = e2 / (1.0L - e2);
    gg_real_t p;
    gg_real_t cb;
    gg_real_t sb;
    gg_real_t pp;
    gg_real_t zz;
    gg_real_t n;
    unsigned it;
    if (gg_finite3(r_e) == 0) {
        return GG_ERR_NONFINITE;
    }
    if (gg_vec3_dot(r_e, r_e) < (GG_GEO_R_MIN_M * GG_GEO_R_MIN_M)) {
        return GG_ERR_RANGE;
    }
    p = sqrtl((r_e[0] * r_e[0]) + (r_e[1] * r_e[1]));
    cb = p * (1.0L - f);
    sb = r_e[2];
    pp = p;
    zz = r_e[2];
    for (it = 0U; it < GG_GEO_BOWRING_ITER; ++it) {
        n = sqrtl((cb * cb) + (sb * sb));
        cb /= n;
        sb /= n;
        pp = p - (e2 * a * cb * cb * cb);
        zz = r_e[2] + (ep2 * b * sb * sb * sb);
        cb = pp;
        sb = (1.0L - f) * zz;
    }
    n = sqrtl((pp * pp) + (zz * zz));
    g->cphi = pp / n;
    g->sphi = zz / n;
    g->pp = pp;
    g->zz = zz;
    if (p > 0.0L) {
        g->clam = r_e[0] / p;
        g->slam = r_e[1] / p;
    } else {
        g->clam = 1.0L; /* on the axis: longitude 0 by convention */
        g->slam = 0.0L;
    }
    g->h = (p * g->cphi) + (r_e[2] * g->sphi) - (a * sqrtl(1.0L - (e2 * g->sphi * g->sphi)));
    return GG_OK;
}

gg_status_t gg_geo_ecef_to_geodetic(const gg_real_t r_e[3], gg_real_t *lat, gg_real_t *lon,
                                      gg_real_t *h)
{
    geo_t g;
    gg_real_t la = 0.0L;
    gg_real_t lo = 0.0L;
    gg_status_t st;
    if ((r_e == NULL) || (lat == NULL) || (lon == NULL) || (h == NULL)) {
        return GG_ERR_NULL;
    }
    st = geodetic_core(r_e, &g);
    if (st == GG_OK) {
        st = gg_atan2(g.zz, g.pp, &la);
    }
    if (st == GG_OK) {
        st = gg_atan2(r_e[1], r_e[0], &lo);
    }
    if (st == GG_OK) {
        *lat = la;
        *lon = lo;
        *h = g.h;
    }
    return st;
}

gg_status_t gg_geo_geodetic_to_ecef(gg_real_t lat, gg_real_t lon, gg_real_t h, gg_real_t r_e[3])
{
    const gg_real_t e2 = GG_WGS84_E2;
    gg_real_t sl;
    gg_real_t cl;
    gg_real_t so;
    gg_real_t co;
    gg_status_t st;
    if (r_e == NULL) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(h)) {
        return GG_ERR_NONFINITE;
    }
    st = gg_sincos(lat, &sl, &cl);
    if (st == GG_OK) {
        st = gg_sincos(lon, &so, &co);
    }
    if (st == GG_OK) {
        const gg_real_t n = GG_WGS84_A_M / sqrtl(1.0L - (e2 * sl * sl));
        r_e[0] = (n + h) * cl * co;
        r_e[1] = (n + h) * cl * so;
        r_e[2] = ((n * (1.0L - e2)) + h) * sl;
    }
    return st;
}

gg_status_t gg_geo_local_frame(const gg_real_t r_e[3], gg_real_t *h, gg_real_t c_e_n[3][3])
{
    geo_t g;
    gg_status_t st;
    if ((r_e == NULL) || (h == NULL) || (c_e_n == NULL)) {
        return GG_ERR_NULL;
    }
    st = geodetic_core(r_e, &g);
    if (st == GG_OK) {
        const gg_real_t sl = g.sphi;
        const gg_real_t cl = g.cphi;
        const gg_real_t so = g.slam;
        const gg_real_t co = g.clam;
        *h = g.h;
        c_e_n[0][0] = -sl * co; /* north */
        c_e_n[0][1] = -sl * so;
        c_e_n[0][2] = cl;
        c_e_n[1][0] = -so;      /* east */
        c_e_n[1][1] = co;
        c_e_n[1][2] = 0.0L;
        c_e_n[2][0] = -cl * co; /* down */
        c_e_n[2][1] = -cl * so;
        c_e_n[2][2] = -sl;
    }
    return st;
}

void gg_geo_radii(double sin_lat, double *rm, double *rn)
{
    const double e2 = (double)GG_WGS84_E2_TAB;
    const double w2 = 1.0 - (e2 * sin_lat * sin_lat);
    const double nr = (double)GG_WGS84_A_M / gg_sqrt_d(w2);
    *rm = (nr * (1.0 - e2)) / w2;
    *rn = nr;
}

gg_status_t gg_geo_normal_gravity(double lat, double h, double *g)
{
    const double a = (double)GG_WGS84_A_M;
    const double f = (double)GG_WGS84_F;
    const double e2 = (double)GG_WGS84_E2_TAB;
    const double m = (double)GG_WGS84_M;
    gg_real_t ls;
    gg_real_t lc;
    gg_status_t st;
    if (g == NULL) {
        return GG_ERR_NULL;
    }
    st = gg_sincos((gg_real_t)lat, &ls, &lc);
    if (st == GG_OK) {
        const double s = (double)ls;
        const double s2 = s * s;
        const double g0 = ((double)GG_WGS84_GAMMA_E_MPS2 * (1.0 + ((double)GG_WGS84_SOMIGLIANA_K * s2))) /
                          gg_sqrt_d(1.0 - (e2 * s2));
        *g = g0 * ((1.0 - (((2.0 / a) * (((1.0 + f) + m) - ((2.0 * f) * s2))) * h)) +
                   (((3.0 / (a * a)) * h) * h));
    }
    return st;
}
