/* The particle filter's measurement model: Gamma_zz from the onboard map
 * and the distance of a fringe pair to the ellipse it predicts
 * (Phillips et al. eqs. 2-6; pf.h). */
#include "pf_int.h"

#include <stddef.h>

#include "ggins/ggmath.h"

/* Distance from (px, py) to the ellipse (a cos t, b sin t), a, b > 0: the
 * trig-free evolute iteration (tangent-point update along the evolute, then
 * renormalisation of (cos t, sin t)), 4 iterations. */
static double pf_ellipse_dist_axes(double px, double py, double a, double b)
{
    double tx = 0.70710678118654752;
    double ty = 0.70710678118654752;
    const double ax = (px < 0.0) ? -px : px;
    const double ay = (py < 0.0) ? -py : py;
    double dx;
    double dy;
    int it;
    for (it = 0; it < 4; ++it) {
        double ex;
        double ey;
        double rx;
        double ry;
        double qx;
        double qy;
        double rr;
        double qq;
        double t;
        const double x = a * tx;
        const double y = b * ty;
        ex = (((a * a) - (b * b)) * tx * tx * tx) / a;
        ey = (((b * b) - (a * a)) * ty * ty * ty) / b;
        rx = x - ex;
        ry = y - ey;
        qx = ax - ex;
        qy = ay - ey;
        rr = gg_sqrt_d((rx * rx) + (ry * ry));
        qq = gg_sqrt_d((qx * qx) + (qy * qy));
        if (qq > 0.0) {
            tx = (((qx * rr) / qq) + ex) / a;
            ty = (((qy * rr) / qq) + ey) / b;
        }
        tx = (tx < 0.0) ? 0.0 : ((tx > 1.0) ? 1.0 : tx);
        ty = (ty < 0.0) ? 0.0 : ((ty > 1.0) ? 1.0 : ty);
        t = gg_sqrt_d((tx * tx) + (ty * ty));
        if (t > 0.0) {
            tx /= t;
            ty /= t;
        }
    }
    dx = ax - (a * tx);
    dy = ay - (b * ty);
    return gg_sqrt_d((dx * dx) + (dy * dy));
}

gg_status_t gg_pf_ellipse_distance(double s0, double s1, double c0, double c1, double amp, double dphi,
                                   double *d)
{
    double sh = 0.0;
    double ch = 0.0;
    double u;
    double v;
    double p;
    double q;
    double a;
    double b;
    gg_status_t st;
    if (d == NULL) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(s0) || !GG_ISFINITE(s1) || !GG_ISFINITE(c0) || !GG_ISFINITE(c1) || !GG_ISFINITE(amp) ||
        !GG_ISFINITE(dphi)) {
        return GG_ERR_NONFINITE;
    }
    if (!(amp > 0.0)) {
        return GG_ERR_RANGE;
    }
    st = gg_sincos_d(0.5 * dphi, &sh, &ch);
    if (st != GG_OK) {
        return st;
    }
    u = (c0 - s0) / amp;
    v = (c1 - s1) / amp;
    p = (u + v) * 0.70710678118654752;
    q = (u - v) * 0.70710678118654752;
    a = 1.4142135623730951 * ((ch < 0.0) ? -ch : ch);
    b = 1.4142135623730951 * ((sh < 0.0) ? -sh : sh);
    if (a < 1e-9) {
        a = 1e-9; /* degenerate ellipse (a line): keep the iteration finite */
    }
    if (b < 1e-9) {
        b = 1e-9;
    }
    *d = amp * pf_ellipse_dist_axes(p, q, a, b);
    return GG_OK;
}

static gg_status_t pf_gmap_gzz(const void *ctx, double lat, double lon, double h, double *gzz)
{
    gg_gmap_sample_t smp;
    gg_status_t s;
    if ((ctx == NULL) || (gzz == NULL)) {
        return GG_ERR_NULL;
    }
    /* MISRA 11.5 deviation: the ops table's context is a void pointer by design (pf.h); it is
     * set only by gg_pf_map_from_gmap to a gg_gmap_t. MISRA 12.2: false positive on the
     * constant mask macros of gmap.h (shift by GG_GMAP_C_DD = 2). */
    /* cppcheck-suppress misra-c2012-11.5 */
    s = gg_gmap_eval((const gg_gmap_t *)ctx, (gg_real_t)lat, (gg_real_t)lon, (gg_real_t)h,
                     /* cppcheck-suppress misra-c2012-12.2 */
                     GG_GMAP_MASK_DD | GG_GMAP_H_EXTRAPOLATE, 0, &smp);
    if (s == GG_OK) {
        *gzz = (double)smp.gamma[GG_GMAP_C_DD];
    }
    return s;
}

gg_status_t gg_pf_map_from_gmap(const gg_gmap_t *gm, gg_pf_map_t *map)
{
    if ((gm == NULL) || (map == NULL)) {
        return GG_ERR_NULL;
    }
    if (!gm->initialized) {
        return GG_ERR_NOT_INIT;
    }
    map->gzz = pf_gmap_gzz;
    map->ctx = gm;
    return GG_OK;
}
