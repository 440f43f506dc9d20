/* Navigation task of the 3-D gravity-gradiometer INS on a rotating WGS-84
 * Earth; frames, equations and the reasons for them in nav3d.h. */
#include "ggins/nav3d.h"
#include "ggins/navtask.h"

#include <stddef.h>

#include "ggins/ggmath.h"

#define N_ACC_3D 6
/* a residual below double resolution can never exceed ulp(f_max)/2 (nav2d.c) */
/* |q0| must be 1 to this tolerance */
#define Q_NORM_TOL 1.0e-6L
/* geodetic conversion: no point within this distance of the centre, m */
#define R_GEODETIC_MIN_M 1.0e5L
#define BOWRING_ITER 4U

static gg_real_t dot3(const gg_real_t a[3], const gg_real_t b[3])
{
    return (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2]);
}

/* v_out = R3(theta) v (sign +1) or R3(-theta) v (sign -1); (s, c) = sin, cos theta */
static void rot3(gg_real_t s, gg_real_t c, int sign, const gg_real_t v[3], gg_real_t o[3])
{
    const gg_real_t ss = (sign > 0) ? s : -s;
    const gg_real_t x = (c * v[0]) - (ss * v[1]);
    const gg_real_t y = (ss * v[0]) + (c * v[1]);
    o[0] = x;
    o[1] = y;
    o[2] = v[2];
}

/* p (x) q, scalar first */
static void qmul(const gg_real_t p[4], const gg_real_t q[4], gg_real_t o[4])
{
    const gg_real_t w = (p[0] * q[0]) - (p[1] * q[1]) - (p[2] * q[2]) - (p[3] * q[3]);
    const gg_real_t x = (p[0] * q[1]) + (p[1] * q[0]) + (p[2] * q[3]) - (p[3] * q[2]);
    const gg_real_t y = (p[0] * q[2]) - (p[1] * q[3]) + (p[2] * q[0]) + (p[3] * q[1]);
    const gg_real_t z = (p[0] * q[3]) + (p[1] * q[2]) - (p[2] * q[1]) + (p[3] * q[0]);
    o[0] = w;
    o[1] = x;
    o[2] = y;
    o[3] = z;
}

/* direction-cosine matrix of a unit quaternion (maps the rotated frame's
 * vectors into the reference frame) */
static void q_to_dcm(const gg_real_t q[4], gg_real_t c[3][3])
{
    const gg_real_t w = q[0];
    const gg_real_t x = q[1];
    const gg_real_t y = q[2];
    const gg_real_t z = q[3];
    c[0][0] = 1.0L - (2.0L * ((y * y) + (z * z)));
    c[0][1] = 2.0L * ((x * y) - (w * z));
    c[0][2] = 2.0L * ((x * z) + (w * y));
    c[1][0] = 2.0L * ((x * y) + (w * z));
    c[1][1] = 1.0L - (2.0L * ((x * x) + (z * z)));
    c[1][2] = 2.0L * ((y * z) - (w * x));
    c[2][0] = 2.0L * ((x * z) - (w * y));
    c[2][1] = 2.0L * ((y * z) + (w * x));
    c[2][2] = 1.0L - (2.0L * ((x * x) + (y * y)));
}

static gg_status_t q_normalize(gg_real_t q[4])
{
    const gg_real_t n2 = (q[0] * q[0]) + (q[1] * q[1]) + (q[2] * q[2]) + (q[3] * q[3]);
    gg_real_t inv;
    size_t j;
    if (!GG_ISFINITE(n2) || !(n2 > 0.5L)) {
        return GG_ERR_RANGE;
    }
    inv = 1.0L / sqrtl(n2);
    for (j = 0U; j < 4U; ++j) {
        q[j] *= inv;
    }
    return GG_OK;
}

/* a 3x3 matrix in a struct: a pointer to a const one yields const rows, so
 * functions taking const gg_real_t m[3][3] accept it without casts */
typedef struct {
    gg_real_t m[3][3];
} mat33_t;

static void mat_copy(gg_real_t src[3][3], mat33_t *dst)
{
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            dst->m[j][k] = src[j][k];
        }
    }
}

/* y = C x */
static void mat_vec(gg_real_t c[3][3], const gg_real_t x[3], gg_real_t y[3])
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        y[j] = (c[j][0] * x[0]) + (c[j][1] * x[1]) + (c[j][2] * x[2]);
    }
}

/* o = C m C^T */
static void similarity(gg_real_t c[3][3], const gg_real_t m[3][3], gg_real_t o[3][3])
{
    gg_real_t t[3][3];
    size_t j;
    size_t k;
    size_t l;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            t[j][k] = 0.0L;
            for (l = 0U; l < 3U; ++l) {
                t[j][k] += c[j][l] * m[l][k];
            }
        }
    }
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            o[j][k] = 0.0L;
            for (l = 0U; l < 3U; ++l) {
                o[j][k] += t[j][l] * c[k][l];
            }
        }
    }
}

/* R3(theta) as a matrix, sign -1 for R3(-theta) */
static void rot3_mat(gg_real_t s, gg_real_t c, int sign, gg_real_t m[3][3])
{
    const gg_real_t ss = (sign > 0) ? s : -s;
    m[0][0] = c;
    m[0][1] = -ss;
    m[0][2] = 0.0L;
    m[1][0] = ss;
    m[1][1] = c;
    m[1][2] = 0.0L;
    m[2][0] = 0.0L;
    m[2][1] = 0.0L;
    m[2][2] = 1.0L;
}

/* ---------------------------------------------------------------- geodesy */

static gg_real_t wgs84_e2(void)
{
    return GG_WGS84_F * (2.0L - GG_WGS84_F);
}

