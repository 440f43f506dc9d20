/* Precision audit: built three times from this one source -
 *   precision.native : firmware and test with x86-64 long double (64-bit mantissa)
 *   precision.ld64   : both built with -mlong-double-64 (long double = double,
 *                      the Arm Cortex-M ABI): compensated accumulators must
 *                      carry the precision alone
 *   precision.naive  : firmware with GGINS_NAIVE_ACCUM (plain double
 *                      accumulators): shown to MISS the bounds, with its figure
 * Truth is binary128 (truthq.h), independent of the long double width. No
 * long double libm call or printf appears here (their ABI differs under
 * -mlong-double-64). */
#include "test_common_q.h"
#include <stdlib.h>
#include "truthq.h"
#include "ggins/gravdr.h"
#include "ggins/nav2d.h"

#if defined(GGINS_NAIVE_ACCUM)
#define VARIANT "naive"
#elif __LDBL_MANT_DIG__ == 53
#define VARIANT "ld64"
#else
#define VARIANT "native"
#endif

static const q_flight_t kFlight = {300, 0, 0};
#define DT_US 10000
#define STEPS_PER_HOUR 360000L

/* Flight positions by rotation recurrence (binary128), re-synchronised with
 * cosq/sinq every 1000 steps: the recurrence's drift over 1000 steps is
 * ~1e-31 relative. */
typedef struct {
    q_t c, s, cd, sd, rho;
    long k;
} q_walk_t;

static void walk_init(q_walk_t *w)
{
    const q_t dl = kFlight.v * (q_t)DT_US * Q_(1e-6) / (Q_RE + kFlight.h);
    w->rho = Q_RE + kFlight.h;
    w->c = cosq(kFlight.lat0);
    w->s = sinq(kFlight.lat0);
    w->cd = cosq(dl);
    w->sd = sinq(dl);
    w->k = 0;
}

static void walk_next(q_walk_t *w)
{
    w->k++;
    if (w->k % 1000 == 0) {
        const q_t lat = kFlight.lat0 + kFlight.v * (q_t)w->k * (q_t)DT_US * Q_(1e-6) / w->rho;
        w->c = cosq(lat);
        w->s = sinq(lat);
    } else {
        const q_t c = w->c * w->cd - w->s * w->sd;
        w->s = w->s * w->cd + w->c * w->sd;
        w->c = c;
    }
}

/* ---- 1. gravity dead reckoning alone, 10 h at 100 Hz, exact inputs ---- */
static void test_gravdr_10h(void **state)
{
    (void)state;
    q_walk_t w;
    walk_init(&w);
    const q_t k = Q_GM / (w.rho * w.rho * w.rho);
    q_t r[3] = {w.rho * w.c, 0, w.rho * w.s}, g[3];
    gg_gravdr_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    q_point_mass_g(r, g);
    for (int j = 0; j < 3; ++j) {
        cfg.g0[j] = (gg_real_t)g[j];
        for (int i = 0; i < 3; ++i)
            cfg.gamma0[j][i] = (gg_real_t)(k * (3 * r[j] * r[i] / (w.rho * w.rho) - (i == j)));
    }
    /* G(0) as given to the integrator (rounded to working precision) is the
     * reference start: the test measures the integration, not that rounding */
    q_t g_start_err[3];
    for (int j = 0; j < 3; ++j) g_start_err[j] = (q_t)cfg.g0[j] - g[j];
    gg_gravdr_t st;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_OK);
    const long n = 10 * STEPS_PER_HOUR;
    for (long s = 1; s <= n; ++s) {
        q_t rn[3];
        walk_next(&w);
        rn[0] = w.rho * w.c;
        rn[1] = 0;
        rn[2] = w.rho * w.s;
        gg_real_t dr[3], gam[3][3];
        for (int j = 0; j < 3; ++j) {
            dr[j] = (gg_real_t)(rn[j] - r[j]);
            for (int i = 0; i < 3; ++i)
                gam[j][i] = (gg_real_t)(k * (3 * rn[j] * rn[i] / (w.rho * w.rho) - (i == j)));
        }
        assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])gam, dr), GG_OK);
        memcpy(r, rn, sizeof r);
    }
    gg_acc_t ga[3];
    assert_int_equal(gg_gravdr_get_acc(&st, ga), GG_OK);
    q_point_mass_g(r, g);
    q_t est[3];
    for (int j = 0; j < 3; ++j) est[j] = (q_t)ga[j].hi + (q_t)ga[j].lo - g_start_err[j];
    const double e = q_norm_diff(est, g);
    printf("[%s] gravity DR, 10 h, 100 Hz, exact inputs: |G - G_true| = %.3e m/s^2 (bound 1e-13)\n",
           VARIANT, e);
