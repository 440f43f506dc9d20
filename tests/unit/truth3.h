/* Closed-form truth of the 3-D tests (test_nav3d.c, test_aid_mmukf.c): a
 * platform moving along a circle of latitude at constant height on a
 * rotating Earth (uniform circular motion in the inertial frame), in the
 * field of a central point mass plus buried anomaly masses fixed to the
 * Earth, with a body that precesses and spins. Every accelerometer reading
 * is built from rigid-body kinematics at the sensor's own position in long
 * double; nothing is integrated numerically. Independent of the firmware
 * (libm trigonometry, its own WGS-84 copy). */
#ifndef GGINS_TEST_TRUTH3_H
#define GGINS_TEST_TRUTH3_H

#include <math.h>
#include <string.h>

#include "truth2d.h"
#include "ggins/nav3d.h"

#ifndef T3_MAX_ANOM
#define T3_MAX_ANOM 16
#endif

#define W_IE 7.292115e-5L
#define A_WGS 6378137.0L
#define F_WGS (1.0L / 298.257223563L)

typedef struct {
    long double lat0, lon0, h0; /* path: circle of latitude lat0 at height h0 */
    long double lon_rate;       /* Earth-relative longitude rate, rad/s */
    long double p, s;           /* body precession (about inertial z) and spin (about body x), rad/s */
    long double c0[3][3];       /* C_b_i at t = 0 (= C_b_e) */
    long double hb[3];          /* half-baselines, m */
    int n_anom;
    long double anom_e[T3_MAX_ANOM][3];   /* anomaly mass positions, ECEF, m */
    long double anom_gm[T3_MAX_ANOM];     /* their GM, m^3/s^2 */
    double bias[6][3];          /* accelerometer faults added to the readings, m/s^2 */
} truth3_t;