/* Geodetic latitude as (sin, cos), longitude as (sin, cos) and height of an
 * ECEF point, without trigonometric functions: Bowring's iteration on the
 * parametric latitude beta (tan beta = (1 - f) tan phi), carried as the
 * vector (cos beta, sin beta), BOWRING_ITER times. */
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
    const gg_real_t e2 = wgs84_e2();
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
    if (dot3(r_e, r_e) < (R_GEODETIC_MIN_M * R_GEODETIC_MIN_M)) {
        return GG_ERR_RANGE;
    }
    p = sqrtl((r_e[0] * r_e[0]) + (r_e[1] * r_e[1]));
    cb = p * (1.0L - f);
    sb = r_e[2];
    pp = p;
    zz = r_e[2];
    for (it = 0U; it < BOWRING_ITER; ++it) {
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

gg_status_t gg_nav3d_ecef_to_geodetic(const gg_real_t r_e[3], gg_real_t *lat, gg_real_t *lon,
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

gg_status_t gg_nav3d_geodetic_to_ecef(gg_real_t lat, gg_real_t lon, gg_real_t h, gg_real_t r_e[3])
{
    const gg_real_t e2 = wgs84_e2();
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

/* Geodetic height and the north/east/down axes in ECEF (rows of C_e_n) at
 * r_e; the up unit vector (the ellipsoid normal) is minus the third row. */
static gg_status_t local_frame(const gg_real_t r_e[3], gg_real_t *h, gg_real_t c_e_n[3][3])
{
    geo_t g;
    const gg_status_t st = geodetic_core(r_e, &g);
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

/* ---------------------------------------------------------------- config */

static int cfg_finite(const gg_nav3d_config_t *cfg)
{
    int ok = 1;
    size_t j;
    if ((gg_finite3(cfg->r0_e) == 0) || (gg_finite3(cfg->v0_e) == 0) ||
        (gg_finite3(cfg->g0_e) == 0) || !GG_ISFINITE(cfg->omega_ie) || !GG_ISFINITE(cfg->f_max) ||
        !GG_ISFINITE(cfg->asym_max)) {
        ok = 0;
    }
    for (j = 0U; j < 4U; ++j) {
        if (!GG_ISFINITE(cfg->q0_b_e[j])) {
            ok = 0;
        }
    }
    return ok;
}

static int n3_in_limits(const gg_nav3d_config_t *cfg)
{
    const gg_real_t rn = sqrtl(dot3(cfg->r0_e, cfg->r0_e));
    int ok = 1;
    size_t k;
    if ((rn < GG_LIM_R_MIN_M) || (rn > GG_LIM_R_MAX_M) ||
        (sqrtl(dot3(cfg->v0_e, cfg->v0_e)) > GG_LIM_V_MAX_MPS) ||
        (sqrtl(dot3(cfg->g0_e, cfg->g0_e)) > GG_LIM_G_MAX_MPS2) || (cfg->dt_us > GG_LIM_DT_MAX_US) ||
        (cfg->f_max > GG_LIM_F_MAX_MPS2) || (cfg->asym_max > 1.0) ||
        (cfg->omega_ie > 1.0e-3L)) {
        ok = 0;
    }
    for (k = 0U; k < 3U; ++k) {
        if ((cfg->geometry.half_base_m[k] < GG_LIM_BASE_MIN_M) ||
            (cfg->geometry.half_base_m[k] > GG_LIM_BASE_MAX_M)) {
            ok = 0;
        }
    }
    return ok;
}

gg_status_t gg_nav3d_init(gg_nav3d_t *nav, const gg_nav3d_config_t *cfg)
{
    gg_diff3d_t diff;
    gg_status_t st;
    gg_real_t qn2;
    if ((nav == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    nav->configured = 0;
    nav->started = 0;
    st = gg_diff3d_init(&diff, &cfg->geometry);
    if (st != GG_OK) {
        return st;
    }
    if ((cfg_finite(cfg) == 0) || (cfg->dt_us <= 0) || (cfg->dt_tol_us < 0) ||
        (cfg->dt_tol_us >= cfg->dt_us) || !(cfg->f_max > 0.0) || !(cfg->asym_max > 0.0) ||
        ((cfg->platform != GG_PLATFORM_STABILIZED) && (cfg->platform != GG_PLATFORM_STRAPDOWN)) ||
        ((cfg->gravity_mode != GG_GRAVITY_GRADIOMETER) && (cfg->gravity_mode != GG_GRAVITY_MODEL)) ||
        (cfg->baro_enable < 0) || (cfg->baro_enable > 1)) {
        return GG_ERR_CONFIG;
    }
    qn2 = (cfg->q0_b_e[0] * cfg->q0_b_e[0]) + (cfg->q0_b_e[1] * cfg->q0_b_e[1]) +
          (cfg->q0_b_e[2] * cfg->q0_b_e[2]) + (cfg->q0_b_e[3] * cfg->q0_b_e[3]);
    if ((qn2 > (1.0L + Q_NORM_TOL)) || (qn2 < (1.0L - Q_NORM_TOL))) {
        return GG_ERR_CONFIG;
    }
    if (n3_in_limits(cfg) == 0) {
        return GG_ERR_RANGE;
    }
    nav->gmodel.initialized = 0;
    if (cfg->gravity_mode == GG_GRAVITY_MODEL) {
        st = gg_gmodel_init(&nav->gmodel, &cfg->model);
        if (st != GG_OK) {
            return st;
        }
    }
    nav->vchan.initialized = 0;
    if (cfg->baro_enable != 0) {
        st = gg_vchan_init(&nav->vchan, &cfg->baro);
        if (st != GG_OK) {
            return st;
        }
    }
    nav->cfg = *cfg;
    nav->diff = diff;
    nav->omega_ie = (cfg->omega_ie == 0.0L) ? GG_WGS84_OMEGA_IE
                                            : ((cfg->omega_ie < 0.0L) ? 0.0L : cfg->omega_ie);
    nav->dt_s = (gg_real_t)cfg->dt_us * 1.0e-6L;
    st = gg_sincos(0.5L * nav->omega_ie * nav->dt_s, &nav->sin_hstep, &nav->cos_hstep);
    if (st != GG_OK) {
        return GG_ERR_CONFIG;
    }
    nav->gravdr.initialized = 0;
    nav->mech.initialized = 0;
    st = gg_task_seq_init(&nav->seq, cfg->dt_us, cfg->dt_tol_us);
    if (st == GG_OK) {
        gg_fdi3d_config_t fc;
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            fc.half_base_m[j] = cfg->geometry.half_base_m[j];
        }
        fc.parity_f_max = cfg->fdi_parity_f_max;
        fc.stabilized = 0;
        if (cfg->platform == GG_PLATFORM_STABILIZED) {
            fc.stabilized = 1;
        }
        if ((cfg->fdi_parity_f_max != 0.0) && !(cfg->fdi_parity_f_max >= GG_FDI3D_FLOOR_MPS2)) {
            st = GG_ERR_CONFIG; /* below the curvature differences: false alarms */
        } else {
            st = gg_fdi3d_init(&nav->fdi, &fc);
        }
    }
    if (st != GG_OK) {
        return st;
    }
    nav->state_step = 0;
    nav->state_clock_us = 0;
    nav->input_step = 0;
    nav->coast_steps = 0U;
    nav->configured = 1;
    return GG_OK;
}

/* ---------------------------------------------------------------- frames */

/* Health bits of a frame's sensors; *known_bad = the readings
 * (GG_FDI3D_BIT) that cannot be used as they are; *whole = 0 when the frame
 * is unusable whatever is rebuilt (accelerometer count, gyro). */
static uint32_t n3_check_frame(const gg_nav3d_t *nav, const gg_frame_t *fr, uint32_t *known_bad,
                               int *whole)
{
    uint32_t h = 0U;
    uint32_t kb = 0U;
    int32_t i;
    int32_t j;
    *whole = 1;
    if (fr->n_acc != N_ACC_3D) {
        h |= GG_HEALTH_ACC_SENSOR;
        *whole = 0;
    }
    for (i = 0; i < N_ACC_3D; ++i) {
        int sensor_bad = 0;
        if (fr->acc_status[i] != GG_SENSOR_OK) {
            h |= GG_HEALTH_ACC_SENSOR;
            sensor_bad = 1;
        }
        for (j = 0; j < 3; ++j) {
            const uint32_t hr = gg_task_check_reading(fr->f[i][j], fr->f_lo[i][j], nav->cfg.f_max);
            h |= hr;
            if ((hr != 0U) || (sensor_bad != 0)) {
                kb |= GG_FDI3D_BIT(i, j);
            }
        }
    }
    *known_bad = kb;
    if (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) {
        if (fr->gyro_status != GG_SENSOR_OK) {
            h |= GG_HEALTH_GYRO_INVALID;
        }
        for (j = 0; j < 3; ++j) {
            const double w = fr->omega_b[j];
            if (!GG_ISFINITE(w) || (w > GG_LIM_W_MAX_RPS) || (w < -GG_LIM_W_MAX_RPS)) {
                h |= GG_HEALTH_GYRO_INVALID;
            }
        }
        if ((h & GG_HEALTH_GYRO_INVALID) != 0U) {
            *whole = 0;
        }
    }
    return h;
}

/* The part of the state a step changes (saved so a failure part-way leaves
 * nothing changed; the configuration and the model are not copied). */
typedef struct {
    gg_gravdr_t gravdr;
    gg_mech_t mech;
    gg_vchan_t vchan;
    gg_real_t q_b_i[4];
    gg_real_t w_k[3];
    gg_real_t w_km1[3];
    gg_real_t w_km2[3];
    gg_real_t omega_dot_b[3];
    int n_w;
    int64_t n_steps;
    gg_real_t sin_th;
    gg_real_t cos_th;
    gg_real_t gamma_b[3][3];
    gg_real_t gamma_e[3][3];
    gg_real_t f_b[3];
    gg_real_t a_c;
    gg_real_t h_ins;
    gg_real_t baro_innov;
} dyn_t;

static void dyn_save(const gg_nav3d_t *nav, dyn_t *d)
{
    size_t j;
    size_t k;
    d->gravdr = nav->gravdr;
    d->mech = nav->mech;
    d->vchan = nav->vchan;
    for (j = 0U; j < 4U; ++j) {
        d->q_b_i[j] = nav->q_b_i[j];
    }
    for (j = 0U; j < 3U; ++j) {
        d->w_k[j] = nav->w_k[j];
        d->w_km1[j] = nav->w_km1[j];
        d->w_km2[j] = nav->w_km2[j];
        d->omega_dot_b[j] = nav->omega_dot_b[j];
        d->f_b[j] = nav->f_b[j];
        for (k = 0U; k < 3U; ++k) {
            d->gamma_b[j][k] = nav->gamma_b[j][k];
            d->gamma_e[j][k] = nav->gamma_e[j][k];
        }
    }
    d->n_w = nav->n_w;
    d->n_steps = nav->n_steps;
    d->sin_th = nav->sin_th;
    d->cos_th = nav->cos_th;
    d->a_c = nav->a_c;
    d->h_ins = nav->h_ins;
    d->baro_innov = nav->baro_innov;
}

static void dyn_restore(gg_nav3d_t *nav, const dyn_t *d)
{
    size_t j;
    size_t k;
    nav->gravdr = d->gravdr;
    nav->mech = d->mech;
    nav->vchan = d->vchan;
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = d->q_b_i[j];
    }
    for (j = 0U; j < 3U; ++j) {
        nav->w_k[j] = d->w_k[j];
        nav->w_km1[j] = d->w_km1[j];
        nav->w_km2[j] = d->w_km2[j];
        nav->omega_dot_b[j] = d->omega_dot_b[j];
        nav->f_b[j] = d->f_b[j];
        for (k = 0U; k < 3U; ++k) {
            nav->gamma_b[j][k] = d->gamma_b[j][k];
            nav->gamma_e[j][k] = d->gamma_e[j][k];
        }
    }
    nav->n_w = d->n_w;
    nav->n_steps = d->n_steps;
    nav->sin_th = d->sin_th;
    nav->cos_th = d->cos_th;
    nav->a_c = d->a_c;
    nav->h_ins = d->h_ins;
    nav->baro_innov = d->baro_innov;
}

/* Inputs of one step, body axes. */
typedef struct {
    gg_real_t gamma_b[3][3];
    gg_real_t f_b[3];
    gg_real_t w[3];
    gg_real_t omega_dot[3];
    gg_real_t trace;
} step_in_t;

/* ---------------------------------------------------------------- state */

/* C_b_i of the current attitude */
static void c_b_i(const gg_nav3d_t *nav, gg_real_t c[3][3])
{
    q_to_dcm(nav->q_b_i, c);
}

/* current G in ECI as compensated values, at the mechanization's position */
static gg_status_t current_g_i(gg_nav3d_t *nav, gg_real_t s, gg_real_t c, gg_acc_t g_i[3],
                               uint32_t *health)
{
    gg_status_t st;
    gg_real_t hi[3];
    gg_real_t lo[3];
    size_t j;
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        gg_real_t r_i[3];
        gg_real_t v_i[3];
        gg_real_t g_e[3];
        uint32_t mflags = 0U;
        st = gg_mech_get(&nav->mech, r_i, v_i);
        if (st == GG_OK) {
            gg_real_t r_e[3];
            rot3(s, c, -1, r_i, r_e);
            st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r_e, g_e, &mflags);
        }
        if ((mflags & GG_GMODEL_OUTSIDE_GRID) != 0U) {
            *health |= GG_HEALTH_MODEL_OUTSIDE;
        }
        if (st == GG_OK) {
            rot3(s, c, +1, g_e, hi);
            lo[0] = 0.0L;
            lo[1] = 0.0L;
            lo[2] = 0.0L;
        }
    } else {
        gg_acc_t ge[3];
        st = gg_gravdr_get_acc(&nav->gravdr, ge);
        if (st == GG_OK) {
            gg_real_t gh[3];
            gg_real_t gl[3];
            for (j = 0U; j < 3U; ++j) {
                gh[j] = ge[j].hi;
                gl[j] = ge[j].lo;
            }
            rot3(s, c, +1, gh, hi);
            rot3(s, c, +1, gl, lo);
        }
    }
    if (st == GG_OK) {
        for (j = 0U; j < 3U; ++j) {
            gg_acc_set(&g_i[j], hi[j]);
            gg_acc_add(&g_i[j], lo[j]);
        }
    }
    return st;
}

/* First accepted frame: start every module at the configured state. */
static gg_status_t n3_start(gg_nav3d_t *nav, const step_in_t *in)
{
    gg_real_t c[3][3];
    gg_real_t gamma_i[3][3];
    gg_real_t f_i[3];
    gg_real_t g0[3];
    gg_status_t st = GG_OK;
    size_t j;
    size_t k;
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = nav->cfg.q0_b_e[j];
    }
    st = q_normalize(nav->q_b_i);
    if (st != GG_OK) {
        return st;
    }
    c_b_i(nav, c);
    similarity(c, in->gamma_b, gamma_i);
    mat_vec(c, in->f_b, f_i);
    for (j = 0U; j < 3U; ++j) {
        g0[j] = nav->cfg.g0_e[j];
    }
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, nav->cfg.r0_e, g0, NULL);
    }
    if (st == GG_OK) {
        gg_gravdr_config_t gc;
        for (j = 0U; j < 3U; ++j) {
            gc.g0[j] = g0[j];
            for (k = 0U; k < 3U; ++k) {
                gc.gamma0[j][k] = gamma_i[j][k];
            }
        }
        gc.trapezoid_only = 0;
        st = gg_gravdr_init(&nav->gravdr, &gc);
    }
    if (st == GG_OK) {
        gg_mech_config_t mc;
        const gg_real_t w = nav->omega_ie;
        mc.dt_s = nav->dt_s;
        for (j = 0U; j < 3U; ++j) {
            mc.r0[j] = nav->cfg.r0_e[j];
            mc.a0[j] = f_i[j] + g0[j];
        }
        /* inertial velocity = Earth-relative + omega x r */
        mc.v0[0] = nav->cfg.v0_e[0] - (w * nav->cfg.r0_e[1]);
        mc.v0[1] = nav->cfg.v0_e[1] + (w * nav->cfg.r0_e[0]);
        mc.v0[2] = nav->cfg.v0_e[2];
        st = gg_mech_init(&nav->mech, &mc);
    }
    if (st == GG_OK) {
        nav->n_steps = 0;
        nav->sin_th = 0.0L;
        nav->cos_th = 1.0L;
        nav->n_w = 1;
        nav->a_c = 0.0L;
        nav->h_ins = 0.0L;
        nav->baro_innov = 0.0L;
        for (j = 0U; j < 3U; ++j) {
            nav->w_k[j] = in->w[j];
            nav->w_km1[j] = in->w[j];
            nav->w_km2[j] = in->w[j];
            nav->omega_dot_b[j] = in->omega_dot[j];
            for (k = 0U; k < 3U; ++k) {
                nav->gamma_e[j][k] = gamma_i[j][k];
            }
        }
    }
    return st;
}