#ifdef GGINS_NAIVE_ACCUM
    assert_true(e > 1e-13);
#else
    assert_true(e < 1e-13);
#endif
}

/* ---- navigation loop helpers ---- */
static void nav_config(gg_nav2d_config_t *cfg, int baro, q_t half_base)
{
    q_t r[3], v[3], a[3], g[3];
    memset(cfg, 0, sizeof *cfg);
    q_flight(&kFlight, 0, r, v, a);
    q_point_mass_g(r, g);
    cfg->geometry.a_m = (gg_real_t)half_base;
    cfg->geometry.b_m = (gg_real_t)half_base;
    cfg->dt_us = DT_US;
    cfg->dt_tol_us = 100;
    for (int j = 0; j < 3; ++j) {
        cfg->r0[j] = (gg_real_t)r[j];
        cfg->v0[j] = (gg_real_t)v[j];
        cfg->g0[j] = (gg_real_t)g[j];
    }
    cfg->f_max = 100.0;
    cfg->asym_max = 1e-9;
    cfg->r_ref_m = (gg_real_t)Q_RE;
    cfg->baro_enable = baro;
    const gg_real_t poles[3] = {0.005L, 0.01L, 0.015L};
    for (int i = 0; i < 3; ++i) cfg->baro.poles[i] = poles[i];
    cfg->baro.omega_s2 = (gg_real_t)(Q_GM / (Q_RE * Q_RE * Q_RE));
    cfg->baro.period_us = 100 * DT_US;
    cfg->baro.max_age_us = 500000;
    cfg->baro.coast_us = 10000000;
    cfg->baro.alt_min_m = -1000;
    cfg->baro.alt_max_m = 30000;
    cfg->baro.gate_m = 100;
    cfg->baro.max_rejects = 5;
}

/* Truth along the flight for step k (positions by the walk: no cosq/sinq
 * per step), and the four sensors' readings. exact_centre = 1 removes the
 * curvature term of the four-sensor mean (a constant added to all four
 * readings: the differences, hence Gamma, are unchanged), leaving a purely
 * numerical test. */
typedef struct {
    q_walk_t w;
    q_t r[3], v[3], f[4][3];
} q_gen_t;

static void gen_init(q_gen_t *g)
{
    walk_init(&g->w);
}

static void gen_step(q_gen_t *g, long k, int exact_centre, q_t half_base)
{
    while (g->w.k < k) walk_next(&g->w);
    const q_t rho = g->w.rho, c = g->w.c, s = g->w.s, w2 = kFlight.v * kFlight.v / rho;
    const q_t a[3] = {-w2 * c, 0, -w2 * s};
    g->r[0] = rho * c;
    g->r[1] = 0;
    g->r[2] = rho * s;
    g->v[0] = -kFlight.v * s;
    g->v[1] = 0;
    g->v[2] = kFlight.v * c;
    q_sensor_forces(g->r, a, half_base, half_base, g->f);
    if (exact_centre) {
        q_t gc[3];
        q_point_mass_g(g->r, gc);
        for (int j = 0; j < 3; ++j) {
            const q_t mean = (g->f[0][j] + g->f[1][j] + g->f[2][j] + g->f[3][j]) / 4;
            const q_t shift = (a[j] - gc[j]) - mean;
            for (int i = 0; i < 4; ++i) g->f[i][j] += shift;
        }
    }
}

