/* The map-matching UKF's navigation state: its NED strapdown mechanization
 * and the error-state algebra (difference and composition) the filter's
 * sigma points are built with (mmukf.h). Attitude products in gg_real_t
 * (quat.h), the state in double. */
#include "mmukf_int.h"

#include <math.h>
#include <stddef.h>

#include "ggins/geo.h"
#include "ggins/ggmath.h"
#include "ggins/limits.h"
#include "ggins/quat.h"

/* sin, cos of a double angle through gg_sincos */
static gg_status_t sc(double x, double *s, double *c)
{
    gg_real_t ls;
    gg_real_t lc;
    const gg_status_t st = gg_sincos((gg_real_t)x, &ls, &lc);
    if (st != GG_OK) {
        return st;
    }
    *s = (double)ls;
    *c = (double)lc;
    return GG_OK;
}

/* q = Exp(th) of a double rotation vector */
static gg_status_t qexp_d(const double th[3], gg_real_t q[4])
{
    const gg_real_t t[3] = {(gg_real_t)th[0], (gg_real_t)th[1], (gg_real_t)th[2]};
    return gg_quat_from_rotvec(t, q);
}

int mm_nav_ok(const gg_mm_nav_t *x)
{
    for (int k = 0; k < 4; ++k) {
        if (!GG_ISFINITE(x->q[k])) {
            return 0;
        }
    }
    for (int k = 0; k < 3; ++k) {
        if (!GG_ISFINITE(x->v[k]) || !GG_ISFINITE(x->bg[k]) || !GG_ISFINITE(x->ba[k])) {
            return 0;
        }
    }
    if (!GG_ISFINITE(x->lat) || !GG_ISFINITE(x->lon) || !GG_ISFINITE(x->h) || (x->lat > GG_LIM_LAT_MAX_RAD) ||
        (x->lat < -GG_LIM_LAT_MAX_RAD) || (x->h < GG_LIM_MM_H_MIN_M) || (x->h > GG_LIM_MM_H_MAX_M)) {
        return 0;
    }
    return 1;
}