/* q' = 1/2 q (x) (0, w) */
static void qdot(const gg_real_t q[4], const gg_real_t w[3], gg_real_t d[4])
{
    const gg_real_t p[4] = {0.0L, w[0], w[1], w[2]};
    size_t j;
    qmul(q, p, d);
    for (j = 0U; j < 4U; ++j) {
        d[j] *= 0.5L;
    }
}

/* Fourth-order Runge-Kutta attitude step with the rate interpolated through
 * the samples k-2 .. k+1, or by cubic Hermite with the measured angular
 * accelerations wd1 (at k+1) and nav->omega_dot_b (at k) on the first two steps (nav3d.h). */
static gg_status_t attitude_step(gg_nav3d_t *nav, const gg_real_t w1[3], const gg_real_t wd1[3])
{
    const gg_real_t h = nav->dt_s;
    gg_real_t wm[3];
    gg_real_t k1[4];
    gg_real_t k2[4];
    gg_real_t k3[4];
    gg_real_t k4[4];
    gg_real_t qt[4];
    gg_real_t q[4];
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        if (nav->n_w >= 3) {
            /* cubic through t_k - 2h, t_k - h, t_k, t_k + h at t_k + h/2:
             * Lagrange weights 1/16, -5/16, 15/16, 5/16 */
            wm[j] = (nav->w_km2[j] - (5.0L * nav->w_km1[j]) + (15.0L * nav->w_k[j]) +
                     (5.0L * w1[j])) * 0.0625L;
        } else {
            /* cubic Hermite at h/2: (w_k + w1)/2 + h/8 (wd_k - wd1) */
            wm[j] = (0.5L * (nav->w_k[j] + w1[j])) + ((0.125L * h) * (nav->omega_dot_b[j] - wd1[j]));
        }
    }
    qdot(nav->q_b_i, nav->w_k, k1);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (0.5L * h * k1[j]);
    }
    qdot(qt, wm, k2);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (0.5L * h * k2[j]);
    }
    qdot(qt, wm, k3);
    for (j = 0U; j < 4U; ++j) {
        qt[j] = nav->q_b_i[j] + (h * k3[j]);
    }
    qdot(qt, w1, k4);
    for (j = 0U; j < 4U; ++j) {
        q[j] = nav->q_b_i[j] + ((h / 6.0L) * (k1[j] + (2.0L * (k2[j] + k3[j])) + k4[j]));
    }
    if (q_normalize(q) != GG_OK) {
        return GG_ERR_RANGE;
    }
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = q[j];
    }
    return GG_OK;
}

