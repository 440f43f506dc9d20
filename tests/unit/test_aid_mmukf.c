/* The gradient-map UKF as an aiding source of the 3-D task (aid_mmukf.h),
 * flown in-process against closed-form truth (truth3.h): an eastbound flight
 * on a rotating Earth over buried masses, the accelerometer readings with
 * white noise, and an onboard map tile built from the same analytic field
 * (point-mass gradients in closed form, independent of the firmware). The
 * task starts with a position error; the aid must recover it with
 * consistent statistics (NEES, NIS in their 95 % bands), and with the aid
 * off (or without a map) the task must be unchanged bit for bit. */
#include "test_common.h"
#include "truth3.h"
#include "ggins/aid_mmukf.h"
#include "ggins/gmap.h"
#include "ggins/limits.h"
#include "ggins/vchan.h"
#include "nav3d_int.h" /* n3_aid_apply: the task's side of a correction */

#define DT_US 10000
#define SIGMA_G 1.0e-11          /* gradiometer noise of a diagonal component, s^-2 (0.01 E) */
#define HB 0.5L                  /* half-baselines, m */
#define N_ANOM 12

static gg_gmap_tile_t g_tile;
static gg_gmap_t g_map;
static gg_nav3d_t g_nav;
static gg_nav3d_t g_nav_ref;

/* ---------------------------------------------------------------- truth */

static void flight_truth(truth3_t *T)
{
    memset(T, 0, sizeof *T);
    T->lat0 = 0.7L;
    T->lon0 = 0.2L;
    T->h0 = 3000.0L;
    for (int j = 0; j < 3; ++j) {
        T->hb[j] = HB;
        T->c0[j][j] = 1.0L;
    }
    /* 200 m/s east */
    {
        const long double e2 = F_WGS * (2.0L - F_WGS);
        const long double n = A_WGS / sqrtl(1.0L - e2 * sinl(T->lat0) * sinl(T->lat0));
        T->lon_rate = 200.0L / ((n + T->h0) * cosl(T->lat0));
    }
    /* buried masses along the route, 6-7 km apart, 1.5-2.5 km either side,
     * 3 km below the ellipsoid (10-20 E at the flight height) */
    T->n_anom = N_ANOM;
    for (int a = 0; a < N_ANOM; ++a) {
        long double p[3];
        const long double dlat = ((a % 2) == 0 ? 1.0L : -1.0L) * (2.5e-4L + 1.0e-4L * (long double)(a % 3));
        geo2ecef(T->lat0 + dlat, T->lon0 + 1.0e-3L * (long double)a, -3000.0L - 300.0L * (long double)(a % 4), p);
        memcpy(T->anom_e[a], p, sizeof p);
        T->anom_gm[a] = ((a % 3) == 1 ? -1.0L : 1.0L) * (1.5e3L + 250.0L * (long double)(a % 5));
    }
}

/* analytic gravitation gradient in ECEF: (GM/d^3)(3 d^ d^T - I) per mass */
static void gamma_e_truth(const truth3_t *T, const long double r[3], long double G[3][3])
{
    t_point_mass_gamma(r, G);
    for (int a = 0; a < T->n_anom; ++a) {
        long double d[3], dd = 0;
        for (int j = 0; j < 3; ++j) {
            d[j] = r[j] - T->anom_e[a][j];
            dd += d[j] * d[j];
        }
        const long double k = T->anom_gm[a] / (dd * sqrtl(dd));
        for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) G[j][l] += k * (3.0L * d[j] * d[l] / dd - (j == l ? 1.0L : 0.0L));
    }
}

/* rows north, east, down at geodetic (lat, lon) */
static void ned_rows(long double lat, long double lon, long double c[3][3])
{
    const long double sl = sinl(lat), cl = cosl(lat), so = sinl(lon), co = cosl(lon);
    const long double m[3][3] = {{-sl * co, -sl * so, cl}, {-so, co, 0.0L}, {-cl * co, -cl * so, -sl}};
    memcpy(c, m, sizeof m);
}

static void gamma_ned6(const truth3_t *T, long double lat, long double lon, long double h, double g6[6])
{
    long double r[3], ge[3][3], c[3][3], t[3][3], gn[3][3];
    geo2ecef(lat, lon, h, r);
    gamma_e_truth(T, r, ge);
    ned_rows(lat, lon, c);
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            t[j][k] = 0;
            for (int l = 0; l < 3; ++l) t[j][k] += c[j][l] * ge[l][k];
        }
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) {
            gn[j][k] = 0;
            for (int l = 0; l < 3; ++l) gn[j][k] += t[j][l] * c[k][l];
        }
    g6[0] = (double)gn[0][0];
    g6[1] = (double)gn[1][1];
    g6[2] = (double)gn[2][2];
    g6[3] = (double)gn[0][1];
    g6[4] = (double)gn[0][2];
    g6[5] = (double)gn[1][2];
}

/* tile around the route: 20 x 120 nodes at ~500 m (bicubic error < 2e-12 s^-2), height derivative by a
 * central difference of the analytic field over +-1 m */
static void build_map(const truth3_t *T)
{
    memset(&g_tile, 0, sizeof g_tile);
    g_tile.nlat = 20;
    g_tile.nlon = 120;
    g_tile.dlat_rad = 0.8e-4;
    g_tile.dlon_rad = 1.0e-4;
    g_tile.lat0_rad = (double)T->lat0 - 9.5 * g_tile.dlat_rad;
    g_tile.lon0_rad = (double)T->lon0 - 10.0 * g_tile.dlon_rad;
    g_tile.h0_m = (double)T->h0;
    g_tile.h_range_m = 500.0;
    for (int i = 0; i < g_tile.nlat; ++i)
        for (int j = 0; j < g_tile.nlon; ++j) {
            const long double lat = (long double)g_tile.lat0_rad + (long double)i * (long double)g_tile.dlat_rad;
            const long double lon = (long double)g_tile.lon0_rad + (long double)j * (long double)g_tile.dlon_rad;
            double g0[6], gp[6], gm[6];
            gamma_ned6(T, lat, lon, T->h0, g0);
            gamma_ned6(T, lat, lon, T->h0 + 1.0L, gp);
            gamma_ned6(T, lat, lon, T->h0 - 1.0L, gm);
            for (int k = 0; k < 6; ++k) {
                g_tile.node[i * g_tile.nlon + j][k] = g0[k];
                g_tile.node[i * g_tile.nlon + j][6 + k] = 0.5 * (gp[k] - gm[k]);
            }
        }
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
}

/* map storage of one tile */
typedef struct {
    const gg_gmap_t *map;
    int calls;
} store_t;