/* frame k from the generator (+ bias on sensor `bi` axis `ba`), perfect 1 Hz baro */
static void nav_frame(const q_gen_t *g, long k, int bi, int ba, double bias, gg_frame_t *fr)
{
    memset(fr, 0, sizeof *fr);
    fr->utime = 1000000 + k * DT_US;
    fr->seq = k;
    fr->n_acc = 4;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j) {
            const q_t x = g->f[i][j] + ((i == bi && j == ba) ? (q_t)bias : 0);
            fr->f[i][j] = (double)x;
            fr->f_lo[i][j] = (double)(x - (q_t)fr->f[i][j]);
        }
    for (int i = 4; i < GG_MAX_ACC; ++i) fr->acc_status[i] = GG_SENSOR_ABSENT;
    fr->gyro_status = GG_SENSOR_ABSENT;
    if (k % 100 == 0) {
        fr->baro_alt_m = (double)(g->w.rho - Q_RE);
        fr->baro_utime = fr->utime;
        fr->baro_status = GG_SENSOR_OK;
    } else {
        fr->baro_status = GG_SENSOR_ABSENT;
    }
}

/* ---- 2. whole loop, perfect sensors, baro-damped ----
 * Frames carry perfect readings with the curvature term of the four-sensor
 * mean removed (gen_step). What is left is one property of the instrument:
 * the differenced gradient (f3 - f1)/2a is the true one plus a^2/6 d3G/dx3
 * (~4e-20 s^-2 at a = 0.5 m), which the dead reckoning integrates along the
 * path (x 300 m/s x hours -> ~1e-13 m/s^2, and b/w_s^2 ~ 7e-8 m along track).
 * It scales with a^2, numerics do not: so the loop is flown with a = b =
 * 0.05 m (physics 100x smaller) for the numerical bounds, and at 0.5 m to
 * show the a^2 scaling - a drift that the physics does not explain would
 * break both. Hourly samples over 5 h. */