static uint32_t n3_baro_health(uint32_t vh)
{
    uint32_t h = 0U;
    h |= ((vh & GG_VCHAN_INVALID) != 0U) ? GG_HEALTH_BARO_INVALID : 0U;
    h |= ((vh & GG_VCHAN_STALE) != 0U) ? GG_HEALTH_BARO_STALE : 0U;
    h |= ((vh & GG_VCHAN_OUTLIER) != 0U) ? GG_HEALTH_BARO_OUTLIER : 0U;
    h |= ((vh & GG_VCHAN_RECAPTURE) != 0U) ? GG_HEALTH_BARO_RECAPTURE : 0U;
    h |= ((vh & GG_VCHAN_COAST) != 0U) ? GG_HEALTH_BARO_COAST : 0U;
    return h;
}

/* Barometric loop along the ellipsoid normal, after the step. */
static gg_status_t n3_baro_step(gg_nav3d_t *nav, const gg_frame_t *fr, uint32_t *health)
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t cen[3][3];
    gg_real_t h;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st == GG_OK) {
        gg_real_t r_e[3];
        rot3(nav->sin_th, nav->cos_th, -1, r_i, r_e);
        st = local_frame(r_e, &h, cen);
    }
    if (st == GG_OK) {
        nav->h_ins = h;
    }
    if ((st == GG_OK) && (nav->cfg.baro_enable != 0)) {
        gg_vchan_sample_t smp;
        gg_vchan_output_t vo;
        smp.alt_m = fr->baro_alt_m;
        smp.utime = fr->baro_utime;
        smp.status = fr->baro_status;
        st = gg_vchan_step(&nav->vchan, fr->utime, h, &smp, &vo);
        if (st == GG_OK) {
            gg_real_t u_e[3];
            gg_real_t u_i[3];
            gg_real_t dr_e[3];
            gg_real_t dr_i[3];
            gg_real_t dv_i[3];
            gg_real_t dg_e[3];
            gg_real_t dg_i[3];
            gg_real_t da[3];
            size_t j;
            for (j = 0U; j < 3U; ++j) {
                u_e[j] = -cen[2][j]; /* up = -down */
                dr_e[j] = vo.dh_m * u_e[j];
            }
            rot3(nav->sin_th, nav->cos_th, +1, u_e, u_i);
            for (j = 0U; j < 3U; ++j) {
                dr_i[j] = vo.dh_m * u_i[j];
                dv_i[j] = vo.dv_mps * u_i[j];
            }
            /* the correction is Earth-relative: moving r_i by dr at fixed v_i would
             * change v_e = v_i - w x r_i by -w x dr (east, ~7e-5 m/s per metre), so
             * v_i moves by w x dr as well */
            dv_i[0] -= nav->omega_ie * dr_i[1];
            dv_i[1] += nav->omega_ie * dr_i[0];
            mat_vec(nav->gamma_e, dr_e, dg_e);
            rot3(nav->sin_th, nav->cos_th, +1, dg_e, dg_i);
            for (j = 0U; j < 3U; ++j) {
                da[j] = dg_i[j] - ((vo.a_c - nav->a_c) * u_i[j]);
            }
            st = gg_mech_correct(&nav->mech, dr_i, dv_i, da);
            if ((st == GG_OK) && (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER)) {
                st = gg_gravdr_correct(&nav->gravdr, dg_e);
            }
            if (st == GG_OK) {
                nav->a_c = vo.a_c;
                if (vo.accepted != 0) {
                    nav->baro_innov = vo.innov_m;
                }
                *health |= n3_baro_health(vo.health);
            }
        }
    }
    return st;
}