static gg_status_t store_tile_at(void *ctx, uint32_t kind, double lat, double lon, double h, const gg_gmap_t **tile)
{
    (void)h; /* the aid checks the tile's height band itself */
    store_t *s = (store_t *)ctx;
    const gg_gmap_tile_t *t = &s->map->tile;
    s->calls++;
    if (kind != GG_GMAP_KIND_TENSOR) return GG_ERR_RANGE; /* the aid asks for the tiles of its kind */
    if (lat < t->lat0_rad || lat > t->lat0_rad + (t->nlat - 1) * t->dlat_rad || lon < t->lon0_rad ||
        lon > t->lon0_rad + (t->nlon - 1) * t->dlon_rad)
        return GG_ERR_RANGE;
    *tile = s->map;
    return GG_OK;
}

/* reproducible normal deviates (xorshift64* + Box-Muller) */
static uint64_t g_rng = 0x9E3779B97F4A7C15ull;
static double urand(void)
{
    g_rng ^= g_rng >> 12;
    g_rng ^= g_rng << 25;
    g_rng ^= g_rng >> 27;
    return ((double)((g_rng * 2685821657736338717ull) >> 11) + 0.5) / 9007199254740992.0;
}
static double nrand(void)
{
    const double u1 = urand(), u2 = urand();
    return sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2);
}

/* a reading's noise so that a diagonal gradient component (difference of two
 * readings over 2 HB) has SIGMA_G */
static double meas_scale(void);
static void add_noise(gg_frame_t *fr)
{
    const double sf = meas_scale() * SIGMA_G * 2.0 * (double)HB / sqrt(2.0);
    for (int s = 0; s < 6; ++s)
        for (int j = 0; j < 3; ++j) fr->f[s][j] += sf * nrand();
}

static void aid_config(gg_aid_mm_config_t *a)
{
    memset(a, 0, sizeof *a);
    a->enable = 1;
    a->update_steps = 500; /* 5 s */
    a->max_passes = 4;
    a->sigma_meas_s2 = SIGMA_G;
    a->sigma_db_s2 = 1.0e-12;
    a->offdiag_ratio = 0.70710678118654752;
    a->sig0_pos_m = 200.0;
    a->sig0_vel_mps = 0.05;
    a->sig0_att_rad = 1.0e-6;
    a->sig0_g_mps2 = 1.0e-7;
    a->q_vel_mps_rts = 1.0e-6;
    a->q_att_rad_rts = 1.0e-9;
    a->q_g_mps2_rts = SIGMA_G * 200.0 * 0.1;
    a->lambda = 0.0;
    a->gate_nis = 0.0;
}

/* chi-square quantile (Wilson-Hilferty) */
static double chi2q(double z, double nu)
{
    const double c = 2.0 / (9.0 * nu);
    const double t = 1.0 - c + z * sqrt(c);
    return nu * t * t * t;
}

/* true - estimate position, ECI axes, at step k */
static void pos_error_i(const truth3_t *T, long long k, const gg_nav3d_output_t *out, long double d_i[3])
{
    const long double t = (long double)k * (long double)DT_US * 1e-6L;
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], th[3][3], d_e[3];
    truth_pose(T, t, r_e, v_e, r_i, a_i, cbi, w, wd);
    for (int j = 0; j < 3; ++j) d_e[j] = r_e[j] - ((long double)out->r_e[j] + (long double)out->r_e_lo[j]);
    rz(W_IE * t, th);
    matvec(th, d_e, d_i);
}

static long double quad3_inv(const double P[GG_UKF_NX_MAX][GG_UKF_NX_MAX], const long double d[3])
{
    /* d^T P_rr^-1 d by cofactors */
    const long double a = P[0][0], b = P[0][1], c = P[0][2], e = P[1][1], f = P[1][2], i = P[2][2];
    const long double A = e * i - f * f, B = -(b * i - c * f), C = b * f - c * e;
    const long double E = a * i - c * c, F = -(a * f - b * c), I = a * e - b * b;
    const long double det = a * A + b * B + c * C;
    const long double q = d[0] * (A * d[0] + B * d[1] + C * d[2]) + d[1] * (B * d[0] + E * d[1] + F * d[2]) +
                          d[2] * (C * d[0] + F * d[1] + I * d[2]);
    return q / det;
}

/* ---------------------------------------------------------------- tests */

/* The measurement model at the true state (zero error) against the analytic
 * body-axes gradient: bicubic map error only (< 2e-3 E here, about the
 * database noise sigma_db the filter is told). */
static void test_predict_matches_field(void **state)
{
    (void)state;
    truth3_t T;
    flight_truth(&T);
    build_map(&T);
    for (int n = 0; n < 5; ++n) {
        const long double t = 37.0L * (long double)n;
        long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], th[3][3], cbe[3][3], ge[3][3];
        truth_pose(&T, t, r_e, v_e, r_i, a_i, cbi, w, wd);
        rz(-W_IE * t, th);
        matmul(th, cbi, cbe);
        gamma_e_truth(&T, r_e, ge);
        gg_real_t re[3], c[3][3];
        for (int j = 0; j < 3; ++j) {
            re[j] = (gg_real_t)r_e[j];
            for (int k = 0; k < 3; ++k) c[j][k] = (gg_real_t)cbe[j][k];
        }
        /* Gamma_b = C_e_b Gamma_e C_b_e */
        long double gb[3][3];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                gb[j][k] = 0;
                for (int l = 0; l < 3; ++l)
                    for (int m = 0; m < 3; ++m) gb[j][k] += cbe[l][j] * ge[l][m] * cbe[m][k];
            }
        const double want[6] = {(double)gb[0][0], (double)gb[1][1], (double)gb[2][2],
                                (double)gb[0][1], (double)gb[0][2], (double)gb[1][2]};
        const double x[GG_UKF_NX_MAX] = {0};
        double z[6];
        const long double thv = W_IE * t;
        assert_int_equal(gg_aid_mm_predict(&g_map, re, c, (gg_real_t)sinl(thv), (gg_real_t)cosl(thv), x, z),
                         GG_OK);
        for (int k = 0; k < 6; ++k) assert_near(z[k], want[k], 2.0e-12);
    }
    /* a 100 m north error in x moves the prediction by the field's change */
    {
        long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3];
        truth_pose(&T, 0.0L, r_e, v_e, r_i, a_i, cbi, w, wd);
        gg_real_t re[3], c[3][3];
        for (int j = 0; j < 3; ++j) {
            re[j] = (gg_real_t)r_e[j];
            for (int k = 0; k < 3; ++k) c[j][k] = (gg_real_t)cbi[j][k];
        }
        long double nr[3][3];
        ned_rows(T.lat0, T.lon0, nr);
        double x[GG_UKF_NX_MAX] = {0};
        for (int j = 0; j < 3; ++j) x[j] = (double)(100.0L * nr[0][j]); /* theta = 0: ECI = ECEF */
        double z[6], want6[6];
        assert_int_equal(gg_aid_mm_predict(&g_map, re, c, 0.0L, 1.0L, x, z), GG_OK);
        long double r2[3], ge[3][3];
        for (int j = 0; j < 3; ++j) r2[j] = r_e[j] + (long double)x[j];
        gamma_e_truth(&T, r2, ge);
        want6[0] = (double)ge[0][0];
        want6[1] = (double)ge[1][1];
        want6[2] = (double)ge[2][2];
        want6[3] = (double)ge[0][1];
        want6[4] = (double)ge[0][2];
        want6[5] = (double)ge[1][2];
        for (int k = 0; k < 6; ++k) assert_near(z[k], want6[k], 2.0e-12);
    }
}