static inline void rz(long double a, long double m[3][3])
{
    const long double c = cosl(a), s = sinl(a);
    const long double r[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
    memcpy(m, r, sizeof r);
}

static inline void rx(long double a, long double m[3][3])
{
    const long double c = cosl(a), s = sinl(a);
    const long double r[3][3] = {{1, 0, 0}, {0, c, -s}, {0, s, c}};
    memcpy(m, r, sizeof r);
}

static inline void matmul(const long double a[3][3], const long double b[3][3], long double o[3][3])
{
    long double t[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            t[i][j] = 0;
            for (int k = 0; k < 3; ++k) t[i][j] += a[i][k] * b[k][j];
        }
    memcpy(o, t, sizeof t);
}

static inline void matvec(const long double a[3][3], const long double x[3], long double y[3])
{
    for (int i = 0; i < 3; ++i) y[i] = a[i][0] * x[0] + a[i][1] * x[1] + a[i][2] * x[2];
}

static inline void mattvec(const long double a[3][3], const long double x[3], long double y[3])
{
    for (int i = 0; i < 3; ++i) y[i] = a[0][i] * x[0] + a[1][i] * x[1] + a[2][i] * x[2];
}

static inline void cross(const long double a[3], const long double b[3], long double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* closed-form geodetic -> ECEF (an independent copy: libm trig) */
static inline void geo2ecef(long double lat, long double lon, long double h, long double r[3])
{
    const long double e2 = F_WGS * (2.0L - F_WGS);
    const long double n = A_WGS / sqrtl(1.0L - e2 * sinl(lat) * sinl(lat));
    r[0] = (n + h) * cosl(lat) * cosl(lon);
    r[1] = (n + h) * cosl(lat) * sinl(lon);
    r[2] = (n * (1.0L - e2) + h) * sinl(lat);
}

/* gravitation in ECEF: central point mass + anomalies */
static inline void field_e(const truth3_t *T, const long double r[3], long double g[3])
{
    t_point_mass_g(r, g);
    for (int a = 0; a < T->n_anom; ++a) {
        long double d[3], dd = 0;
        for (int j = 0; j < 3; ++j) {
            d[j] = r[j] - T->anom_e[a][j];
            dd += d[j] * d[j];
        }
        const long double k = T->anom_gm[a] / (dd * sqrtl(dd));
        for (int j = 0; j < 3; ++j) g[j] -= k * d[j];
    }
}

/* truth at time t: r_e, v_e (Earth-relative), r_i, a_i, C_b_i = C0 Rz(pt) Rx(st)
 * and the body rate and angular acceleration (C0 is fixed in the inertial
 * frame, so C^T C' = (Rz Rx)^T (Rz Rx)' = p [(Rx^T e_z) x] + s [e_x x]) */
static inline void truth_pose(const truth3_t *T, long double t, long double r_e[3], long double v_e[3],
                       long double r_i[3], long double a_i[3], long double cbi[3][3],
                       long double w[3], long double wd[3])
{
    long double base[3], m[3][3], m2[3][3];
    geo2ecef(T->lat0, 0.0L, T->h0, base);
    const long double lon = T->lon0 + T->lon_rate * t;
    rz(lon, m);
    matvec(m, base, r_e);
    v_e[0] = -T->lon_rate * r_e[1];
    v_e[1] = T->lon_rate * r_e[0];
    v_e[2] = 0.0L;
    const long double lam = lon + W_IE * t, rate = W_IE + T->lon_rate;
    rz(lam, m);
    matvec(m, base, r_i);
    a_i[0] = -rate * rate * r_i[0];
    a_i[1] = -rate * rate * r_i[1];
    a_i[2] = 0.0L;
    rz(T->p * t, m);
    rx(T->s * t, m2);
    matmul(m, m2, m);
    matmul(T->c0, m, cbi);
    const long double st = sinl(T->s * t), ct = cosl(T->s * t);
    w[0] = T->s;
    w[1] = T->p * st;
    w[2] = T->p * ct;
    wd[0] = 0.0L;
    wd[1] = T->p * T->s * ct;
    wd[2] = -T->p * T->s * st;
}

static inline void make_frame(const truth3_t *T, long long k, int64_t dt_us, gg_frame_t *fr)
{
    const long double t = (long double)k * (long double)dt_us * 1e-6L;
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], th[3][3];
    truth_pose(T, t, r_e, v_e, r_i, a_i, cbi, w, wd);
    rz(W_IE * t, th);
    memset(fr, 0, sizeof *fr);
    fr->utime = k * dt_us;
    fr->seq = k;
    fr->n_acc = 6;
    for (int sidx = 0; sidx < 6; ++sidx) {
        long double d[3] = {0, 0, 0}, dd[3], p_i[3], p_e[3], g_e[3], g_i[3], g_b[3], a_b[3];
        long double t1[3], t2[3], t3[3];
        d[sidx % 3] = (sidx < 3 ? 1.0L : -1.0L) * T->hb[sidx % 3];
        matvec(cbi, d, dd);
        for (int j = 0; j < 3; ++j) p_i[j] = r_i[j] + dd[j];
        mattvec(th, p_i, p_e);
        field_e(T, p_e, g_e);
        matvec(th, g_e, g_i);
        mattvec(cbi, g_i, g_b);
        mattvec(cbi, a_i, a_b);
        cross(wd, d, t1);
        cross(w, d, t2);
        cross(w, t2, t3);
        for (int j = 0; j < 3; ++j) {
            const long double f = a_b[j] + t1[j] + t3[j] - g_b[j] + (long double)T->bias[sidx][j];
            fr->f[sidx][j] = (double)f;
            fr->f_lo[sidx][j] = (double)(f - (long double)fr->f[sidx][j]);
        }
        fr->acc_status[sidx] = GG_SENSOR_OK;
    }
    for (int j = 0; j < 3; ++j) fr->omega_b[j] = (double)w[j];
    fr->gyro_status = GG_SENSOR_OK;
    fr->baro_alt_m = (double)T->h0;
    fr->baro_utime = fr->utime;
    fr->baro_status = (k % 10 == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
}

static inline void dcm_to_quat(const long double c[3][3], long double q[4])
{
    /* c is close to a rotation; Shepperd's method (largest diagonal term) */
    const long double tr = c[0][0] + c[1][1] + c[2][2];
    if (tr > 0) {
        const long double s = 2.0L * sqrtl(1.0L + tr);
        q[0] = 0.25L * s;
        q[1] = (c[2][1] - c[1][2]) / s;
        q[2] = (c[0][2] - c[2][0]) / s;
        q[3] = (c[1][0] - c[0][1]) / s;
    } else if (c[0][0] > c[1][1] && c[0][0] > c[2][2]) {
        const long double s = 2.0L * sqrtl(1.0L + c[0][0] - c[1][1] - c[2][2]);
        q[0] = (c[2][1] - c[1][2]) / s;
        q[1] = 0.25L * s;
        q[2] = (c[0][1] + c[1][0]) / s;
        q[3] = (c[0][2] + c[2][0]) / s;
    } else if (c[1][1] > c[2][2]) {
        const long double s = 2.0L * sqrtl(1.0L + c[1][1] - c[0][0] - c[2][2]);
        q[0] = (c[0][2] - c[2][0]) / s;
        q[1] = (c[0][1] + c[1][0]) / s;
        q[2] = 0.25L * s;
        q[3] = (c[1][2] + c[2][1]) / s;
    } else {
        const long double s = 2.0L * sqrtl(1.0L + c[2][2] - c[0][0] - c[1][1]);
        q[0] = (c[1][0] - c[0][1]) / s;
        q[1] = (c[0][2] + c[2][0]) / s;
        q[2] = (c[1][2] + c[2][1]) / s;
        q[3] = 0.25L * s;
    }
}

static inline void make_config(const truth3_t *T, int platform, int baro, int64_t dt_us,
                        gg_nav3d_config_t *cfg)
{
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], g[3];
    truth_pose(T, 0.0L, r_e, v_e, r_i, a_i, cbi, w, wd);
    field_e(T, r_e, g);
    memset(cfg, 0, sizeof *cfg);
    for (int j = 0; j < 3; ++j) {
        cfg->geometry.half_base_m[j] = T->hb[j];
        cfg->r0_e[j] = r_e[j];
        cfg->v0_e[j] = v_e[j];
        cfg->g0_e[j] = g[j];
    }
    dcm_to_quat(cbi, cfg->q0_b_e);
    cfg->platform = platform;
    cfg->dt_us = dt_us;
    cfg->dt_tol_us = dt_us / 100;
    cfg->omega_ie = 0.0L; /* WGS-84 default */
    cfg->f_max = 100.0;
    cfg->asym_max = 1e-9;
    cfg->gravity_mode = GG_GRAVITY_GRADIOMETER;
    cfg->baro_enable = baro;
    if (baro) {
        cfg->baro.poles[0] = 0.01L;
        cfg->baro.poles[1] = 0.012L;
        cfg->baro.poles[2] = 0.014L;
        cfg->baro.omega_s2 = 9.8L / 6.4e6L;
        cfg->baro.period_us = 10 * dt_us;
        cfg->baro.max_age_us = 10 * dt_us;
        cfg->baro.coast_us = 100 * dt_us;
        cfg->baro.alt_min_m = -1000.0;
        cfg->baro.alt_max_m = 30000.0;
        cfg->baro.gate_m = 50.0;
        cfg->baro.max_rejects = 10;
    }
}

static inline void default_truth(truth3_t *T)
{
    memset(T, 0, sizeof *T);
    T->lat0 = 0.7L;
    T->lon0 = 0.2L;
    T->h0 = 3000.0L;
    T->hb[0] = 0.5L;
    T->hb[1] = 0.4L;
    T->hb[2] = 0.6L;
    for (int i = 0; i < 3; ++i) T->c0[i][i] = 1.0L;
    /* two buried masses near the start (~1e-5 m/s^2, ~5 E at the path) */
    long double p[3];
    geo2ecef(0.7L, 0.2015L, -4000.0L, p);
    memcpy(T->anom_e[0], p, sizeof p);
    T->anom_gm[0] = 800.0L;
    geo2ecef(0.7005L, 0.2060L, -6000.0L, p);
    memcpy(T->anom_e[1], p, sizeof p);
    T->anom_gm[1] = -500.0L;
    T->n_anom = 2;
}

#endif /* GGINS_TEST_TRUTH3_H */