static void loop_run(q_t half_base, double *worst_r, double *worst_g)
{
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    q_gen_t gen;
    gen_init(&gen);
    nav_config(&cfg, 1, half_base);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    const long n = 5 * STEPS_PER_HOUR;
    *worst_r = 0;
    *worst_g = 0;
    for (long k = 0; k <= n; ++k) {
        gen_step(&gen, k, 1, half_base);
        nav_frame(&gen, k, -1, 0, 0, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        if (k % STEPS_PER_HOUR == 0) {
            q_t g[3], rn[3], gn[3];
            const q_t *r = gen.r;
            q_point_mass_g(r, g);
            for (int j = 0; j < 3; ++j) {
                rn[j] = out.r_i[j];
                gn[j] = out.g_i[j];
            }
            const double er = q_norm_diff(rn, r), eg = q_norm_diff(gn, g);
            if (getenv("GGINS_VERBOSE") != NULL) {
                const q_t rr = sqrtq(r[0] * r[0] + r[2] * r[2]);
                const q_t up = ((rn[0] - r[0]) * r[0] + (rn[2] - r[2]) * r[2]) / rr;
                const q_t al = ((rn[0] - r[0]) * -r[2] + (rn[2] - r[2]) * r[0]) / rr;
                printf("  a = %.2f m, t = %3.1f h: dr up %+.3e along %+.3e m, |dG| %.3e, a_c %+.3e\n",
                       (double)half_base, (double)k / STEPS_PER_HOUR, (double)up, (double)al, eg,
                       out.g_up_corr);
            }
            if (er > *worst_r) *worst_r = er;
            if (eg > *worst_g) *worst_g = eg;
        }
    }
    printf("[%s] perfect sensors + baro, 5 h, a = b = %.2f m: worst |dr| = %.3e m, worst |dG| = "
           "%.3e m/s^2\n", VARIANT, (double)half_base, *worst_r, *worst_g);
}

static void test_loop_perfect_baro(void **state)
{
    (void)state;
    double r_small, g_small;
    loop_run(Q_(0.05), &r_small, &g_small);
#ifdef GGINS_NAIVE_ACCUM
    assert_true(r_small > 1e-8 || g_small > 1e-14);
#else
    assert_true(r_small < 1e-8);
    assert_true(g_small < 1e-14);
    double r_paper, g_paper;
    loop_run(Q_(0.5), &r_paper, &g_paper);
    printf("[%s] a = 0.5 m over a = 0.05 m: position %.1fx, gravity %.1fx (a^2 scaling: 100x)\n",
           VARIANT, r_paper / r_small, g_paper / g_small);
    assert_true(g_paper / g_small > 30.0 && g_paper / g_small < 300.0);
#endif
}

/* ---- 3. a 1e-12 m/s^2 bias on one accelerometer against the linear error
 * model (Welker et al. eqs. 7, 9, 10 with docs/design.md's sign: dV' = 1/4 sum df
 * + dG), integrated here by RK4 in binary128 along the true trajectory.
 * Bias on sensor 2, x axis: d = df2x enters dV'x with 1/4 and dG'x through
 * dGamma_xz = -d/2b times Vz. The firmware's error is taken as (biased run -
 * perfect run), which removes the common numerical floor. */
static void lin_deriv(q_t t, const q_t x[6], q_t d, q_t dx[6])
{
    q_t r[3], v[3], a[3], gam[3][3];
    q_flight(&kFlight, t, r, v, a);
    q_point_mass_gamma(r, gam);
    dx[0] = x[2];
    dx[1] = x[3];
    dx[2] = x[4] + d / 4;
    dx[3] = x[5];
    dx[4] = gam[0][0] * x[2] + gam[0][2] * x[3] - d / (2 * Q_(0.5)) * v[2];
    dx[5] = gam[2][0] * x[2] + gam[2][2] * x[3];
}

static void test_bias_matches_linear_model(void **state)
{
    (void)state;
    const double bias = 1e-12;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav_p, nav_b;
    gg_frame_t fr_p, fr_b;
    gg_nav_output_t out_p, out_b;
    q_gen_t gen;
    gen_init(&gen);
    nav_config(&cfg, 0, Q_(0.5));
    assert_int_equal(gg_nav2d_init(&nav_p, &cfg), GG_OK);
    assert_int_equal(gg_nav2d_init(&nav_b, &cfg), GG_OK);
    const long n = STEPS_PER_HOUR;
    for (long k = 0; k <= n; ++k) {
        gen_step(&gen, k, 0, Q_(0.5));
        nav_frame(&gen, k, -1, 0, 0, &fr_p);
        nav_frame(&gen, k, 1, 0, bias, &fr_b);
        assert_int_equal(gg_nav2d_step(&nav_p, &fr_p, NULL, &out_p), GG_OK);
        assert_int_equal(gg_nav2d_step(&nav_b, &fr_b, NULL, &out_b), GG_OK);
    }
    /* linear model, RK4, 1 s steps */
    q_t x[6] = {0, 0, 0, 0, 0, 0};
    const q_t h = 1;
    for (int s = 0; s < 3600; ++s) {
        const q_t t = s;
        q_t k1[6], k2[6], k3[6], k4[6], y[6];
        lin_deriv(t, x, bias, k1);
        for (int i = 0; i < 6; ++i) y[i] = x[i] + h / 2 * k1[i];
        lin_deriv(t + h / 2, y, bias, k2);
        for (int i = 0; i < 6; ++i) y[i] = x[i] + h / 2 * k2[i];
        lin_deriv(t + h / 2, y, bias, k3);
        for (int i = 0; i < 6; ++i) y[i] = x[i] + h * k3[i];
        lin_deriv(t + h, y, bias, k4);
        for (int i = 0; i < 6; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    const double fw[6] = {out_b.r_i[0] - out_p.r_i[0], out_b.r_i[2] - out_p.r_i[2],
                          out_b.v_i[0] - out_p.v_i[0], out_b.v_i[2] - out_p.v_i[2],
                          out_b.g_i[0] - out_p.g_i[0], out_b.g_i[2] - out_p.g_i[2]};
    const char *names[6] = {"dx m", "dz m", "dvx m/s", "dvz m/s", "dGx m/s^2", "dGz m/s^2"};
    for (int i = 0; i < 6; ++i) {
        const double lin = (double)x[i];
        const double rel = fabs(fw[i] - lin) / fabs(lin);
        printf("[%s] bias 1e-12 on f2x, 1 h: %-9s firmware %+.6e  linear model %+.6e  rel.diff %.2e\n",
               VARIANT, names[i], fw[i], lin, rel);
        assert_true(rel < 0.01);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gravdr_10h),
        cmocka_unit_test(test_loop_perfect_baro),
        cmocka_unit_test(test_bias_matches_linear_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