typedef struct {
    double err_h0, err_h_end, err_h_ref_end;
    double nees_mean, nis_mean, nees_last, nis_sum;
    int n_epochs;
    uint32_t updates, rejected;
    int nx;
    double bias_est[6], bias_sig[6]; /* the task's bias estimates and the aid's sigmas at the end */
} flight_t;

/* Options of fly_aided beyond the defaults (stabilized platform, no body
 * rotation, exact gyros, the epoch's own sample). */
typedef struct {
    int strapdown;
    long double spin, precession; /* body rates of the truth (truth3.h), rad/s */
    double gyro_noise;            /* white noise added to each frame's gyro rate, rad/s */
    int32_t average_steps;        /* filter: steps averaged into an epoch */
    double sigma_gyro;            /* filter: the gyro noise it is told, rad/s */
    double meas_scale;            /* gradiometer noise (readings and filter) times this (0: 1) */
    double gyro_bias[3];          /* constant bias added to each frame's gyro rate, rad/s */
    double acc_bias[3];           /* constant bias added to every accelerometer's reading, m/s^2 */
    int bias_states;              /* filter: bias states on, with these initial sigmas */
    double sig0_gyro_bias, sig0_acc_bias;
} fly_opt_t;
static fly_opt_t g_opt;
static double meas_scale(void)
{
    return g_opt.meas_scale > 0.0 ? g_opt.meas_scale : 1.0;
}

/* Fly n steps with the start position off by (dN, dE); aided and unaided
 * side by side on the same noisy frames. */