/* Up unit vector in ECI at the mechanization's current position. */
static gg_status_t up_i(const gg_nav3d_t *nav, gg_real_t s, gg_real_t c, gg_real_t u_i[3])
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t cen[3][3];
    gg_real_t h;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st == GG_OK) {
        gg_real_t r_e[3];
        rot3(s, c, -1, r_i, r_e);
        st = local_frame(r_e, &h, cen);
    }
    if (st == GG_OK) {
        const gg_real_t u_e[3] = {-cen[2][0], -cen[2][1], -cen[2][2]};
        rot3(s, c, +1, u_e, u_i);
    }
    return st;
}

/* Advance the modules by one step with the inputs of its end point (or
 * start them on the first frame). The caller restores the state on failure. */
static gg_status_t n3_advance(gg_nav3d_t *nav, const gg_frame_t *fr, const step_in_t *in,
                           const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st = GG_OK;
    uint32_t t0;
    if (nav->started == 0) {
        st = n3_start(nav, in);
    } else {
        const int64_t n1 = nav->n_steps + 1;
        const gg_real_t th1 = nav->omega_ie * ((gg_real_t)n1 * nav->dt_s);
        /* half-step angle and mid-step angle (addition theorem from theta_k) */
        const gg_real_t sh = nav->sin_hstep;
        const gg_real_t ch = nav->cos_hstep;
        const gg_real_t sm = (nav->sin_th * ch) + (nav->cos_th * sh);
        const gg_real_t cm = (nav->cos_th * ch) - (nav->sin_th * sh);
        gg_real_t s1 = 0.0L;
        gg_real_t c1 = 1.0L;
        gg_real_t gamma_i[3][3];
        gg_real_t f_i[3];
        gg_real_t r_k[3];
        gg_real_t dr_i[3];
        gg_acc_t g_i[3];
        uint32_t t1;
        size_t j;
        t0 = gg_task_cycles(hal);
        st = gg_sincos(th1, &s1, &c1);
        if ((st == GG_OK) && (nav->cfg.platform == GG_PLATFORM_STRAPDOWN)) {
            st = attitude_step(nav, in->w, in->omega_dot);
        }
        if (st == GG_OK) {
            gg_real_t cb[3][3];
            gg_real_t v_k[3];
            c_b_i(nav, cb);
            similarity(cb, in->gamma_b, gamma_i);
            mat_vec(cb, in->f_b, f_i);
            st = gg_mech_get(&nav->mech, r_k, v_k);
        }
        t1 = gg_task_cycles(hal);
        cyc[GG_MOD_DIFF] += t1 - t0;
        if (st == GG_OK) {
            st = gg_mech_step_position(&nav->mech, dr_i);
        }
        t0 = gg_task_cycles(hal);
        cyc[GG_MOD_MECH] += t0 - t1;
        if (st == GG_OK) {
            /* dr_e = R3(-th1) dr_i + [R3(-th1) - R3(-th0)] r_i(k); c1 - c0 = -2 sh sm,
             * s1 - s0 = 2 sh cm (half-angle identities: no cancellation) */
            const gg_real_t dc = -2.0L * sh * sm;
            const gg_real_t ds = 2.0L * sh * cm;
            gg_real_t dr_e[3];
            gg_real_t r_inv[3][3];
            rot3(s1, c1, -1, dr_i, dr_e);
            dr_e[0] += (dc * r_k[0]) + (ds * r_k[1]);
            dr_e[1] += (-ds * r_k[0]) + (dc * r_k[1]);
            rot3_mat(s1, c1, -1, r_inv);
            mat33_t gi;
            const mat33_t *gip = &gi;
            mat33_t ge;
            const mat33_t *gep = &ge;
            mat_copy(gamma_i, &gi);
            similarity(r_inv, gip->m, nav->gamma_e);
            mat_copy(nav->gamma_e, &ge);
            if (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER) {
                st = gg_gravdr_step(&nav->gravdr, gep->m, dr_e);
            }
        }
        if (st == GG_OK) {
            st = current_g_i(nav, s1, c1, g_i, health);
        }
        t1 = gg_task_cycles(hal);
        cyc[GG_MOD_GRAVDR] += t1 - t0;
        if (st == GG_OK) {
            gg_real_t u[3] = {0.0L, 0.0L, 0.0L};
            if (nav->cfg.baro_enable != 0) {
                st = up_i(nav, s1, c1, u);
            }
            if (st == GG_OK) {
                gg_real_t f_next[3];
                for (j = 0U; j < 3U; ++j) {
                    f_next[j] = f_i[j] - (nav->a_c * u[j]);
                }
                st = gg_mech_step_velocity(&nav->mech, f_next, g_i);
            }
        }
        cyc[GG_MOD_MECH] += gg_task_cycles(hal) - t1;
        if (st == GG_OK) {
            nav->n_steps += 1;
            nav->sin_th = s1;
            nav->cos_th = c1;
            for (j = 0U; j < 3U; ++j) {
                nav->w_km2[j] = nav->w_km1[j];
                nav->w_km1[j] = nav->w_k[j];
                nav->w_k[j] = in->w[j];
                nav->omega_dot_b[j] = in->omega_dot[j];
            }
            nav->n_w = (nav->n_w < 3) ? (nav->n_w + 1) : 3;
        }
    }
    t0 = gg_task_cycles(hal);
    if (st == GG_OK) {
        st = n3_baro_step(nav, fr, health);
    }
    cyc[GG_MOD_VCHAN] += gg_task_cycles(hal) - t0;
    return st;
}