gg_status_t gg_mm_mech(gg_mm_nav_t *xio, const gg_mm_imu_t *imu, double dt, int32_t vertical_hold,
                       double h_hold, double vd_hold)
{
    if ((xio == NULL) || (imu == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(dt) || (dt <= 0.0) || (dt > GG_LIM_MM_DT_MAX_S) || (mm_nav_ok(xio) == 0)) {
        return GG_ERR_RANGE;
    }
    /* cppcheck-suppress misra-c2012-9.3 */
    gg_mm_nav_t x = *xio;
    double s;
    double c;
    gg_status_t st = sc(x.lat, &s, &c);
    if (st != GG_OK) {
        return st;
    }
    double rm;
    double rn;
    double g;
    gg_geo_radii(s, &rm, &rn);
    st = gg_geo_normal_gravity(x.lat, x.h, &g);
    if (st != GG_OK) {
        return st;
    }
    const double wie = (double)GG_WGS84_OMEGA_IE;
    const double w_ie[3] = {wie * c, 0.0, -wie * s};
    const double w_en[3] = {x.v[1] / (rn + x.h), -x.v[0] / (rm + x.h), -x.v[1] * s / (c * (rn + x.h))};
    double th[3];
    double thh[3];
    double thn[3];
    double thnh[3];
    gg_real_t f[3];
    for (int k = 0; k < 3; ++k) {
        const double w = imu->omega_b[k] - x.bg[k];
        f[k] = (gg_real_t)(imu->f_b[k] - x.ba[k]);
        th[k] = w * dt;
        thh[k] = 0.5 * th[k];
        thn[k] = -(w_ie[k] + w_en[k]) * dt;
        thnh[k] = 0.5 * thn[k];
    }
    gg_real_t q0[4];
    gg_real_t qb[4];
    gg_real_t qh[4];
    gg_real_t qn[4];
    gg_real_t qnh[4];
    gg_real_t qm[4];
    gg_real_t qt[4];
    gg_real_t C[3][3];
    gg_real_t fn[3];
    if ((qexp_d(th, qb) != GG_OK) || (qexp_d(thh, qh) != GG_OK) || (qexp_d(thn, qn) != GG_OK) ||
        (qexp_d(thnh, qnh) != GG_OK)) {
        return GG_ERR_RANGE;
    }
    for (int k = 0; k < 4; ++k) {
        q0[k] = (gg_real_t)x.q[k];
    }
    /* mid-step attitude for the specific force (body AND navigation frame
     * rotated by half a step) */
    gg_quat_mul(q0, qh, qt);
    gg_quat_mul(qnh, qt, qm);
    gg_quat_to_dcm(qm, C);
    gg_mat3_vec(C, f, fn);
    gg_quat_mul(q0, qb, qt);
    gg_quat_mul(qn, qt, q0);
    if (gg_quat_normalize(q0) != GG_OK) {
        return GG_ERR_RANGE;
    }
    for (int k = 0; k < 4; ++k) {
        x.q[k] = (double)q0[k];
    }
    const double a[3] = {(2.0 * w_ie[0]) + w_en[0], (2.0 * w_ie[1]) + w_en[1], (2.0 * w_ie[2]) + w_en[2]};
    const double cor[3] = {(a[1] * x.v[2]) - (a[2] * x.v[1]), (a[2] * x.v[0]) - (a[0] * x.v[2]),
                           (a[0] * x.v[1]) - (a[1] * x.v[0])};
    double vn[3];
    vn[0] = x.v[0] + ((double)fn[0] - cor[0]) * dt;
    vn[1] = x.v[1] + ((double)fn[1] - cor[1]) * dt;
    vn[2] = x.v[2] + ((double)fn[2] + g - cor[2]) * dt;
    if (vertical_hold != 0) {
        vn[2] = vd_hold;
    }
    x.lat += 0.5 * (x.v[0] + vn[0]) / (rm + x.h) * dt;
    x.lon += 0.5 * (x.v[1] + vn[1]) / ((rn + x.h) * c) * dt;
    x.h -= 0.5 * (x.v[2] + vn[2]) * dt;
    if (vertical_hold != 0) {
        x.h = h_hold;
    }
    x.v[0] = vn[0];
    x.v[1] = vn[1];
    x.v[2] = vn[2];
    if (mm_nav_ok(&x) == 0) {
        return GG_ERR_RANGE;
    }
    *xio = x;
    return GG_OK;
}

gg_status_t gg_mm_error(const gg_mm_nav_t *a, const gg_mm_nav_t *b, double d[GG_MM_NX])
{
    if ((a == NULL) || (b == NULL) || (d == NULL)) {
        return GG_ERR_NULL;
    }
    double s;
    double c;
    double rm;
    double rn;
    gg_real_t qa[4];
    gg_real_t qb[4];
    gg_real_t qi[4];
    gg_real_t qe[4];
    gg_real_t phi[3];
    gg_status_t st = sc(b->lat, &s, &c);
    if (st != GG_OK) {
        return st;
    }
    gg_geo_radii(s, &rm, &rn);
    for (int k = 0; k < 4; ++k) {
        qa[k] = (gg_real_t)a->q[k];
        qb[k] = (gg_real_t)b->q[k];
    }
    gg_quat_conj(qb, qi);
    gg_quat_mul(qa, qi, qe); /* C_a = Exp(phi) C_b */
    st = gg_quat_to_rotvec(qe, phi);
    if (st != GG_OK) {
        return st;
    }
    for (int k = 0; k < 3; ++k) {
        d[k] = (double)phi[k];
        d[3 + k] = a->v[k] - b->v[k];
        d[9 + k] = a->bg[k] - b->bg[k];
        d[12 + k] = a->ba[k] - b->ba[k];
    }
    d[6] = (a->lat - b->lat) * (rm + b->h);
    d[7] = (a->lon - b->lon) * (rn + b->h) * c;
    d[8] = -(a->h - b->h);
    return GG_OK;
}

gg_status_t mm_apply(const gg_mm_nav_t *b, const double *d, gg_mm_nav_t *a)
{
    for (int k = 0; k < GG_MM_NX; ++k) {
        if (!GG_ISFINITE(d[k])) {
            return GG_ERR_NONFINITE;
        }
    }
    double s;
    double c;
    double rm;
    double rn;
    gg_real_t qe[4];
    gg_real_t q[4];
    gg_status_t st = sc(b->lat, &s, &c);
    if (st != GG_OK) {
        return st;
    }
    gg_geo_radii(s, &rm, &rn);
    st = qexp_d(d, qe);
    if (st != GG_OK) {
        return st;
    }
    /* cppcheck-suppress misra-c2012-9.3 */
    gg_mm_nav_t r = *b;
    for (int k = 0; k < 4; ++k) {
        q[k] = (gg_real_t)b->q[k];
    }
    gg_quat_mul(qe, q, q);
    if (gg_quat_normalize(q) != GG_OK) {
        return GG_ERR_RANGE;
    }
    for (int k = 0; k < 4; ++k) {
        r.q[k] = (double)q[k];
    }
    for (int k = 0; k < 3; ++k) {
        r.v[k] = b->v[k] + d[3 + k];
        r.bg[k] = b->bg[k] + d[9 + k];
        r.ba[k] = b->ba[k] + d[12 + k];
    }
    r.lat = b->lat + (d[6] / (rm + b->h));
    r.lon = b->lon + (d[7] / ((rn + b->h) * c));
    r.h = b->h - d[8];
    if (mm_nav_ok(&r) == 0) {
        return GG_ERR_RANGE;
    }
    *a = r;
    return GG_OK;
}

gg_status_t gg_mm_apply(const gg_mm_nav_t *b, const double d[GG_MM_NX], gg_mm_nav_t *a)
{
    if ((b == NULL) || (d == NULL) || (a == NULL)) {
        return GG_ERR_NULL;
    }
    if (mm_nav_ok(b) == 0) {
        return GG_ERR_RANGE;
    }
    return mm_apply(b, d, a);
}