static flight_t fly_aided(long long n, const double dr_ned[3], const double dv_ned[3], const double psi[3],
                          double sig0_pos, int model_mode)
{
    truth3_t T;
    gg_nav3d_config_t cfg, cref;
    gg_nav3d_output_t out, oref;
    gg_frame_t fr;
    store_t store;
    gg_hal_map_t hm;
    gg_hal_t hal;
    flight_t res = {0};
    flight_truth(&T);
    T.s = g_opt.spin;
    T.p = g_opt.precession;
    build_map(&T);
    make_config(&T, g_opt.strapdown != 0 ? GG_PLATFORM_STRAPDOWN : GG_PLATFORM_STABILIZED, 0, DT_US, &cfg);
    if (model_mode != 0) {
        /* the onboard model: the central point mass (the truth's field without the buried masses) */
        cfg.gravity_mode = GG_GRAVITY_MODEL;
        cfg.model.gm = T_GM;
        cfg.model.a_m = A_WGS;
    }
    {
        long double nr[3][3];
        ned_rows(T.lat0, T.lon0, nr);
        for (int j = 0; j < 3; ++j)
            for (int l = 0; l < 3; ++l) {
                cfg.r0_e[j] -= (gg_real_t)(dr_ned[l] * (double)nr[l][j]); /* dr = true - estimate */
                cfg.v0_e[j] -= (gg_real_t)(dv_ned[l] * (double)nr[l][j]);
            }
    }
    {
        /* C_est = (I - [psi x]) C_true: q_est = q(-psi) (x) q_true (theta = 0: ECI = ECEF) */
        const long double a0 = 1.0L, a1 = -0.5L * psi[0], a2 = -0.5L * psi[1], a3 = -0.5L * psi[2];
        const long double b0 = cfg.q0_b_e[0], b1 = cfg.q0_b_e[1], b2 = cfg.q0_b_e[2], b3 = cfg.q0_b_e[3];
        long double q[4] = {a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3, a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                            a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1, a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0};
        const long double nq = sqrtl(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
        for (int j = 0; j < 4; ++j) cfg.q0_b_e[j] = (gg_real_t)(q[j] / nq);
    }
    cref = cfg;
    aid_config(&cfg.aid_mm);
    cfg.aid_mm.sig0_pos_m = sig0_pos;
    cfg.aid_mm.average_steps = g_opt.average_steps;
    cfg.aid_mm.sigma_gyro_rps = g_opt.sigma_gyro;
    cfg.aid_mm.sigma_meas_s2 = meas_scale() * SIGMA_G;
    if (g_opt.bias_states != 0) {
        cfg.aid_mm.bias_states = 1;
        cfg.aid_mm.sig0_gyro_bias_rps = g_opt.sig0_gyro_bias;
        cfg.aid_mm.sig0_acc_bias_mps2 = g_opt.sig0_acc_bias;
    }
    assert_int_equal(gg_nav3d_init(&g_nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_init(&g_nav_ref, &cref), GG_OK);
    store.map = &g_map;
    store.calls = 0;
    hm.ctx = &store;
    hm.tile_at = store_tile_at;
    memset(&hal, 0, sizeof hal);
    hal.map = &hm;
    double nees = 0.0, nis = 0.0;
    int k_ep = 0;
    for (long long k = 0; k <= n; ++k) {
        make_frame(&T, k, DT_US, &fr);
        add_noise(&fr);
        if (g_opt.gyro_noise > 0.0)
            for (int j = 0; j < 3; ++j) fr.omega_b[j] += g_opt.gyro_noise * nrand();
        for (int j = 0; j < 3; ++j) {
            fr.omega_b[j] += g_opt.gyro_bias[j];
            for (int s = 0; s < 6; ++s) fr.f[s][j] += g_opt.acc_bias[j];
        }
        const gg_status_t st = gg_nav3d_step(&g_nav, &fr, &hal, &out);
        if (st != GG_OK) fail_msg("step %lld: status %d health 0x%x", k, st, out.health);
        assert_int_equal(gg_nav3d_step(&g_nav_ref, &fr, NULL, &oref), GG_OK);
        assert_true((out.health & (GG_HEALTH_MM_FAIL | GG_HEALTH_MM_NO_MAP)) == 0U);
        if (out.mm_corrected != 0) {
            long double d[3];
            pos_error_i(&T, k, &out, d);
            res.nees_last = (double)quad3_inv((const double(*)[GG_UKF_NX_MAX])g_nav.aid_mm.ukf.P, d);
            nees += res.nees_last;
            nis += out.mm_nis;
            ++k_ep;
        }
    }
    {
        long double d[3];
        pos_error_i(&T, n, &out, d);
        res.err_h_end = (double)sqrtl(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        pos_error_i(&T, n, &oref, d);
        res.err_h_ref_end = (double)sqrtl(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    res.n_epochs = k_ep;
    res.nees_mean = k_ep > 0 ? nees / k_ep : 0.0;
    res.nis_mean = k_ep > 0 ? nis / k_ep : 0.0;
    res.nis_sum = nis;
    res.updates = out.mm_updates;
    res.nx = g_nav.aid_mm.nx;
    res.rejected = out.mm_rejected;
    for (int j = 0; j < 6; ++j) {
        res.bias_est[j] = out.mm_bias[j];
        res.bias_sig[j] = res.nx > g_nav.aid_mm.nb ? out.mm_sigma[g_nav.aid_mm.nb + j] : 0.0;
    }
    assert_true(store.calls >= k_ep);
    return res;
}

/* 200 s eastbound with the start 150 m south and 100 m west of the truth
 * (the filter told 200 m): the aid brings the position error below 5 m
 * (unaided it stays ~180 m). */
static void test_recovers_start_offset(void **state)
{
    (void)state;
    const double dr[3] = {150.0, 100.0, 0.0};
    const double dv[3] = {0.0, 0.0, 0.0};
    const double psi[3] = {0.0, 0.0, 0.0};
    g_rng = 0x9E3779B97F4A7C15ull;
    const flight_t f = fly_aided(20000, dr, dv, psi, 200.0, 0);
    print_message("aid: %d epochs (%u updated, %u rejected), |dr| end %.3f m (unaided %.3f m)\n",
                  f.n_epochs, f.updates, f.rejected, f.err_h_end, f.err_h_ref_end);
    assert_true(f.n_epochs >= 35);
    assert_true(f.err_h_ref_end > 150.0);
    assert_true(f.err_h_end < 5.0);
}

/* Consistency over 20 flights of 100 s, each with its start errors drawn
 * from the filter's own P0 (30 m, 0.05 m/s and 1 urad per axis) and its own sensor
 * noise: the mean over the flights of the position NEES (3 dof) after the
 * last epoch, and the mean NIS (6 dof) over all epochs of all flights, in
 * their 95 % chi-square bands. */
static void test_consistency(void **state)
{
    (void)state;
    const int n_runs = 20;
    const double z = 1.959963984540054;
    double nees = 0.0, nis = 0.0;
    int n_ep = 0;
    g_rng = 0x2545F4914F6CDD1Dull;
    for (int r = 0; r < n_runs; ++r) {
        double dr[3], dv[3], psi[3];
        for (int j = 0; j < 3; ++j) {
            dr[j] = 30.0 * nrand();
            dv[j] = 0.05 * nrand();
            psi[j] = 1.0e-6 * nrand();
        }
        const flight_t f = fly_aided(10000, dr, dv, psi, 30.0, 0);
        assert_true(f.n_epochs >= 18);
        assert_true(f.err_h_end < 10.0);
        nees += f.nees_last;
        nis += f.nis_sum;
        n_ep += f.n_epochs;
    }
    nees /= n_runs;
    nis /= n_ep;
    print_message("aid: %d flights, mean NEES %.3f (3 dof, band %.3f..%.3f), mean NIS %.3f over %d epochs "
                  "(6 dof, band %.3f..%.3f)\n",
                  n_runs, nees, chi2q(-z, 3.0 * n_runs) / n_runs, chi2q(z, 3.0 * n_runs) / n_runs, nis, n_ep,
                  chi2q(-z, 6.0 * n_ep) / n_ep, chi2q(z, 6.0 * n_ep) / n_ep);
    assert_true(nees > chi2q(-z, 3.0 * n_runs) / n_runs && nees < chi2q(z, 3.0 * n_runs) / n_runs);
    assert_true(nis > chi2q(-z, 6.0 * n_ep) / n_ep && nis < chi2q(z, 6.0 * n_ep) / n_ep);
}

/* A strapdown body turning at 2.2 mrad/s (spin about x 2e-3, precession
 * 1e-3 rad/s) with gyro white noise of 2e-6 rad/s per 10 ms sample: removing
 * [w x]^2 with the noisy rate adds 2 |w| sigma_w ~ 9e-9 s^-2 (9 E) to each
 * sample's tensor, 90 times the gradiometer noise (0.1 E per sample here, so
 * that the averaged noise, not the map error, dominates R's other
 * directions). The epoch averages its ~490 samples (1 km of track) in ECEF
 * axes (the body turns by 1.1 mrad, 5 E of tensor, within an epoch; the
 * field is curved along the track: two map nodes) and R carries the rate
 * noise's share (aid_mmukf.h); start errors drawn from P0, 12 flights of
 * 100 s: the position NEES after the last epoch and the NIS over all epochs
 * in their 95 % bands. The same flights with the filter not told the gyro
 * noise: NIS far above its band. */
static void test_gyro_share_averaged(void **state)
{
    (void)state;
    const int n_runs = 12;
    const double z = 1.959963984540054;
    double nees = 0.0, nis = 0.0, nis_blind = 0.0;
    int n_ep = 0, n_ep_blind = 0;
    memset(&g_opt, 0, sizeof g_opt);
    g_opt.strapdown = 1;
    g_opt.spin = 2.0e-3L;
    g_opt.precession = 1.0e-3L;
    g_opt.gyro_noise = 2.0e-6;
    g_opt.average_steps = 500;
    g_opt.meas_scale = 10.0;
    for (int pass = 0; pass < 2; ++pass) {
        g_rng = 0x5851F42D4C957F2Dull;
        g_opt.sigma_gyro = pass == 0 ? g_opt.gyro_noise : 0.0;
        for (int r = 0; r < n_runs; ++r) {
            double dr[3], dv[3], psi[3];
            for (int j = 0; j < 3; ++j) {
                dr[j] = 30.0 * nrand();
                dv[j] = 0.05 * nrand();
                psi[j] = 1.0e-6 * nrand();
            }
            const flight_t f = fly_aided(10000, dr, dv, psi, 30.0, 0);
            assert_true(f.n_epochs >= 18);
            if (pass == 0) {
                nees += f.nees_last;
                nis += f.nis_sum;
                n_ep += f.n_epochs;
            } else {
                nis_blind += f.nis_sum;
                n_ep_blind += f.n_epochs;
            }
        }
    }
    memset(&g_opt, 0, sizeof g_opt);
    nees /= n_runs;
    nis /= n_ep;
    nis_blind /= n_ep_blind;
    print_message("aid, turning strapdown body, gyro noise: %d flights, mean NEES %.3f (band %.3f..%.3f), mean NIS "
                  "%.3f over %d epochs (band %.3f..%.3f); filter not told the gyro noise: NIS %.1f\n",
                  n_runs, nees, chi2q(-z, 3.0 * n_runs) / n_runs, chi2q(z, 3.0 * n_runs) / n_runs, nis, n_ep,
                  chi2q(-z, 6.0 * n_ep) / n_ep, chi2q(z, 6.0 * n_ep) / n_ep, nis_blind);
    assert_true(nees > chi2q(-z, 3.0 * n_runs) / n_runs && nees < chi2q(z, 3.0 * n_runs) / n_runs);
    assert_true(nis > chi2q(-z, 6.0 * n_ep) / n_ep && nis < chi2q(z, 6.0 * n_ep) / n_ep);
    assert_true(nis_blind > 3.0 * chi2q(z, 6.0 * n_ep_blind) / n_ep_blind);
}

/* Model mode (the onboard model lacks the buried masses: 10-20 E, ~4e-5 m/s^2
 * of unmodelled gravity): 9 error states, no gravitation state; the same
 * start offset is recovered. */
static void test_model_mode_recovers(void **state)
{
    (void)state;
    const double dr[3] = {150.0, 100.0, 0.0};
    const double dv[3] = {0.0, 0.0, 0.0};
    const double psi[3] = {0.0, 0.0, 0.0};
    g_rng = 0x9E3779B97F4A7C15ull;
    const flight_t f = fly_aided(20000, dr, dv, psi, 200.0, 1);
    print_message("aid (model mode): %d epochs, |dr| end %.3f m (unaided %.3f m)\n", f.n_epochs, f.err_h_end,
                  f.err_h_ref_end);
    assert_int_equal(f.nx, GG_AID_MM_NX_MODEL);
    assert_true(f.err_h_ref_end > 150.0);
    assert_true(f.err_h_end < 5.0);
}

/* The aid switched off, and switched on without a map: the navigation
 * state is bit for bit that of the unaided task; without a map every epoch
 * is flagged NO_MAP. */
static void test_off_and_no_map_unchanged(void **state)
{
    (void)state;
    truth3_t T;
    gg_nav3d_config_t cfg, con;
    gg_nav3d_output_t o0, o1;
    gg_frame_t fr;
    gg_hal_map_t hm = {NULL, NULL};
    gg_hal_t hal;
    flight_truth(&T);
    make_config(&T, GG_PLATFORM_STRAPDOWN, 1, DT_US, &cfg);
    con = cfg;
    aid_config(&con.aid_mm);
    assert_int_equal(gg_nav3d_init(&g_nav_ref, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_init(&g_nav, &con), GG_OK);
    memset(&hal, 0, sizeof hal);
    hal.map = &hm;
    uint32_t no_map = 0U;
    for (long long k = 0; k <= 3000; ++k) {
        make_frame(&T, k, DT_US, &fr);
        assert_int_equal(gg_nav3d_step(&g_nav_ref, &fr, NULL, &o0), GG_OK);
        assert_int_equal(gg_nav3d_step(&g_nav, &fr, &hal, &o1), GG_OK);
        assert_memory_equal(o0.r_e, o1.r_e, sizeof o0.r_e);
        assert_memory_equal(o0.r_e_lo, o1.r_e_lo, sizeof o0.r_e_lo);
        assert_memory_equal(o0.v_e, o1.v_e, sizeof o0.v_e);
        assert_memory_equal(o0.g_e, o1.g_e, sizeof o0.g_e);
        assert_memory_equal(o0.q_b_e, o1.q_b_e, sizeof o0.q_b_e);
        assert_true(o0.mm_epochs == 0U && o0.mm_sigma[0] == 0.0);
        no_map |= o1.health & GG_HEALTH_MM_NO_MAP;
        assert_true((o0.health & ~(uint32_t)0x0FFFFFFFu) == 0U);
    }
    assert_true(no_map != 0U);
    assert_int_equal(o1.mm_no_map, o1.mm_epochs);
    assert_true(o1.mm_epochs == 6U);
}

/* Bias states: a strapdown body turning at 2.2 mrad/s whose gyros read a
 * constant bias of ~0.05 deg/h per axis and whose six accelerometers share a
 * constant bias of ~5 ug per axis, 200 s. The gyro bias turns the attitude
 * by ~5e-5 rad in 200 s (0.15 E of tensor through the ~3000 E of the normal
 * field's flattening, against 0.0005 E of averaged noise) and enters the
 * [w x]^2 removal; the accelerometer bias moves the position by ~1 m. With
 * the bias states the task learns the gyro bias to within a tenth of it and
 * three of its sigmas, and every bias estimate lies within four sigmas of the
 * truth; without them the same frames leave a position error several times
 * larger. */
static void test_bias_states(void **state)
{
    (void)state;
    const double bw[3] = {2.5e-7, -2.0e-7, 3.0e-7};
    const double bf[3] = {5.0e-5, -4.0e-5, 3.0e-5};
    const double dr[3] = {10.0, -8.0, 0.0};
    const double dv[3] = {0.0, 0.0, 0.0};
    const double psi[3] = {0.0, 0.0, 0.0};
    flight_t f[2];
    for (int pass = 0; pass < 2; ++pass) {
        memset(&g_opt, 0, sizeof g_opt);
        g_opt.strapdown = 1;
        g_opt.spin = 2.0e-3L;
        g_opt.precession = 1.0e-3L;
        g_opt.average_steps = 500;
        for (int j = 0; j < 3; ++j) {
            g_opt.gyro_bias[j] = bw[j];
            g_opt.acc_bias[j] = bf[j];
        }
        g_opt.bias_states = pass == 0;
        g_opt.sig0_gyro_bias = 5.0e-7;
        g_opt.sig0_acc_bias = 1.0e-4;
        g_rng = 0xD1B54A32D192ED03ull;
        f[pass] = fly_aided(20000, dr, dv, psi, 30.0, 0);
    }
    memset(&g_opt, 0, sizeof g_opt);
    print_message("aid with bias states (nx %d): |dr| end %.3f m, gyro bias est %.3e %.3e %.3e rad/s "
                  "(sigma %.1e %.1e %.1e), acc bias est %.3e %.3e %.3e m/s^2 (sigma %.1e %.1e %.1e); "
                  "without (nx %d): |dr| end %.3f m\n",
                  f[0].nx, f[0].err_h_end, f[0].bias_est[0], f[0].bias_est[1], f[0].bias_est[2], f[0].bias_sig[0],
                  f[0].bias_sig[1], f[0].bias_sig[2], f[0].bias_est[3], f[0].bias_est[4], f[0].bias_est[5],
                  f[0].bias_sig[3], f[0].bias_sig[4], f[0].bias_sig[5], f[1].nx, f[1].err_h_end);
    assert_int_equal(f[0].nx, GG_AID_MM_NX_DR + GG_AID_MM_NX_BIAS);
    assert_int_equal(f[1].nx, GG_AID_MM_NX_DR);
    for (int j = 0; j < 3; ++j) {
        const double e = f[0].bias_est[j] - bw[j];
        assert_true(fabs(e) < 0.1 * fabs(bw[j]));
        assert_true(fabs(e) < 3.0 * f[0].bias_sig[j]);
        assert_true(fabs(f[0].bias_est[3 + j] - bf[j]) < 4.0 * f[0].bias_sig[3 + j]);
        assert_true(f[1].bias_est[j] == 0.0 && f[1].bias_est[3 + j] == 0.0);
    }
    assert_true(f[1].err_h_end > 3.0 * f[0].err_h_end);
}

/* The covariance propagation against a dense reimplementation: 300 steps of
 * the aid with fixed INS inputs (a turning body's attitude, specific force and
 * gradient, bias states on) accumulate Phi = F^300 and Q = sum F^k Qd F^kT
 * with F = I + A h + (A h)^2 / 2; the test builds A densely from aid_mmukf.h's
 * error dynamics and multiplies full matrices in long double. */
static void test_propagation_dense(void **state)
{
    (void)state;
    gg_aid_mm_config_t c;
    gg_aid_ins_t ins;
    gg_aid_corr_t corr;
    const int n = GG_AID_MM_NX_DR + GG_AID_MM_NX_BIAS, nb = GG_AID_MM_NX_DR, steps = 300;
    const double h = 0.01, w = 7.292115e-5;
    aid_config(&c);
    c.update_steps = 100000;
    c.bias_states = 1;
    c.sig0_gyro_bias_rps = 1.0e-7;
    c.sig0_acc_bias_mps2 = 1.0e-4;
    c.q_gyro_bias_rps_rts = 3.0e-9;
    c.q_acc_bias_mps2_rts = 2.0e-7;
    c.sigma_gyro_rps = 2.0e-6;
    static gg_aid_mm_t a;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    memset(&ins, 0, sizeof ins);
    ins.n_steps = 1;
    ins.dt_s = h;
    ins.omega_ie = w;
    ins.sin_th = 0.0L;
    ins.cos_th = 1.0L;
    ins.r_e[0] = 6378137.0L;
    const double ang = 0.3;
    const double cb[3][3] = {{cos(ang), -sin(ang), 0.0}, {sin(ang) * 0.8, cos(ang) * 0.8, -0.6},
                             {sin(ang) * 0.6, cos(ang) * 0.6, 0.8}};
    const double g[3][3] = {{3.1e-6, 2.0e-9, -1.0e-9}, {2.0e-9, -1.5e-6, 4.0e-9}, {-1.0e-9, 4.0e-9, -1.6e-6}};
    const double f[3] = {0.4, -1.2, 9.81};
    for (int j = 0; j < 3; ++j) {
        ins.f_i[j] = f[j];
        for (int k = 0; k < 3; ++k) {
            ins.c_b_e[j][k] = (gg_real_t)cb[j][k];
            ins.c_b_i[j][k] = cb[j][k];
            ins.gamma_i[j][k] = g[j][k];
        }
    }
    for (int s = 0; s < steps; ++s) assert_int_equal(gg_aid_mm_step(&a, &ins, NULL, &corr), GG_OK);
    /* dense A h and F */
    static long double A[18][18], F[18][18], P[18][18], Q[18][18], T[18][18];
    memset(A, 0, sizeof A);
    for (int j = 0; j < 3; ++j) {
        A[j][3 + j] = h;
        A[3 + j][9 + j] = h;
        for (int k = 0; k < 3; ++k) {
            A[3 + j][k] = g[j][k] * h;
            A[6 + j][nb + k] = -cb[j][k] * h;
            A[3 + j][nb + 3 + k] = -cb[j][k] * h;
        }
    }
    A[3][7] = f[2] * h; A[3][8] = -f[1] * h; A[4][6] = -f[2] * h;
    A[4][8] = f[0] * h; A[5][6] = f[1] * h; A[5][7] = -f[0] * h;
    A[9][10] = -w * h; A[10][9] = w * h;
    for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
            long double s2 = 0.0L;
            for (int l = 0; l < n; ++l) s2 += A[j][l] * A[l][k];
            F[j][k] = A[j][k] + 0.5L * s2 + (j == k ? 1.0L : 0.0L);
        }
    memset(P, 0, sizeof P);
    memset(Q, 0, sizeof Q);
    for (int j = 0; j < n; ++j) P[j][j] = 1.0L;
    const long double qd[18] = {0, 0, 0, c.q_vel_mps_rts * c.q_vel_mps_rts * h, c.q_vel_mps_rts * c.q_vel_mps_rts * h,
                                c.q_vel_mps_rts * c.q_vel_mps_rts * h, 0, 0, 0,
                                c.q_g_mps2_rts * c.q_g_mps2_rts * h, c.q_g_mps2_rts * c.q_g_mps2_rts * h,
                                c.q_g_mps2_rts * c.q_g_mps2_rts * h, 9e-18 * h, 9e-18 * h, 9e-18 * h,
                                4e-14 * h, 4e-14 * h, 4e-14 * h};
    const long double qa = c.q_att_rad_rts * c.q_att_rad_rts * h + 4e-12 * h * h;
    for (int s = 0; s < steps; ++s) {
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                long double s2 = 0.0L;
                for (int l = 0; l < n; ++l) s2 += F[j][l] * P[l][k];
                T[j][k] = s2;
            }
        memcpy(P, T, sizeof P);
        for (int j = 0; j < n; ++j)
            for (int k = 0; k < n; ++k) {
                long double s2 = 0.0L;
                for (int l = 0; l < n; ++l)
                    for (int m = 0; m < n; ++m) s2 += F[j][l] * Q[l][m] * F[k][m];
                T[j][k] = s2;
            }
        memcpy(Q, T, sizeof Q);
        for (int j = 0; j < n; ++j) Q[j][j] += (j >= 6 && j < 9) ? qa : qd[j];
    }
    double ep = 0.0, eq = 0.0;
    for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
            const double dp = fabs((double)(a.phi[j][k] - P[j][k])) / (1e-30 + fabs((double)P[j][k]) + 1e-12);
            const double sq = sqrtl(Q[j][j] * Q[k][k]);
            const double dq = sq > 0 ? fabs((double)(a.q[j][k] - Q[j][k])) / sq : fabs(a.q[j][k]);
            if (dp > ep) ep = dp;
            if (dq > eq) eq = dq;
        }
    print_message("aid propagation, 18 states, %d steps: worst Phi difference %.2e (relative), worst Q difference "
                  "%.2e (correlation units) against the dense long-double reference\n", steps, ep, eq);
    assert_true(ep < 1e-12);
    assert_true(eq < 1e-12);
}

/* The barometric loop in the aid's error model against the loop itself: a level
 * vehicle (up = ECI z, Gamma = diag(-w_s^2, -w_s^2, 2 w_s^2), no Earth rate, no
 * other noise) fed the gains gg_vchan applies once per 1 s sample. (1) Over one
 * sample period the aid's vertical block (dr_z, dv_z, dg_z) of Phi has the
 * eigenvalues the loop was designed for, exp(-p_i T) (vchan.h). (2) Its noise,
 * 300 periods from zero, equals the loop's covariance iterated with the 3-state
 * loop's own matrices: exp(A T) by a long-double Taylor series, the sample's
 * correction x + K (C x - n) (vchan.h), the barometer's white noise. */
static void test_baro_loop_model(void **state)
{
    (void)state;
    const long double ws2 = 9.80L / 6371000.0L;
    const double h = 0.01;
    const int per = 100, periods = 300;
    const double sb = 0.7; /* barometer noise per sample, m */
    gg_vchan_config_t vc;
    static gg_vchan_t vs;
    memset(&vc, 0, sizeof vc);
    vc.poles[0] = 0.05L;
    vc.poles[1] = 0.1L;
    vc.poles[2] = 0.15L;
    vc.omega_s2 = ws2;
    vc.period_us = 1000000;
    vc.max_age_us = 500000;
    vc.coast_us = 10000000;
    vc.alt_min_m = -1000.0;
    vc.alt_max_m = 30000.0;
    vc.gate_m = 50.0;
    vc.max_rejects = 5;
    assert_int_equal(gg_vchan_init(&vs, &vc), GG_OK);
    gg_aid_mm_config_t c;
    aid_config(&c);
    c.update_steps = 100000; /* no epoch: Phi and Q accumulate */
    c.q_vel_mps_rts = 0.0;
    c.q_att_rad_rts = 0.0;
    c.q_g_mps2_rts = 0.0;
    c.sigma_baro_m = sb;
    static gg_aid_mm_t a;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    gg_aid_ins_t ins;
    gg_aid_corr_t corr;
    memset(&ins, 0, sizeof ins);
    ins.n_steps = 1;
    ins.dt_s = h;
    ins.omega_ie = 0.0;
    ins.sin_th = 0.0L;
    ins.cos_th = 1.0L;
    ins.r_e[2] = 6371000.0L;
    for (int j = 0; j < 3; ++j) {
        ins.c_b_e[j][j] = 1.0L;
        ins.c_b_i[j][j] = 1.0;
        ins.gamma_i[j][j] = (double)((j == 2) ? (2.0L * ws2) : -ws2);
    }
    ins.loop_u_i[2] = 1.0;
    /* (1) one period from the identity */
    for (int s = 1; s <= per; ++s) {
        for (int j = 0; j < 3; ++j) ins.loop_k[j] = (s == per) ? (double)vs.kd[j] : 0.0;
        assert_int_equal(gg_aid_mm_step(&a, &ins, NULL, &corr), GG_OK);
    }
    const int iv[3] = {2, 5, 11};
    long double M[3][3];
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) M[j][k] = a.phi[iv[j]][iv[k]];
    const long double tr = M[0][0] + M[1][1] + M[2][2];
    const long double m2 = (M[0][0] * M[1][1] - M[0][1] * M[1][0]) + (M[0][0] * M[2][2] - M[0][2] * M[2][0]) +
                           (M[1][1] * M[2][2] - M[1][2] * M[2][1]);
    const long double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
    long double z[3];
    for (int j = 0; j < 3; ++j) z[j] = expl(-vc.poles[j] * 1.0L);
    const long double tr0 = z[0] + z[1] + z[2], m20 = z[0] * z[1] + z[0] * z[2] + z[1] * z[2], det0 = z[0] * z[1] * z[2];
    print_message("baro loop in the aid: characteristic polynomial over one period: trace %.12Lf (designed %.12Lf), "
                  "minors %.12Lf (%.12Lf), det %.12Lf (%.12Lf)\n", tr, tr0, m2, m20, det, det0);
    assert_true(fabsl(tr - tr0) < 1e-9L);
    assert_true(fabsl(m2 - m20) < 1e-9L);
    assert_true(fabsl(det - det0) < 1e-9L);
    /* (2) the noise over 300 periods, against the loop's own 3-state covariance */
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    for (int s = 1; s <= per * periods; ++s) {
        for (int j = 0; j < 3; ++j) ins.loop_k[j] = ((s % per) == 0) ? (double)vs.kd[j] : 0.0;
        assert_int_equal(gg_aid_mm_step(&a, &ins, NULL, &corr), GG_OK);
    }
    long double A[3][3] = {{0, 1, 0}, {2.0L * ws2, 0, -1}, {0, 0, 0}}, E[3][3], T[3][3], X[3][3];
    memset(E, 0, sizeof E);
    for (int j = 0; j < 3; ++j) E[j][j] = 1.0L;
    memcpy(T, E, sizeof T);
    for (int n = 1; n < 40; ++n) { /* T <- T A / n, E += T */
        long double U[3][3];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                U[j][k] = 0;
                for (int l = 0; l < 3; ++l) U[j][k] += T[j][l] * A[l][k] / (long double)n;
            }
        memcpy(T, U, sizeof T);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) E[j][k] += T[j][k];
    }
    long double G[3][3]; /* (I + K C) exp(A T), C = [1 0 0] */
    for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) G[j][k] = E[j][k] + vs.kd[j] * E[0][k];
    memset(X, 0, sizeof X);
    for (int p = 0; p < periods; ++p) {
        long double U[3][3];
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                U[j][k] = 0;
                for (int l = 0; l < 3; ++l)
                    for (int m = 0; m < 3; ++m) U[j][k] += G[j][l] * X[l][m] * G[k][m];
            }
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) X[j][k] = U[j][k] + vs.kd[j] * vs.kd[k] * (long double)(sb * sb);
    }
    const double rz = sqrt(a.q[2][2]), vz = sqrt(a.q[5][5]), gz = sqrt(a.q[11][11]);
    const double rz0 = (double)sqrtl(X[0][0]), vz0 = (double)sqrtl(X[1][1]), gz0 = (double)sqrtl(X[2][2]);
    const double cor = a.q[2][5] / (rz * vz), cor0 = (double)(X[0][1] / sqrtl(X[0][0] * X[1][1]));
    print_message("baro loop in the aid, %d periods, %.1f m noise: sigma dh %.6f m (loop %.6f), dv %.6e m/s "
                  "(%.6e), integral %.6e m/s^2 (%.6e), corr(dh, dv) %.6f (%.6f)\n", periods, sb, rz, rz0, vz, vz0, gz,
                  gz0, cor, cor0);
    assert_true(fabs(rz / rz0 - 1.0) < 1e-6);
    assert_true(fabs(vz / vz0 - 1.0) < 1e-6);
    assert_true(fabs(gz / gz0 - 1.0) < 1e-6);
    assert_true(fabs(cor - cor0) < 1e-6);
    /* bad input: a non-finite gain or a non-unit up direction is refused */
    ins.loop_k[0] = NAN;
    assert_int_equal(gg_aid_mm_step(&a, &ins, NULL, &corr), GG_ERR_RANGE);
    ins.loop_k[0] = 0.0;
    ins.loop_u_i[2] = 2.0;
    assert_int_equal(gg_aid_mm_step(&a, &ins, NULL, &corr), GG_ERR_RANGE);
    c.sigma_baro_m = -1.0;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
}