/* Differencing of one frame: body-axis gradient, centre force, angular
 * acceleration and parity. */
static gg_status_t difference(const gg_nav3d_t *nav, const gg_frame_t *fr, step_in_t *in)
{
    gg_diff3d_input_t di;
    gg_diff3d_output_t d;
    gg_status_t st;
    size_t i;
    size_t j;
    for (i = 0U; i < 6U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            di.f[i][j] = fr->f[i][j];
            di.f_lo[i][j] = fr->f_lo[i][j];
        }
    }
    for (j = 0U; j < 3U; ++j) {
        di.omega_b[j] = (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) ? (gg_real_t)fr->omega_b[j]
                                                                      : 0.0L;
    }
    st = gg_diff3d_step(&nav->diff, &di, &d);
    if (st == GG_OK) {
        for (j = 0U; j < 3U; ++j) {
            size_t k;
            in->f_b[j] = d.f_c[j];
            in->w[j] = di.omega_b[j];
            in->omega_dot[j] = d.omega_dot[j];
            for (k = 0U; k < 3U; ++k) {
                in->gamma_b[j][k] = d.gamma[j][k];
            }
        }
        in->trace = d.trace;
    }
    return st;
}

/* Bridge lost frames: f_b, Gamma_b, w and omega_dot interpolated linearly between the
 * last accepted frame and this one, no barometer. */
static gg_status_t n3_bridge(gg_nav3d_t *nav, const gg_frame_t *fr, const step_in_t *in,
                          int64_t missing, const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT],
                          uint32_t *health)
{
    gg_status_t st = GG_OK;
    step_in_t base;
    int64_t i;
    size_t j;
    size_t k;
    /* the last accepted frame's inputs (advance moves w_k on) */
    base = *in;
    for (j = 0U; j < 3U; ++j) {
        base.f_b[j] = nav->f_b[j];
        base.w[j] = nav->w_k[j];
        base.omega_dot[j] = nav->omega_dot_b[j];
        for (k = 0U; k < 3U; ++k) {
            base.gamma_b[j][k] = nav->gamma_b[j][k];
        }
    }
    for (i = 1; (i <= missing) && (i <= GG_NAV3D_MAX_BRIDGE) && (st == GG_OK); ++i) {
        const gg_real_t w = (gg_real_t)i / ((gg_real_t)missing + 1.0L);
        step_in_t bi;
        gg_frame_t fi;
        bi = *in;
        fi = *fr;
        for (j = 0U; j < 3U; ++j) {
            bi.f_b[j] = base.f_b[j] + (w * (in->f_b[j] - base.f_b[j]));
            bi.w[j] = base.w[j] + (w * (in->w[j] - base.w[j]));
            bi.omega_dot[j] = base.omega_dot[j] + (w * (in->omega_dot[j] - base.omega_dot[j]));
            for (k = 0U; k < 3U; ++k) {
                bi.gamma_b[j][k] =
                    base.gamma_b[j][k] + (w * (in->gamma_b[j][k] - base.gamma_b[j][k]));
            }
        }
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        fi.baro_status = GG_SENSOR_ABSENT;
        st = n3_advance(nav, &fi, &bi, hal, cyc, health);
    }
    return st;
}

/* Coast n steps on the last usable inputs (f_b, Gamma_b, w and omega_dot
 * held; an outage longer than the bridge), no barometer. */
static gg_status_t n3_coast(gg_nav3d_t *nav, const gg_frame_t *fr, int64_t n, const gg_hal_t *hal,
                            uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st = GG_OK;
    step_in_t hold;
    gg_frame_t fi = *fr;
    int64_t i;
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        hold.f_b[j] = nav->f_b[j];
        hold.w[j] = nav->w_k[j];
        hold.omega_dot[j] = nav->omega_dot_b[j];
        for (k = 0U; k < 3U; ++k) {
            hold.gamma_b[j][k] = nav->gamma_b[j][k];
        }
    }
    hold.trace = 0.0L;
    fi.baro_status = GG_SENSOR_ABSENT;
    for (i = 1; (i <= n) && (i <= GG_TASK_CATCHUP_STEPS) && (st == GG_OK); ++i) {
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        st = n3_advance(nav, &fi, &hold, hal, cyc, health);
    }
    return st;
}

/* Parity residuals: antisymmetric part against 0 (stabilized) or against the
 * gyro-derived angular acceleration (strapdown), and the trace. */
static void n3_parity(const gg_nav3d_t *nav, const step_in_t *in, gg_real_t p[4])
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        if (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) {
            /* third-order backward difference; needs three earlier gyro
             * samples, 0 (no evidence) on the first three steps */
            if ((nav->started != 0) && (nav->n_w >= 3)) {
                p[j] = in->omega_dot[j] -
                       (((11.0L * in->w[j]) - (18.0L * nav->w_k[j]) + (9.0L * nav->w_km1[j]) -
                         (2.0L * nav->w_km2[j])) /
                        (6.0L * nav->dt_s));
            } else {
                p[j] = 0.0L;
            }
        } else {
            p[j] = in->omega_dot[j];
        }
    }
    p[3] = in->trace;
}