static void test_config(void **state)
{
    (void)state;
    gg_aid_mm_t a;
    gg_aid_mm_config_t c;
    aid_config(&c);
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    assert_int_equal(a.nx, GG_AID_MM_NX_DR);
    assert_int_equal(gg_aid_mm_init(&a, &c, 0), GG_OK);
    assert_int_equal(a.nx, GG_AID_MM_NX_MODEL); /* model mode: no gravitation state */
    c.update_steps = 2 * c.max_passes + 1;       /* too short for the schedule */
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.sigma_meas_s2 = NAN;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.average_steps = c.update_steps + 1; /* the window longer than the period */
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.average_steps = c.update_steps;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    c.sigma_gyro_rps = -1.0e-6;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.sigma_gyro_bias_rps = NAN;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.bias_states = 1; /* bias states need their initial sigmas */
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    c.sig0_gyro_bias_rps = 1.0e-7;
    c.sig0_acc_bias_mps2 = 1.0e-4;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    assert_int_equal(a.nx, GG_AID_MM_NX_DR + GG_AID_MM_NX_BIAS);
    assert_int_equal(gg_aid_mm_init(&a, &c, 0), GG_OK);
    assert_int_equal(a.nx, GG_AID_MM_NX_MODEL + GG_AID_MM_NX_BIAS);
    c.q_acc_bias_mps2_rts = -1.0;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    c.q_acc_bias_mps2_rts = 0.0;
    c.bias_states = 2;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_ERR_CONFIG);
    aid_config(&c);
    c.enable = 0;
    assert_int_equal(gg_aid_mm_init(&a, &c, 1), GG_OK);
    assert_int_equal(a.initialized, 0);
}