static void n3_fill_output(const gg_nav3d_t *nav, const gg_frame_t *fr, gg_status_t status,
                        uint32_t health, gg_nav3d_output_t *out)
{
    const gg_nav3d_output_t empty = {0};
    size_t j;
    size_t k;
    *out = empty;
    out->utime = fr->utime;
    out->seq = fr->seq;
    out->status = (int32_t)status;
    out->health = health;
    if ((nav->started == 0) || (nav->mech.initialized == 0)) {
        gg_real_t lat = 0.0L;
        gg_real_t lon = 0.0L;
        gg_real_t h = 0.0L;
        out->health |= GG_HEALTH_NOT_INIT;
        if (nav->configured != 0) {
            for (j = 0U; j < 3U; ++j) {
                out->r_e[j] = (double)nav->cfg.r0_e[j];
                out->v_e[j] = (double)nav->cfg.v0_e[j];
                out->g_e[j] = (double)nav->cfg.g0_e[j];
            }
            if (gg_nav3d_ecef_to_geodetic(nav->cfg.r0_e, &lat, &lon, &h) == GG_OK) {
                out->lat_rad = (double)lat;
                out->lon_rad = (double)lon;
                out->h_m = (double)h;
            }
        }
        return;
    }
    {
        const gg_real_t s = nav->sin_th;
        const gg_real_t c = nav->cos_th;
        const gg_real_t w = nav->omega_ie;
        const gg_real_t th = w * ((gg_real_t)nav->n_steps * nav->dt_s);
        gg_real_t rh[3];
        gg_real_t rl[3];
        gg_real_t reh[3];
        gg_real_t rel[3];
        gg_real_t r_e[3];
        gg_real_t v_rel[3];
        gg_real_t v_e[3];
        gg_real_t cen[3][3];
        gg_real_t cb[3][3];
        gg_real_t cbe[3][3];
        gg_real_t cbn[3][3];
        gg_real_t r_inv[3][3];
        gg_real_t lat = 0.0L;
        gg_real_t lon = 0.0L;
        gg_real_t h = 0.0L;
        gg_real_t sh = 0.0L;
        gg_real_t ch = 1.0L;
        gg_real_t a = 0.0L;
        gg_acc_t ra[3];
        gg_acc_t va[3];
        if (gg_mech_get_acc(&nav->mech, ra, va) != GG_OK) {
            out->health |= GG_HEALTH_NOT_INIT;
            return;
        }
        for (j = 0U; j < 3U; ++j) {
            rh[j] = ra[j].hi;
            rl[j] = ra[j].lo;
            v_rel[j] = gg_acc_value(&va[j]);
        }
        rot3(s, c, -1, rh, reh);
        rot3(s, c, -1, rl, rel);
        for (j = 0U; j < 3U; ++j) {
            r_e[j] = reh[j] + rel[j];
            out->r_e[j] = (double)r_e[j];
            out->r_e_lo[j] = (double)(r_e[j] - (gg_real_t)out->r_e[j]);
        }
        /* Earth-relative velocity: v_i - omega x r_i, rotated into ECEF */
        {
            const gg_real_t r0 = rh[0] + rl[0];
            const gg_real_t r1 = rh[1] + rl[1];
            v_rel[0] += w * r1;
            v_rel[1] -= w * r0;
        }
        rot3(s, c, -1, v_rel, v_e);
        if ((local_frame(r_e, &h, cen) != GG_OK) ||
            (gg_nav3d_ecef_to_geodetic(r_e, &lat, &lon, &h) != GG_OK)) {
            out->health |= GG_HEALTH_NOT_INIT;
        }
        out->lat_rad = (double)lat;
        out->lon_rad = (double)lon;
        out->h_m = (double)h;
        {
            gg_real_t vn[3];
            mat_vec(cen, v_e, vn);
            for (j = 0U; j < 3U; ++j) {
                out->v_e[j] = (double)v_e[j];
                out->v_n[j] = (double)vn[j];
            }
        }
        if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
            gg_real_t g[3] = {0.0L, 0.0L, 0.0L};
            (void)gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r_e, g, NULL);
            for (j = 0U; j < 3U; ++j) {
                out->g_e[j] = (double)g[j];
            }
        } else {
            gg_acc_t g[3];
            if (gg_gravdr_get_acc(&nav->gravdr, g) == GG_OK) {
                for (j = 0U; j < 3U; ++j) {
                    const gg_real_t gv = gg_acc_value(&g[j]);
                    out->g_e[j] = (double)gv;
                    out->g_e_lo[j] = (double)(gv - (gg_real_t)out->g_e[j]);
                }
            }
        }
        /* attitude: C_b_e = R3(-theta) C_b_i; q_b_e = q_i_e (x) q_b_i with
         * q_i_e = (cos theta/2, 0, 0, -sin theta/2) */
        c_b_i(nav, cb);
        rot3_mat(s, c, -1, r_inv);
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                cbe[j][k] = (r_inv[j][0] * cb[0][k]) + (r_inv[j][1] * cb[1][k]) +
                            (r_inv[j][2] * cb[2][k]);
            }
        }
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                cbn[j][k] = (cen[j][0] * cbe[0][k]) + (cen[j][1] * cbe[1][k]) +
                            (cen[j][2] * cbe[2][k]);
            }
        }
        if (gg_sincos(0.5L * th, &sh, &ch) == GG_OK) {
            const gg_real_t qie[4] = {ch, 0.0L, 0.0L, -sh};
            gg_real_t qbe[4];
            qmul(qie, nav->q_b_i, qbe);
            for (j = 0U; j < 4U; ++j) {
                out->q_b_e[j] = (double)qbe[j];
            }
        }
        if (gg_atan2(cbn[2][1], cbn[2][2], &a) == GG_OK) {
            out->rpy_rad[0] = (double)a;
        }
        if (gg_atan2(-cbn[2][0], sqrtl((cbn[2][1] * cbn[2][1]) + (cbn[2][2] * cbn[2][2])), &a) ==
            GG_OK) {
            out->rpy_rad[1] = (double)a;
        }
        if (gg_atan2(cbn[1][0], cbn[0][0], &a) == GG_OK) {
            out->rpy_rad[2] = (double)a;
        }
        out->t_s = (double)((gg_real_t)nav->n_steps * nav->dt_s);
    }
    for (j = 0U; j < 3U; ++j) {
        out->f_b[j] = (double)nav->f_b[j];
        out->omega_b[j] = (double)nav->w_k[j];
        out->omega_dot_b[j] = (double)nav->omega_dot_b[j];
        for (k = 0U; k < 3U; ++k) {
            out->gamma_e[j][k] = (double)nav->gamma_e[j][k];
            out->gamma_b[j][k] = (double)nav->gamma_b[j][k];
        }
    }
    for (j = 0U; j < 4U; ++j) {
        out->parity[j] = (double)nav->parity[j];
    }
    out->h_ins_m = (double)nav->h_ins;
    out->baro_innov_m = (double)nav->baro_innov;
    out->g_up_corr = (double)nav->a_c;
}

gg_status_t gg_nav3d_step(gg_nav3d_t *nav, const gg_frame_t *frame, const gg_hal_t *hal,
                          gg_nav3d_output_t *out)
{
    uint32_t cyc[GG_MOD_COUNT] = {0U, 0U, 0U, 0U, 0U};
    const uint32_t t_start = gg_task_cycles(hal);
    uint32_t health;
    gg_status_t st = GG_OK;
    gg_status_t st_read = GG_OK;
    step_in_t in;
    gg_real_t par[4] = {0.0L, 0.0L, 0.0L, 0.0L};
    int64_t fstep = -1;
    int used = 0;
    uint32_t known_bad = 0U;
    uint32_t rebuilt = 0U;
    int whole = 1;
    gg_fdi3d_t fdi_saved;
    gg_frame_t fixed;
    if ((nav == NULL) || (frame == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (nav->configured == 0) {
        const gg_nav3d_output_t empty = {0};
        *out = empty;
        out->utime = frame->utime;
        out->seq = frame->seq;
        out->status = (int32_t)GG_ERR_NOT_INIT;
        out->health = GG_HEALTH_NOT_INIT | GG_HEALTH_FRAME_REJECTED;
        return GG_ERR_NOT_INIT;
    }
    fdi_saved = nav->fdi;
    health = n3_check_frame(nav, frame, &known_bad, &whole);
    health |= gg_task_seq_update(&nav->seq, frame, &fstep);
    if (fstep < 0) {
        st_read = GG_ERR_SEQUENCE;
    } else if (whole == 0) {
        st_read = GG_ERR_SENSOR;
    } else {
        const uint32_t t0 = gg_task_cycles(hal);
        gg_real_t w_now[3];
        gg_real_t wd_ref[3];
        const gg_real_t *wd_p = NULL;
        gg_fdi3d_output_t fo;
        size_t j;
        fixed = *frame;
        for (j = 0U; j < 3U; ++j) {
            w_now[j] = (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) ? (gg_real_t)frame->omega_b[j]
                                                                    : 0.0L;
            /* the gyro-derived angular acceleration (third-order backward
             * difference, as the parity below), once three earlier samples exist */
            wd_ref[j] = ((11.0L * w_now[j]) - (18.0L * nav->w_k[j]) + (9.0L * nav->w_km1[j]) -
                         (2.0L * nav->w_km2[j])) /
                        (6.0L * nav->dt_s);
        }
        if ((nav->started != 0) && (nav->n_w >= 3) && (fstep == (nav->state_step + 1))) {
            wd_p = wd_ref;
        }
        st_read = gg_fdi3d_step(&nav->fdi, known_bad, w_now, wd_p, fixed.f, fixed.f_lo, &fo);
        rebuilt = fo.rebuilt;
        if ((fo.flags & GG_FDI3D_DETECTED) != 0U) {
            health |= GG_HEALTH_ACC_FAULT;
        }
        if ((st_read == GG_OK) && ((fo.flags & GG_FDI3D_PAIR) != 0U)) {
            health |= GG_HEALTH_GRAD_COAST;
        }
        if (st_read != GG_OK) {
            /* the readings' own fault, as the health word says */
            if ((health & GG_HEALTH_ACC_NONFINITE) != 0U) {
                st_read = GG_ERR_NONFINITE;
            } else if ((health & GG_HEALTH_ACC_RANGE) != 0U) {
                st_read = GG_ERR_RANGE;
            } else {
                st_read = GG_ERR_SENSOR; /* flagged bad, or a fault parity cannot isolate */
            }
        } else {
            if (rebuilt != 0U) {
                health |= GG_HEALTH_ACC_REBUILT;
            }
            st_read = difference(nav, &fixed, &in);
        }
        cyc[GG_MOD_DIFF] = gg_task_cycles(hal) - t0;
    }
    st = st_read;
    if (fstep >= 0) {
        /* module states saved so a failure part-way leaves nothing changed */
        dyn_t saved;
        const int64_t step_saved = nav->state_step;
        const int64_t clock_saved = nav->state_clock_us;
        gg_task_plan_t plan = {0, 0, 0};
        gg_status_t st_nav = GG_OK;
        uint32_t step_health = 0U;
        gg_frame_t ft;
        ft = *frame;
        ft.utime = gg_task_seq_clock(&nav->seq, frame->utime);
        if ((frame->baro_utime >= 0) && (frame->baro_utime <= GG_TIME_MAX)) {
            ft.baro_utime = gg_task_seq_clock(&nav->seq, frame->baro_utime);
        }
        if (st_read == GG_OK) {
            n3_parity(nav, &in, par);
        }
        dyn_save(nav, &saved);
        if (nav->started == 0) {
            if (st_read == GG_OK) {
                plan.use = 1;
            }
        } else {
            gg_task_plan(fstep, nav->state_step, (st_read == GG_OK) ? 1 : 0, GG_NAV3D_MAX_BRIDGE,
                         &plan);
        }
        if (plan.coast > 0) {
            st_nav = n3_coast(nav, &ft, plan.coast, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                nav->state_step += plan.coast;
                nav->state_clock_us += plan.coast * nav->cfg.dt_us;
                step_health |= GG_HEALTH_COAST;
            }
        }
        if ((st_nav == GG_OK) && (plan.use != 0)) {
            st_nav = n3_bridge(nav, &ft, &in, plan.bridge, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                st_nav = n3_advance(nav, &ft, &in, hal, cyc, &step_health);
            }
        }
        if (st_nav != GG_OK) {
            dyn_restore(nav, &saved);
            nav->state_step = step_saved;
            nav->state_clock_us = clock_saved;
            st = st_nav;
        } else {
            health |= step_health;
            if (plan.coast > 0) {
                nav->coast_steps += (uint32_t)plan.coast;
            }
            if (plan.use != 0) {
                used = 1;
                nav->state_step = fstep;
                nav->state_clock_us = ft.utime;
            } else if (st == GG_OK) {
                st = GG_ERR_SEQUENCE; /* still catching up an outage: not used yet */
            } else {
                /* the readings' own error */
            }
        }
    }
    if (used != 0) {
        size_t j;
        size_t k;
        for (j = 0U; j < 3U; ++j) {
            nav->f_b[j] = in.f_b[j];
            for (k = 0U; k < 3U; ++k) {
                nav->gamma_b[j][k] = in.gamma_b[j][k];
            }
        }
        for (j = 0U; j < 4U; ++j) {
            const gg_real_t lim = (gg_real_t)nav->cfg.asym_max;
            nav->parity[j] = par[j];
            if ((par[j] > lim) || (par[j] < -lim)) {
                health |= GG_HEALTH_GAMMA_ASYM;
            }
        }
        nav->started = 1;
        nav->input_step = fstep;
    } else {
        nav->fdi = fdi_saved;
        rebuilt = 0U;
        health |= GG_HEALTH_FRAME_REJECTED;
    }
    n3_fill_output(nav, frame, st, health, out);
    out->acc_rebuilt = rebuilt;
    out->acc_excluded = nav->fdi.excluded;
    out->resync_count = nav->seq.resyncs;
    out->coast_steps = nav->coast_steps;
    if (nav->started != 0) {
        const int64_t d_in = nav->seq.last_step - nav->input_step;
        const int64_t d_state = nav->seq.last_step - nav->state_step;
        out->outage_s = (double)((gg_real_t)d_in * nav->dt_s);
        out->state_lag_s = (double)((gg_real_t)d_state * nav->dt_s);
    }
    out->health |= gg_task_close_cycles(hal, nav->cfg.dt_us, t_start, cyc, out->cycles);
    return st;
}

gg_status_t gg_nav3d_task_cycle(gg_nav3d_t *nav, const gg_hal_t *hal)
{
    gg_frame_t frame;
    gg_nav3d_output_t out;
    gg_status_t st;
    gg_status_t st_step;
    if ((nav == NULL) || (hal == NULL) || (hal->read_frame == NULL) ||
        (hal->write_output3d == NULL)) {
        return GG_ERR_NULL;
    }
    st = hal->read_frame(hal->ctx, &frame);
    if (st != GG_OK) {
        return st;
    }
    st_step = gg_nav3d_step(nav, &frame, hal, &out);
    st = hal->write_output3d(hal->ctx, &out);
    if (st != GG_OK) {
        return GG_ERR_IO;
    }
    return st_step;
}