/* The bias estimates a correction may leave in the task: inside
 * GG_AID_MM_BIAS_SIGMAS initial sigmas and inside the absolute bounds of
 * limits.h. A correction beyond either is refused whole, the state byte for
 * byte as before (the fuzzer's finding: an ungated epoch of wild readings
 * taught a gyro bias of 0.027 rad/s, whose rotation terms, 7.5e-4 s^-2, then
 * failed the differencing's range check on every later frame). The absolute
 * gyro bound keeps those terms, 3 b^2 at most, below a tenth of the
 * gradient range. */
static void test_bias_bound(void **state)
{
    (void)state;
    truth3_t T;
    gg_nav3d_config_t cfg;
    gg_aid_corr_t c;
    gg_frame_t fr;
    gg_nav3d_output_t out;
    assert_true(3.0 * GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS * GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS <=
                0.1 * (double)GG_LIM_GAMMA_MAX_S2);
    flight_truth(&T);
    build_map(&T);
    make_config(&T, GG_PLATFORM_STRAPDOWN, 0, DT_US, &cfg);
    make_frame(&T, 0, DT_US, &fr);
    aid_config(&cfg.aid_mm);
    cfg.aid_mm.bias_states = 1;
    cfg.aid_mm.sig0_gyro_bias_rps = 1.0e-7;
    cfg.aid_mm.sig0_acc_bias_mps2 = 1.0e-4;
    assert_int_equal(gg_nav3d_init(&g_nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_step(&g_nav, &fr, NULL, &out), GG_OK); /* the state started */
    memset(&c, 0, sizeof c);
    c.valid = 1;
    c.db_w[1] = 0.0274623; /* the finding */
    memcpy(&g_nav_ref, &g_nav, sizeof g_nav);
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
    assert_memory_equal(&g_nav_ref, &g_nav, sizeof g_nav);
    c.db_w[1] = 9.0e-7; /* 9 sigma: taken */
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_OK);
    assert_true(g_nav.bias_w[1] == 9.0e-7);
    c.db_w[1] = 2.0e-7; /* to 11 sigma: refused */
    memcpy(&g_nav_ref, &g_nav, sizeof g_nav);
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
    assert_memory_equal(&g_nav_ref, &g_nav, sizeof g_nav);
    c.db_w[1] = -1.8e-6; /* to -9 sigma: taken */
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_OK);
    c.db_w[1] = 0.0;
    c.db_f[2] = -1.1e-3; /* accelerometer, 11 sigma */
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
    c.db_f[2] = NAN;
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_NONFINITE);
    /* the widest initial sigmas the aid accepts: the absolute bounds decide */
    cfg.aid_mm.sig0_gyro_bias_rps = GG_LIM_AID_MM_SIGMA_W_MAX_RPS;
    cfg.aid_mm.sig0_acc_bias_mps2 = GG_LIM_AID_MM_ACC_BIAS_MAX_MPS2;
    assert_int_equal(gg_nav3d_init(&g_nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_step(&g_nav, &fr, NULL, &out), GG_OK); /* the state started */
    memset(&c, 0, sizeof c);
    c.valid = 1;
    c.db_w[0] = 0.99 * GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS;
    c.db_f[0] = 0.99 * GG_LIM_AID_MM_BIAS_F_EST_MAX_MPS2;
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_OK);
    c.db_w[0] = 0.02 * GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS;
    c.db_f[0] = 0.0;
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
    c.db_w[0] = 0.0;
    c.db_f[0] = 0.02 * GG_LIM_AID_MM_BIAS_F_EST_MAX_MPS2;
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
    /* no bias states: no bias correction at all */
    cfg.aid_mm.bias_states = 0;
    assert_int_equal(gg_nav3d_init(&g_nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_step(&g_nav, &fr, NULL, &out), GG_OK); /* the state started */
    c.db_f[0] = 1.0e-12;
    assert_int_equal(n3_aid_apply(&g_nav, &c), GG_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_config),
        cmocka_unit_test(test_predict_matches_field),
        cmocka_unit_test(test_off_and_no_map_unchanged),
        cmocka_unit_test(test_recovers_start_offset),
        cmocka_unit_test(test_consistency),
        cmocka_unit_test(test_model_mode_recovers),
        cmocka_unit_test(test_gyro_share_averaged),
        cmocka_unit_test(test_bias_states),
        cmocka_unit_test(test_propagation_dense),
        cmocka_unit_test(test_baro_loop_model),
        cmocka_unit_test(test_bias_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
