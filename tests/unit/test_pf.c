/* Particle filter (pf.h) against independent truth: the generator's sample statistics and a Kolmogorov-Smirnov test against
 * erf; the ellipse distance against brute-force minimisation over the ellipse;
 * the posterior of a static 1-D problem (known linear map, no process noise, no
 * resampling: the weighted particles are importance samples of the posterior)
 * against a grid-based Bayesian reference, with the unobserved axis staying at
 * its prior; determinism for a seed; failed shots; degenerate weights; bad input. */
#include <stdlib.h>
#include "test_common.h"
#include "ggins/pf.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif


static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, z = *(const double *)b;
    return (x > z) - (x < z);
}

static void test_rng(void **state)
{
    (void)state;
    static double z[100000];
    gg_rng_t r;
    const int n = 100000;
    assert_int_equal(gg_rng_seed(&r, 42), GG_OK);
    double mu = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
        double u = 0;
        assert_int_equal(gg_rng_uniform(&r, &u), GG_OK);
        assert_true(u >= 0.0 && u < 1.0);
        mu += u; m2 += u * u;
    }
    mu /= n; m2 /= n;
    assert_near(mu, 0.5, 5 * sqrt(1.0 / 12 / n));
    assert_near(m2 - mu * mu, 1.0 / 12, 5 * sqrt(1.0 / 180 / n));
    double m1 = 0, v = 0, k4 = 0;
    for (int i = 0; i < n; ++i) {
        assert_int_equal(gg_rng_normal(&r, &z[i]), GG_OK);
        m1 += z[i]; v += z[i] * z[i]; k4 += z[i] * z[i] * z[i] * z[i];
    }
    m1 /= n; v /= n; k4 /= n;
    printf("normal: mean %.4f var %.4f E[z^4] %.4f\n", m1, v, k4);
    assert_near(m1, 0.0, 5 / sqrt(n));
    assert_near(v, 1.0, 5 * sqrt(2.0 / n));
    assert_near(k4, 3.0, 5 * sqrt(96.0 / n));
    qsort(z, (size_t)n, sizeof z[0], cmp_d);
    double dmax = 0;
    for (int i = 0; i < n; ++i) {
        const double F = 0.5 * erfc(-z[i] / sqrt(2.0));
        dmax = fmax(dmax, fmax(fabs(F - (double)i / n), fabs(F - (double)(i + 1) / n)));
    }
    printf("KS D = %.5f (1%% critical %.5f)\n", dmax, 1.628 / sqrt(n));
    assert_true(dmax < 1.628 / sqrt(n));
}

/* brute force: dense sampling of the parameter, then golden-section refinement */
static double brute_dist(double s0, double s1, double c0, double c1, double A, double dphi)
{
    const int m = 4000;
    double best = 1e300, bt = 0;
    for (int i = 0; i < m; ++i) {
        const double t = 2 * M_PI * i / m;
        const double dx = s0 - (c0 - A * cos(t)), dy = s1 - (c1 - A * cos(t + dphi));
        if (dx * dx + dy * dy < best) { best = dx * dx + dy * dy; bt = t; }
    }
    double lo = bt - 2 * M_PI / m, hi = bt + 2 * M_PI / m;
    for (int it = 0; it < 100; ++it) {
        const double a = lo + 0.382 * (hi - lo), b = lo + 0.618 * (hi - lo);
        const double fa = pow(s0 - (c0 - A * cos(a)), 2) + pow(s1 - (c1 - A * cos(a + dphi)), 2);
        const double fb = pow(s0 - (c0 - A * cos(b)), 2) + pow(s1 - (c1 - A * cos(b + dphi)), 2);
        if (fa < fb) hi = b; else lo = a;
    }
    const double t = 0.5 * (lo + hi);
    return hypot(s0 - (c0 - A * cos(t)), s1 - (c1 - A * cos(t + dphi)));
}

static void test_ellipse_distance(void **state)
{
    (void)state;
    gg_rng_t r;
    gg_rng_seed(&r, 9);
    double worst = 0, worst_near = 0;
    for (int k = 0; k < 3000; ++k) {
        double u1 = 0, u2 = 0, u3 = 0, z = 0;
        gg_rng_uniform(&r, &u1); gg_rng_uniform(&r, &u2); gg_rng_uniform(&r, &u3);
        gg_rng_normal(&r, &z);
        const double dphi = 0.05 + 3.0 * u1, A = 0.25, t = 2 * M_PI * u2;
        /* points near the ellipse (the filter's regime) and far from it */
        const double off = (k % 3 == 0) ? 0.3 * (u3 - 0.5) : 0.01 * z;
        const double s0 = 0.5 - A * cos(t) + off, s1 = 0.5 - A * cos(t + dphi) - 0.7 * off;
        double d = 0;
        assert_int_equal(gg_pf_ellipse_distance(s0, s1, 0.5, 0.5, A, dphi, &d), GG_OK);
        const double ref = brute_dist(s0, s1, 0.5, 0.5, A, dphi);
        worst = fmax(worst, fabs(d - ref));
        if (k % 3 != 0) worst_near = fmax(worst_near, fabs(d - ref));
    }
    printf("ellipse distance vs brute force: worst %.2e (near the ellipse %.2e)\n", worst, worst_near);
    assert_true(worst_near < 1e-9);
    assert_true(worst < 1e-6);
}

/* Map: Gamma_zz = G0 + GE * east offset (m) from (LAT0, LON0); east from the same
 * WGS-84 radii (libm here). */
#define LAT0 0.8
#define LON0 -0.03
#define H0 3000.0
static const double G0 = 3.08e-6, GE = 3.0e-9;
static double rn_of(void)
{
    const double e2 = 6.69437999014e-3, s = sin(LAT0);
    return (6378137.0 / sqrt(1 - e2 * s * s) + H0) * cos(LAT0);
}
static gg_status_t map_lin(const void *ctx, double lat, double lon, double h, double *g)
{
    (void)ctx; (void)lat; (void)h;
    *g = G0 + GE * (lon - LON0) * rn_of();
    return GG_OK;
}
static gg_status_t map_off(const void *ctx, double lat, double lon, double h, double *g)
{
    (void)ctx; (void)lat; (void)lon; (void)h; (void)g;
    return GG_ERR_RANGE;
}

static gg_pf_config_t base_cfg(void)
{
    gg_pf_config_t c;
    memset(&c, 0, sizeof c);
    c.n = 500; c.seed = 1;
    c.k_eff = 4 * M_PI / 852.347e-9; c.T = 0.16; c.dz = 1.0; c.contrast = 0.5;
    c.c0 = 0.5; c.c1 = 0.5; c.sigma = 0.01;
    c.sigma0_pos = 100.0; c.sigma0_vel = 0.0; c.q_pos = 0.0; c.q_vel = 0.0;
    c.dt = 1.0; c.gain = 1.0; c.ess_frac = 0.5;
    c.map.gzz = map_lin; c.map.ctx = NULL;
    return c;
}

/* Static 1-D: truth east offset X, prior N(0, 100^2) on both axes, shots with
 * noise sigma; ess_frac 0 (no resampling). Reference: the posterior on a grid. */
static void test_posterior_1d(void **state)
{
    (void)state;
    const double X = 60.0, sig = 0.01, A = 0.25;
    const double scale = 4 * M_PI / 852.347e-9 * 1.0 * 0.16 * 0.16;
    enum { NS = 10, NG = 4001 };
    double s0[NS], s1[NS];
    gg_rng_t r;
    gg_rng_seed(&r, 77);
    for (int k = 0; k < NS; ++k) {
        double u = 0, z0 = 0, z1 = 0;
        gg_rng_uniform(&r, &u); gg_rng_normal(&r, &z0); gg_rng_normal(&r, &z1);
        const double dphi = scale * (G0 + GE * X), t = 2 * M_PI * u;
        s0[k] = 0.5 - A * cos(t) + 0.5 * sig * z0;
        s1[k] = 0.5 - A * cos(t + dphi) + 0.5 * sig * z1;
    }
    /* grid reference (brute-force distance, libm) */
    static double lp[NG];
    double lmax = -1e300;
    for (int i = 0; i < NG; ++i) {
        const double x = -500.0 + 0.25 * i;
        lp[i] = -0.5 * x * x / (100.0 * 100.0);
        for (int k = 0; k < NS; ++k) {
            const double d = brute_dist(s0[k], s1[k], 0.5, 0.5, A, scale * (G0 + GE * x));
            lp[i] -= d * d / (2 * sig * sig);
        }
        lmax = fmax(lmax, lp[i]);
    }
    double z = 0, m = 0, m2 = 0;
    for (int i = 0; i < NG; ++i) {
        const double x = -500.0 + 0.25 * i, p = exp(lp[i] - lmax);
        z += p; m += p * x; m2 += p * x * x;
    }
    m /= z; m2 = m2 / z - m * m;
    const double sd = sqrt(m2);
    /* the filter, averaged over independent seeds */
    const int runs = 40;
    double em = 0, ev = 0, nm = 0, nv = 0, ess_min = 1e9;
    for (int s = 0; s < runs; ++s) {
        gg_pf_config_t c = base_cfg();
        static gg_pf_t pf;
        gg_pf_output_t o;
        c.seed = 1000u + (uint64_t)s;
        c.ess_frac = 0.0;
        assert_int_equal(gg_pf_init(&pf, &c), GG_OK);
        for (int k = 0; k < NS; ++k) {
            gg_pf_input_t in = {LAT0, LON0, H0, 1, s0[k], s1[k], 0.0, 0.0};
            assert_int_equal(gg_pf_step(&pf, &in, &o), GG_OK);
        }
        double me = 0, ve = 0, mn = 0, vn = 0;
        for (int i = 0; i < c.n; ++i) {
            me += pf.w[i] * pf.x[i][1]; mn += pf.w[i] * pf.x[i][0];
        }
        for (int i = 0; i < c.n; ++i) {
            ve += pf.w[i] * pow(pf.x[i][1] - me, 2); vn += pf.w[i] * pow(pf.x[i][0] - mn, 2);
        }
        em += me / runs; ev += ve / runs; nm += mn / runs; nv += vn / runs;
        ess_min = fmin(ess_min, o.ess);
        assert_near(o.mean[1], me, 1e-9);
        assert_near(o.corr[1], me, 1e-9); /* gain 1 */
    }
    printf("1-D posterior east: grid mean %.2f sd %.2f | PF mean %.2f sd %.2f (ESS >= %.0f); north PF mean %.2f sd %.2f (prior 0, 100)\n",
           m, sd, em, sqrt(ev), ess_min, nm, sqrt(nv));
    /* Monte Carlo error of the seed average: ~ sd / sqrt(runs * ESS) */
    const double tol_m = 4 * sd / sqrt(runs * ess_min);
    assert_near(em, m, tol_m);
    assert_near(sqrt(ev), sd, 0.1 * sd);
    assert_true(sd < 40.0); /* the shots did constrain the east axis */
    assert_near(nm, 0.0, 4 * 100.0 / sqrt(runs * ess_min));
    assert_near(sqrt(nv), 100.0, 10.0);
}

static void test_determinism_and_skip(void **state)
{
    (void)state;
    static gg_pf_t a, b;
    gg_pf_config_t c = base_cfg();
    c.q_pos = 2.0; c.q_vel = 0.01; c.sigma0_vel = 0.2; c.gain = 0.1;
    gg_pf_output_t oa, ob;
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    assert_int_equal(gg_pf_init(&b, &c), GG_OK);
    for (int k = 0; k < 50; ++k) {
        gg_pf_input_t in = {LAT0, LON0, H0, (k % 5) != 0, 0.5 + 0.25 * cos(k), 0.5 - 0.25 * cos(k + 1.16), 0.0, 0.0};
        assert_int_equal(gg_pf_step(&a, &in, &oa), GG_OK);
        assert_int_equal(gg_pf_step(&b, &in, &ob), GG_OK);
        assert_memory_equal(&oa, &ob, sizeof oa);
    }
    assert_memory_equal(a.x, b.x, sizeof a.x);
    c.seed = 2;
    assert_int_equal(gg_pf_init(&b, &c), GG_OK);
    assert_true(memcmp(a.x, b.x, sizeof a.x) != 0);
    /* failed shot: weights untouched (uniform -> ESS = N), particles only predicted */
    c.q_pos = 0; c.q_vel = 0; c.sigma0_vel = 0;
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    double before[GG_PF_MAX][GG_PF_NX];
    memcpy(before, a.x, sizeof before);
    gg_pf_input_t fail = {LAT0, LON0, H0, 0, NAN, NAN, 0.0, 0.0}; /* the pair is not read */
    assert_int_equal(gg_pf_step(&a, &fail, &oa), GG_OK);
    assert_true(oa.health & GG_PF_H_SKIPPED);
    assert_near(oa.ess, 500.0, 1e-9);
    for (int i = 0; i < c.n; ++i)
        for (int k = 0; k < GG_PF_NX; ++k) assert_true(before[i][k] == a.x[i][k]); /* +0 == -0 */
}

static void test_degenerate_and_bad_input(void **state)
{
    (void)state;
    static gg_pf_t a, snap;
    gg_pf_config_t c = base_cfg();
    c.map.gzz = map_off;
    gg_pf_output_t o;
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.6, 0.4, 0.0, 0.0};
    assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
    assert_true(o.health & GG_PF_H_DEGENERATE);
    assert_true(o.health & GG_PF_H_MAP_MISS);
    assert_near(o.ess, 500.0, 1e-9);
    assert_true(isfinite(o.corr[0]) && isfinite(o.corr[1]) && isfinite(o.mean[2]));
    for (int i = 0; i < c.n; ++i) assert_true(isfinite(a.w[i]));
    /* a pair far from every candidate: exp underflows for all but the best, never NaN */
    c = base_cfg();
    c.sigma = 1e-6;
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    gg_pf_input_t far = {LAT0, LON0, H0, 1, 3.0, -3.0, 0.0, 0.0};
    assert_int_equal(gg_pf_step(&a, &far, &o), GG_OK);
    assert_true(isfinite(o.corr[0]) && isfinite(o.ess) && o.ess >= 1.0);
    /* bad input: state untouched */
    memcpy(&snap, &a, sizeof a);
    gg_pf_input_t bad = {LAT0, LON0, H0, 1, NAN, 0.5, 0.0, 0.0};
    assert_int_equal(gg_pf_step(&a, &bad, &o), GG_ERR_NONFINITE);
    gg_pf_input_t bad2 = {2.0, LON0, H0, 1, 0.5, 0.5, 0.0, 0.0};
    assert_int_equal(gg_pf_step(&a, &bad2, &o), GG_ERR_RANGE);
    assert_memory_equal(&snap, &a, sizeof a);
    assert_int_equal(gg_pf_step(NULL, &bad, &o), GG_ERR_NULL);
    /* configuration */
    c = base_cfg(); c.n = GG_PF_MAX + 1;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    c = base_cfg(); c.sigma = 0;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    c = base_cfg(); c.map.gzz = NULL;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    c = base_cfg(); c.gain = NAN;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    /* finite but absurd: an initial spread of 3e154 m (a fuzz finding) made the
     * cloud's spread overflow and fed a 2e153 m correction back; each bound
     * accepted at the limit, refused beyond it */
    c = base_cfg(); c.sigma0_pos = 3.0e154;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    {
        struct { double *f; double lim; } b[] = {
            {&c.k_eff, GG_LIM_PF_K_EFF_MAX}, {&c.T, GG_LIM_PF_T_MAX_S}, {&c.dz, GG_LIM_PF_DZ_MAX_M},
            {&c.dt, GG_LIM_PF_DT_MAX_S}, {&c.sigma, GG_LIM_PF_S_MAX}, {&c.c0, GG_LIM_PF_S_MAX},
            {&c.c1, GG_LIM_PF_S_MAX}, {&c.sigma0_pos, GG_LIM_PF_POS_SIGMA_MAX_M},
            {&c.q_pos, GG_LIM_PF_POS_SIGMA_MAX_M}, {&c.sigma0_vel, GG_LIM_PF_VEL_SIGMA_MAX_MPS},
            {&c.q_vel, GG_LIM_PF_VEL_SIGMA_MAX_MPS}, {&c.sigma0_acc, GG_LIM_PF_ACC_SIGMA_MAX_MPS2},
            {&c.q_acc, GG_LIM_PF_ACC_SIGMA_MAX_MPS2}, {&c.sigma0_bias, GG_LIM_PF_ACC_SIGMA_MAX_MPS2},
            {&c.q_bias, GG_LIM_PF_ACC_SIGMA_MAX_MPS2}, {&c.sigma0_jerk, GG_LIM_PF_JERK_SIGMA_MAX_MPS3},
            {&c.q_jerk, GG_LIM_PF_JERK_SIGMA_MAX_MPS3}};
        for (size_t i = 0; i < sizeof b / sizeof b[0]; ++i) {
            c = base_cfg();
            *b[i].f = b[i].lim;
            if (gg_pf_init(&a, &c) != GG_OK) fail_msg("bound %zu refused at its limit", i);
            c = base_cfg();
            *b[i].f = b[i].lim * 1.000001;
            if (gg_pf_init(&a, &c) != GG_ERR_CONFIG) fail_msg("bound %zu not enforced", i);
        }
        c = base_cfg(); c.c0 = -GG_LIM_PF_S_MAX * 1.000001;
        assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    }
    memset(&snap, 0, sizeof snap);
    assert_int_equal(gg_pf_step(&snap, &in, &o), GG_ERR_NOT_INIT);
}

/* Systematic resampling: each particle gets floor(N w) or ceil(N w) copies. */
static void test_resampling_counts(void **state)
{
    (void)state;
    static gg_pf_t a;
    gg_pf_config_t c = base_cfg();
    c.sigma = 0.003;
    c.ess_frac = 1.0; /* always resample after the update */
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    for (int i = 0; i < c.n; ++i) a.x[i][0] = (double)i; /* tag the particles (north: no effect on the map) */
    gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.5 - 0.25 * cos(0.3), 0.5 - 0.25 * cos(0.3 + 1.2), 0.0, 0.0};
    /* predict the weights independently: w_i ~ exp(-d_i^2 / 2 s^2) at the candidate's map value */
    double w[GG_PF_MAX], sw = 0;
    const double scale = c.k_eff * c.dz * c.T * c.T;
    for (int i = 0; i < c.n; ++i) {
        const double g = G0 + GE * a.x[i][1];
        const double d = brute_dist(in.s0, in.s1, 0.5, 0.5, 0.25, scale * g);
        w[i] = exp(-d * d / (2 * c.sigma * c.sigma));
        sw += w[i];
    }
    gg_pf_output_t o;
    assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
    assert_true(o.health & GG_PF_H_RESAMPLED);
    int cnt[GG_PF_MAX] = {0};
    for (int i = 0; i < c.n; ++i) {
        const int tag = (int)a.x[i][0];
        assert_true(tag >= 0 && tag < c.n && fabs(a.x[i][0] - tag) == 0.0);
        cnt[tag]++;
    }
    for (int i = 0; i < c.n; ++i) {
        const double nw = c.n * w[i] / sw;
        assert_true(cnt[i] >= (int)floor(nw - 1e-6) && cnt[i] <= (int)ceil(nw + 1e-6));
    }
}


/* MODEL_INS propagation (no noise, failed shots) against independent solutions of the
 * continuous horizontal INS error equations r' = v, v' = -w_s^2 r + a -/+ 2 W sinL k x v:
 * at the equator (no Coriolis) the closed form r = r0 cos wt + v0/w sin wt + a/w^2 (1 - cos wt);
 * at 45 deg an RK4 integration (0.1 s steps) of the coupled N/E system. 2 h, 1 s steps. */
static double ws2_of(double lat, double h)
{
    const double e2 = 6.69437999014e-3, s = sin(lat), w2 = 1 - e2 * s * s, nr = 6378137.0 / sqrt(w2);
    const double rm = nr * (1 - e2) / w2 + h;
    return 9.80665 / sqrt(rm * (nr + h));
}
static void ins_rhs(const double y[6], double ws2, double f, double d[6])
{
    d[0] = y[2]; d[1] = y[3];
    d[2] = -ws2 * y[0] + y[4] - f * y[3];
    d[3] = -ws2 * y[1] + y[5] + f * y[2];
    d[4] = 0; d[5] = 0;
}
static void test_ins_model_propagation(void **state)
{
    (void)state;
    static gg_pf_t a;
    const double y0[6] = {300.0, -200.0, 0.4, -0.25, 2e-4, -3e-4};
    for (int pass = 0; pass < 2; ++pass) {
        const double lat = pass == 0 ? 0.0 : M_PI / 4;
        gg_pf_config_t c = base_cfg();
        c.model = GG_PF_MODEL_INS; c.n = 1; c.sigma0_pos = 0; c.gain = 1.0;
        assert_int_equal(gg_pf_init(&a, &c), GG_OK);
        for (int k = 0; k < 6; ++k) a.x[0][k] = y0[k];
        const double ws2 = ws2_of(lat, H0), w = sqrt(ws2), f = 2 * 7.292115e-5 * sin(lat);
        double y[6];
        memcpy(y, y0, sizeof y);
        double worst = 0, amp = 0;
        gg_pf_output_t o;
        for (int n = 1; n <= 7200; ++n) {
            gg_pf_input_t in = {lat, LON0, H0, 0, 0, 0, 0.0, 0.0};
            assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
            double ref[2];
            if (pass == 0) {
                const double t = n, ct = cos(w * t), st = sin(w * t);
                for (int ax = 0; ax < 2; ++ax)
                    ref[ax] = y0[ax] * ct + y0[2 + ax] / w * st + y0[4 + ax] / ws2 * (1 - ct);
            } else {
                for (int sub = 0; sub < 10; ++sub) { /* RK4, 0.1 s */
                    double k1[6], k2[6], k3[6], k4[6], t1[6];
                    const double hh = 0.1;
                    ins_rhs(y, ws2, f, k1);
                    for (int j = 0; j < 6; ++j) t1[j] = y[j] + 0.5 * hh * k1[j];
                    ins_rhs(t1, ws2, f, k2);
                    for (int j = 0; j < 6; ++j) t1[j] = y[j] + 0.5 * hh * k2[j];
                    ins_rhs(t1, ws2, f, k3);
                    for (int j = 0; j < 6; ++j) t1[j] = y[j] + hh * k3[j];
                    ins_rhs(t1, ws2, f, k4);
                    for (int j = 0; j < 6; ++j) y[j] += hh / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
                }
                ref[0] = y[0]; ref[1] = y[1];
            }
            worst = fmax(worst, hypot(a.x[0][0] - ref[0], a.x[0][1] - ref[1]));
            amp = fmax(amp, hypot(ref[0], ref[1]));
        }
        printf("INS-model propagation at lat %.0f deg, 2 h: worst |r - reference| %.2f m (max |r| %.0f m)\n",
               lat * 180 / M_PI, worst, amp);
        /* semi-implicit Euler at w dt = 1.2e-3 keeps amplitude and phase to ~ 2e-4 of the amplitude
         * over 2 h (measured); a wrong Coriolis sign gives 0.16 x amplitude, no Schuler term ~ 10x */
        assert_true(amp > 300.0);
        assert_true(worst < 1e-3 * amp);
        assert_near(o.mean[4], y0[4], 1e-18); /* no process noise: the specific-force state is constant */
    }
}

/* MODEL_INS process noise: the spread of the cloud without measurements against the
 * covariance of the continuous model r' = v, v' = -w_s^2 r + a + n_v, a' = n_a (+ white
 * position noise), propagated by the Lyapunov ODE P' = A P + P A^T + Q (RK4, 0.05 s)
 * at the equator (axes independent). 1000 s, 500 particles x 8 seeds, N and E pooled. */
static void lyap_rhs(const double P[3][3], double ws2, const double q[3], double D[3][3])
{
    const double A[3][3] = {{0, 1, 0}, {-ws2, 0, 1}, {0, 0, 0}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = 0;
            for (int k = 0; k < 3; ++k) s += A[i][k] * P[k][j] + P[i][k] * A[j][k];
            D[i][j] = s + (i == j ? q[i] : 0.0);
        }
}
static void test_ins_model_spread(void **state)
{
    (void)state;
    static gg_pf_t a;
    const double qp = 0.5, qv = 2e-3, qa = 2e-5, s0p = 20, s0v = 0.1, s0a = 3e-4, T = 1000;
    const int seeds = 8;
    double vr = 0, vv = 0, va = 0, crv = 0;
    for (int sd = 0; sd < seeds; ++sd) {
        gg_pf_config_t c = base_cfg();
        c.model = GG_PF_MODEL_INS; c.seed = 500u + (uint64_t)sd;
        c.sigma0_pos = s0p; c.sigma0_vel = s0v; c.sigma0_acc = s0a;
        c.q_pos = qp; c.q_vel = qv; c.q_acc = qa;
        assert_int_equal(gg_pf_init(&a, &c), GG_OK);
        gg_pf_output_t o;
        for (int n = 0; n < (int)T; ++n) {
            gg_pf_input_t in = {0.0, LON0, H0, 0, 0, 0, 0.0, 0.0};
            assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
        }
        for (int ax = 0; ax < 2; ++ax) {
            double m[3] = {0, 0, 0};
            for (int i = 0; i < c.n; ++i)
                for (int k = 0; k < 3; ++k) m[k] += a.x[i][ax + 2 * k] / c.n;
            for (int i = 0; i < c.n; ++i) {
                const double dr = a.x[i][ax] - m[0], dv = a.x[i][ax + 2] - m[1], da = a.x[i][ax + 4] - m[2];
                vr += dr * dr; vv += dv * dv; va += da * da; crv += dr * dv;
            }
        }
    }
    const double nn = 2.0 * seeds * (500 - 1);
    vr /= nn; vv /= nn; va /= nn; crv /= nn;
    /* reference: white noise per 1 s step = spectral density q^2 (dt = 1) */
    const double ws2 = ws2_of(0.0, H0), q[3] = {qp * qp, qv * qv, qa * qa};
    double P[3][3] = {{s0p * s0p, 0, 0}, {0, s0v * s0v, 0}, {0, 0, s0a * s0a}};
    const double hh = 0.05;
    for (int n = 0; n < (int)(T / hh + 0.5); ++n) {
        double k1[3][3], k2[3][3], k3[3][3], k4[3][3], t1[3][3];
        lyap_rhs(P, ws2, q, k1);
        for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) t1[i][j] = P[i][j] + 0.5 * hh * k1[i][j];
        lyap_rhs(t1, ws2, q, k2);
        for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) t1[i][j] = P[i][j] + 0.5 * hh * k2[i][j];
        lyap_rhs(t1, ws2, q, k3);
        for (int i = 0; i < 3; ++i) for (int j = 0; j < 3; ++j) t1[i][j] = P[i][j] + hh * k3[i][j];
        lyap_rhs(t1, ws2, q, k4);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) P[i][j] += hh / 6 * (k1[i][j] + 2 * k2[i][j] + 2 * k3[i][j] + k4[i][j]);
    }
    printf("INS-model spread after %.0f s: sd r %.1f m (Lyapunov %.1f), v %.3f m/s (%.3f), a %.2e (%.2e), "
           "corr(r,v) %.3f (%.3f)\n", T, sqrt(vr), sqrt(P[0][0]), sqrt(vv), sqrt(P[1][1]), sqrt(va), sqrt(P[2][2]),
           crv / sqrt(vr * vv), P[0][1] / sqrt(P[0][0] * P[1][1]));
    /* sampling error of a variance from 7984 draws: 1.6 %; discretisation (1 s vs continuous) < 1 % */
    assert_near(vr / P[0][0], 1.0, 0.07);
    assert_near(vv / P[1][1], 1.0, 0.07);
    assert_near(va / P[2][2], 1.0, 0.07);
    assert_near(crv / sqrt(vr * vv), P[0][1] / sqrt(P[0][0] * P[1][1]), 0.05);
}

/* Regularised resampling: a correlated cloud, one shot with a linear map (weights known
 * independently from the brute-force distance), forced resampling. After it the equally
 * weighted cloud must keep the weighted mean and covariance of before (Liu-West
 * shrinkage; without it the covariance would grow by 1 + h^2 = 1.25), and all particles
 * must be distinct (plain resampling duplicates). 20 seeds. */
static void test_regularised_resampling(void **state)
{
    (void)state;
    static gg_pf_t a;
    const int seeds = 20;
    double acc_dm = 0, acc_rv = 0, acc_rc = 0, acc_rn = 0;
    int distinct_min = GG_PF_MAX, distinct_plain = 0;
    for (int sd = 0; sd < seeds + 1; ++sd) {
        gg_pf_config_t c = base_cfg();
        c.model = GG_PF_MODEL_INS; c.seed = 900u + (uint64_t)sd;
        c.sigma = 0.004; c.ess_frac = 1.0; c.sigma0_pos = 0;
        c.reg_bw = (sd < seeds) ? 1.0 : 0.0; /* the last run: plain resampling */
        assert_int_equal(gg_pf_init(&a, &c), GG_OK);
        if (c.reg_bw > 0) {
            const double h = pow(4.0 / (8.0 * c.n), 1.0 / 10.0); /* Silverman, d = 6 */
            assert_near(a.reg_h, h, 1e-12);
        }
        gg_rng_t r;
        gg_rng_seed(&r, 4242u + (uint64_t)sd);
        for (int i = 0; i < c.n; ++i) { /* east and east velocity correlated, north independent */
            double z1 = 0, z2 = 0, z3 = 0;
            gg_rng_normal(&r, &z1); gg_rng_normal(&r, &z2); gg_rng_normal(&r, &z3);
            a.x[i][1] = 150.0 * z1; a.x[i][3] = 0.3 * z1 + 0.1 * z2; a.x[i][0] = 80.0 * z3;
            for (int k = 4; k < 6; ++k) a.x[i][k] = 0;
            a.x[i][2] = 0;
        }
        /* the prediction (no noise) first moves the particles; weights at the predicted positions */
        gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.5 - 0.25 * cos(0.3), 0.5 - 0.25 * cos(0.3 + 1.16), 0.0, 0.0};
        static double xp[GG_PF_MAX][GG_PF_NX];
        {
            const double e2 = 6.69437999014e-3, sl = sin(LAT0), w2 = 1 - e2 * sl * sl, nr = 6378137.0 / sqrt(w2);
            const double ws2 = 9.80665 / sqrt((nr * (1 - e2) / w2 + H0) * (nr + H0)), f = 2 * 7.292115e-5 * sl;
            for (int i = 0; i < c.n; ++i) {
                const double vn = a.x[i][2] + (-ws2 * a.x[i][0] - f * a.x[i][3]);
                const double ve = a.x[i][3] + (-ws2 * a.x[i][1] + f * a.x[i][2]);
                xp[i][0] = a.x[i][0] + vn; xp[i][1] = a.x[i][1] + ve; xp[i][2] = vn; xp[i][3] = ve;
                xp[i][4] = 0; xp[i][5] = 0;
            }
        }
        double w[GG_PF_MAX], sw = 0;
        const double scale = c.k_eff * c.dz * c.T * c.T;
        for (int i = 0; i < c.n; ++i) {
            const double d = brute_dist(in.s0, in.s1, 0.5, 0.5, 0.25, scale * (G0 + GE * xp[i][1]));
            w[i] = exp(-d * d / (2 * c.sigma * c.sigma));
            sw += w[i];
        }
        double m[4] = {0, 0, 0, 0}, cv[4][4] = {{0}};
        for (int i = 0; i < c.n; ++i)
            for (int k = 0; k < 4; ++k) m[k] += w[i] / sw * xp[i][k];
        for (int i = 0; i < c.n; ++i)
            for (int j = 0; j < 4; ++j)
                for (int k = 0; k < 4; ++k) cv[j][k] += w[i] / sw * (xp[i][j] - m[j]) * (xp[i][k] - m[k]);
        gg_pf_output_t o;
        assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
        assert_true(o.health & GG_PF_H_RESAMPLED);
        double ma[4] = {0, 0, 0, 0}, ca[4][4] = {{0}};
        for (int i = 0; i < c.n; ++i)
            for (int k = 0; k < 4; ++k) ma[k] += a.x[i][k] / c.n;
        for (int i = 0; i < c.n; ++i)
            for (int j = 0; j < 4; ++j)
                for (int k = 0; k < 4; ++k) ca[j][k] += (a.x[i][j] - ma[j]) * (a.x[i][k] - ma[k]) / c.n;
        int distinct = 0;
        for (int i = 0; i < c.n; ++i) {
            int dup = 0;
            for (int j = 0; j < i && !dup; ++j) dup = (a.x[j][1] == a.x[i][1]);
            distinct += !dup;
        }
        if (c.reg_bw > 0) {
            acc_dm += (ma[1] - m[1]) / sqrt(cv[1][1]) / seeds;
            acc_rv += ca[1][1] / cv[1][1] / seeds;
            acc_rn += ca[0][0] / cv[0][0] / seeds;
            acc_rc += (ca[1][3] / sqrt(ca[1][1] * ca[3][3]) - cv[1][3] / sqrt(cv[1][1] * cv[3][3])) / seeds;
            distinct_min = distinct < distinct_min ? distinct : distinct_min;
        } else {
            distinct_plain = distinct;
        }
    }
    printf("regularised resampling (20 seeds): mean shift %.3f sd, var ratio east %.3f north %.3f, "
           "corr(E, vE) change %.4f; distinct %d (plain resampling %d)\n", acc_dm, acc_rv, acc_rn, acc_rc,
           distinct_min, distinct_plain);
    /* per seed the resampled mean scatters by ~ sd sqrt(1/ESS) and the variance ratio by ~ sqrt(2/ESS);
     * averaged over 20 seeds: mean 0.02 sd, ratio ~ 0.02 */
    assert_near(acc_dm, 0.0, 0.08);
    assert_near(acc_rv, 1.0, 0.08);
    assert_near(acc_rn, 1.0, 0.08);
    assert_near(acc_rc, 0.0, 0.03);
    assert_int_equal(distinct_min, 500);
    assert_true(distinct_plain < 450);
}

/* The gmap adapter: a tile holding a cubic polynomial in (lat, lon) as DD (bicubic
 * Lagrange is exact for it) and a linear height term; values vs the polynomial. */
static void test_gmap_adapter(void **state)
{
    (void)state;
    static gg_gmap_t gm;
    static gg_gmap_tile_t tile;
    memset(&tile, 0, sizeof tile);
    tile.nlat = 20; tile.nlon = 20; tile.lat0_rad = 0.8; tile.lon0_rad = -0.03;
    tile.dlat_rad = 1e-4; tile.dlon_rad = 1e-4; tile.h0_m = 3000.0; tile.h_range_m = 500.0;
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 20; ++j) {
            const double a = i * 1e-4, b = j * 1e-4;
            tile.node[i * 20 + j][GG_GMAP_C_DD] = 3.08e-6 + 1e-5 * a - 2e-5 * b + 3e-3 * a * a * b + 1e-1 * b * b * b;
            tile.node[i * 20 + j][GG_GMAP_NCOMP + GG_GMAP_C_DD] = -1.45e-12;
        }
    assert_int_equal(gg_gmap_init(&gm, &tile), GG_OK);
    gg_pf_map_t m;
    assert_int_equal(gg_pf_map_from_gmap(&gm, &m), GG_OK);
    double worst = 0;
    for (int k = 0; k < 100; ++k) {
        const double a = 3e-4 + 1.2e-3 * (k % 10) / 10.0, b = 2e-4 + 1.3e-3 * (k / 10) / 10.0, h = 3000.0 + 7.0 * k;
        double g = 0;
        assert_int_equal(m.gzz(m.ctx, 0.8 + a, -0.03 + b, h, &g), GG_OK);
        const double ref = 3.08e-6 + 1e-5 * a - 2e-5 * b + 3e-3 * a * a * b + 1e-1 * b * b * b - 1.45e-12 * (h - 3000.0);
        worst = fmax(worst, fabs(g - ref));
    }
    printf("gmap adapter: worst |DD - polynomial| %.2e s^-2\n", worst);
    assert_true(worst < 1e-18);
    double g = 0;
    assert_int_equal(m.gzz(m.ctx, 0.9, -0.03, 3000.0, &g), GG_ERR_RANGE);
    static gg_gmap_t empty;
    memset(&empty, 0, sizeof empty);
    assert_int_equal(gg_pf_map_from_gmap(&empty, &m), GG_ERR_NOT_INIT);
}

/* ---- Rao-Blackwellised model (GG_PF_MODEL_RBPF) ----
 * Independent truth: the psi-angle INS error equations written with vector cross
 * products in physical states p = (rN, rE, vN, vE, psiN, psiE, psiD, epsN, epsE, epsD,
 * bN, bE) (the form of the coldatom truth, flight.cpp): v' = -psi x f - w_s^2 r
 * - 2 Omega x v + b, psi' = -(Omega + rho) x psi + eps, f = (0, 0, -g), integrated by
 * RK4; the filter's states are p mapped by a = g (psiE, -psiN, psiD), j = g (epsE, -epsN, epsD). */
#define RB_G 9.80665
#define RB_OM 7.292115e-5
typedef struct { double ws2, om[3], wie[3]; } rb_geo_t;
static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1]; c[1] = a[2] * b[0] - a[0] * b[2]; c[2] = a[0] * b[1] - a[1] * b[0];
}
static rb_geo_t rb_geo(double lat, double h, double vn, double ve)
{
    const double e2 = 6.69437999014e-3, sl = sin(lat), cl = cos(lat), w2 = 1 - e2 * sl * sl, nr = 6378137.0 / sqrt(w2);
    const double rm = nr * (1 - e2) / w2 + h, rn = nr + h;
    rb_geo_t g;
    g.ws2 = RB_G / sqrt(rm * rn);
    g.wie[0] = RB_OM * cl; g.wie[1] = 0; g.wie[2] = -RB_OM * sl;
    g.om[0] = g.wie[0] + ve / rn; g.om[1] = -vn / rm; g.om[2] = g.wie[2] - ve * tan(lat) / rn;
    return g;
}
static void rb_phys_rhs(const rb_geo_t *g, const double p[12], double d[12])
{
    const double f[3] = {0, 0, -RB_G}, v[3] = {p[2], p[3], 0}, psi[3] = {p[4], p[5], p[6]};
    double pf[3], wv[3], wp[3];
    cross3(psi, f, pf); cross3(g->wie, v, wv); cross3(g->om, psi, wp);
    d[0] = p[2]; d[1] = p[3];
    d[2] = -pf[0] - g->ws2 * p[0] - 2 * wv[0] + p[10];
    d[3] = -pf[1] - g->ws2 * p[1] - 2 * wv[1] + p[11];
    for (int i = 0; i < 3; ++i) d[4 + i] = -wp[i] + p[7 + i];
    for (int i = 7; i < 12; ++i) d[i] = 0;
}
/* filter state = T p */
static void rb_to_filter(const double p[12], double x[12])
{
    x[0] = p[0]; x[1] = p[1]; x[2] = p[2]; x[3] = p[3];
    x[4] = RB_G * p[5]; x[5] = -RB_G * p[4]; x[6] = RB_G * p[6];
    x[7] = RB_G * p[8]; x[8] = -RB_G * p[7]; x[9] = RB_G * p[9];
    x[10] = p[10]; x[11] = p[11];
}
static void rb_to_phys(const double x[12], double p[12])
{
    p[0] = x[0]; p[1] = x[1]; p[2] = x[2]; p[3] = x[3];
    p[5] = x[4] / RB_G; p[4] = -x[5] / RB_G; p[6] = x[6] / RB_G;
    p[8] = x[7] / RB_G; p[7] = -x[8] / RB_G; p[9] = x[9] / RB_G;
    p[10] = x[10]; p[11] = x[11];
}
/* RK4 of the physical equations over t seconds in steps of hh, in filter coordinates */
static void rb_rk4(const rb_geo_t *g, double x[12], double t, double hh)
{
    double p[12], k1[12], k2[12], k3[12], k4[12], y[12];
    rb_to_phys(x, p);
    const long n = lround(t / hh);
    for (long s = 0; s < n; ++s) {
        rb_phys_rhs(g, p, k1);
        for (int i = 0; i < 12; ++i) y[i] = p[i] + 0.5 * hh * k1[i];
        rb_phys_rhs(g, y, k2);
        for (int i = 0; i < 12; ++i) y[i] = p[i] + 0.5 * hh * k2[i];
        rb_phys_rhs(g, y, k3);
        for (int i = 0; i < 12; ++i) y[i] = p[i] + hh * k3[i];
        rb_phys_rhs(g, y, k4);
        for (int i = 0; i < 12; ++i) p[i] += hh / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    rb_to_filter(p, x);
}
/* A in filter coordinates, column by column (the equations are linear) */
static void rb_afilt(const rb_geo_t *g, double A[12][12])
{
    for (int k = 0; k < 12; ++k) {
        double x[12] = {0}, p[12], d[12], dx[12];
        x[k] = 1;
        rb_to_phys(x, p);
        rb_phys_rhs(g, p, d);
        rb_to_filter(d, dx);
        for (int i = 0; i < 12; ++i) A[i][k] = dx[i];
    }
}
/* continuous Lyapunov P' = A P + P A^T + diag(qc) by RK4 over t */
static void rb_lyap_rhs(double A[12][12], const double qc[12], double P[12][12], double D[12][12])
{
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j) {
            double s = 0;
            for (int k = 0; k < 12; ++k) s += A[i][k] * P[k][j] + P[i][k] * A[j][k];
            D[i][j] = s + (i == j ? qc[i] : 0.0);
        }
}
static void rb_lyap(double A[12][12], const double qc[12], double P[12][12], double t, double hh)
{
    static double k1[12][12], k2[12][12], k3[12][12], k4[12][12], y[12][12];
    const long n = lround(t / hh);
    for (long s = 0; s < n; ++s) {
        rb_lyap_rhs(A, qc, P, k1);
        for (int i = 0; i < 12; ++i) for (int j = 0; j < 12; ++j) y[i][j] = P[i][j] + 0.5 * hh * k1[i][j];
        rb_lyap_rhs(A, qc, y, k2);
        for (int i = 0; i < 12; ++i) for (int j = 0; j < 12; ++j) y[i][j] = P[i][j] + 0.5 * hh * k2[i][j];
        rb_lyap_rhs(A, qc, y, k3);
        for (int i = 0; i < 12; ++i) for (int j = 0; j < 12; ++j) y[i][j] = P[i][j] + hh * k3[i][j];
        rb_lyap_rhs(A, qc, y, k4);
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j) P[i][j] += hh / 6 * (k1[i][j] + 2 * k2[i][j] + 2 * k3[i][j] + k4[i][j]);
    }
}
static gg_pf_config_t rb_cfg(void)
{
    gg_pf_config_t c = base_cfg();
    c.model = GG_PF_MODEL_RBPF;
    c.sigma0_pos = 20; c.sigma0_vel = 0.1; c.sigma0_acc = 1e-4; c.sigma0_jerk = 5e-7; c.sigma0_bias = 3e-4;
    c.q_pos = 0.05; c.q_vel = 2e-3; c.q_acc = 2e-5; c.q_jerk = 1e-9; c.q_bias = 1e-6;
    return c;
}

/* F = exp(A dt) and Q of one step against RK4 of the cross-product equations and of the
 * Lyapunov equation; then 3 h of F^k from a gyro-bias and accelerometer-bias start
 * against 3 h of RK4 (the Earth-rate rotation of the tilt, 0.6 rad, must be right). */
static void test_rb_model(void **state)
{
    (void)state;
    gg_pf_config_t c = rb_cfg();
    const double lat = 0.85, h = 3000, vn = -97, ve = 26;
    static double F[12][12], Q[12][12], T[12][12], A[12][12], Pq[12][12];
    assert_int_equal(gg_pf_rb_model(&c, lat, h, vn, ve, F, Q, T), GG_OK);
    const rb_geo_t g = rb_geo(lat, h, vn, ve);
    double worst_f = 0, worst_q = 0;
    for (int k = 0; k < 12; ++k) {
        double x[12] = {0};
        x[k] = 1;
        rb_rk4(&g, x, 1.0, 0.01);
        for (int i = 0; i < 12; ++i) worst_f = fmax(worst_f, fabs(F[i][k] - x[i]));
    }
    rb_afilt(&g, A);
    const double qc[12] = {c.q_pos * c.q_pos, c.q_pos * c.q_pos, c.q_vel * c.q_vel, c.q_vel * c.q_vel,
                           c.q_acc * c.q_acc, c.q_acc * c.q_acc, c.q_acc * c.q_acc,
                           c.q_jerk * c.q_jerk, c.q_jerk * c.q_jerk, c.q_jerk * c.q_jerk,
                           c.q_bias * c.q_bias, c.q_bias * c.q_bias}; /* dt = 1 s */
    memset(Pq, 0, sizeof Pq);
    rb_lyap(A, qc, Pq, 1.0, 0.01);
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
            worst_q = fmax(worst_q, fabs(Q[i][j] - Pq[i][j]) / sqrt(Pq[i][i] * Pq[j][j]));
    /* long horizon */
    double x0[12] = {0, 0, 0, 0, 0, 0, 0, RB_G * 4e-8, -RB_G * 3e-8, RB_G * 5e-8, 2e-4, -1e-4};
    double xf[12], xr[12];
    memcpy(xf, x0, sizeof xf); memcpy(xr, x0, sizeof xr);
    for (int k = 0; k < 10800; ++k) {
        double y[12];
        for (int i = 0; i < 12; ++i) {
            y[i] = 0;
            for (int q = 0; q < 12; ++q) y[i] += F[i][q] * xf[q];
        }
        memcpy(xf, y, sizeof y);
    }
    rb_rk4(&g, xr, 10800.0, 0.1);
    const double rr = hypot(xr[0], xr[1]);
    const double dr = hypot(xf[0] - xr[0], xf[1] - xr[1]);
    printf("RBPF model: |F - RK4| %.2e, |Q - Lyapunov| %.2e (relative), 3 h from gyro + accelerometer biases: "
           "|r| %.1f m, F^k vs RK4 %.2e m\n", worst_f, worst_q, rr, dr);
    assert_true(worst_f < 1e-10);
    assert_true(worst_q < 1e-8);
    assert_true(rr > 1000.0);
    assert_true(dr < 1e-6 * rr);
}

/* Without measurements the Rao-Blackwellised cloud is a Gaussian mixture whose covariance
 * (spread of the particles' (r, m) plus P) must follow the Lyapunov equation of the
 * continuous model from the prior: 600 s, 8 seeds x 500 particles. */
static void test_rb_spread(void **state)
{
    (void)state;
    static gg_pf_t a;
    static double A[12][12], P[12][12];
    const double lat = 0.85, h = 3000, vn = -97, ve = 26, T = 600;
    const int seeds = 8;
    double var[12] = {0};
    double info_sum = 0.0;
    gg_pf_config_t c = rb_cfg();
    for (int sd = 0; sd < seeds; ++sd) {
        c.seed = 700u + (uint64_t)sd;
        assert_int_equal(gg_pf_init(&a, &c), GG_OK);
        gg_pf_output_t o;
        for (int n = 0; n < (int)T; ++n) {
            gg_pf_input_t in = {lat, LON0, h, 0, 0, 0, vn, ve};
            assert_int_equal(gg_pf_step(&a, &in, &o), GG_OK);
        }
        double m[12] = {0};
        for (int i = 0; i < c.n; ++i)
            for (int k = 0; k < 12; ++k) m[k] += a.x[i][k] / c.n;
        for (int i = 0; i < c.n; ++i)
            for (int k = 0; k < 12; ++k) var[k] += (a.x[i][k] - m[k]) * (a.x[i][k] - m[k]) / (c.n - 1) / seeds;
        for (int k = 2; k < 12; ++k) var[k] += a.P[k - 2][k - 2] / seeds;
        info_sum += o.info / seeds;
        assert_true(o.spread_fi[0] == sqrt(a.P_fi[0][0]) && o.spread_fi[1] == sqrt(a.P_fi[1][1]));
    }
    const rb_geo_t g = rb_geo(lat, h, vn, ve);
    rb_afilt(&g, A);
    const double qc[12] = {c.q_pos * c.q_pos, c.q_pos * c.q_pos, c.q_vel * c.q_vel, c.q_vel * c.q_vel,
                           c.q_acc * c.q_acc, c.q_acc * c.q_acc, c.q_acc * c.q_acc,
                           c.q_jerk * c.q_jerk, c.q_jerk * c.q_jerk, c.q_jerk * c.q_jerk,
                           c.q_bias * c.q_bias, c.q_bias * c.q_bias};
    const double s0[12] = {c.sigma0_pos, c.sigma0_pos, c.sigma0_vel, c.sigma0_vel, c.sigma0_acc, c.sigma0_acc,
                           c.sigma0_acc, c.sigma0_jerk, c.sigma0_jerk, c.sigma0_jerk, c.sigma0_bias, c.sigma0_bias};
    memset(P, 0, sizeof P);
    for (int k = 0; k < 12; ++k) P[k][k] = s0[k] * s0[k];
    rb_lyap(A, qc, P, T, 0.05);
    double worst = 0;
    printf("RBPF spread after %.0f s (mixture / Lyapunov variance):", T);
    for (int k = 0; k < 12; ++k) {
        printf(" %.3f", var[k] / P[k][k]);
        worst = fmax(worst, fabs(var[k] / P[k][k] - 1));
    }
    printf("\n");
    /* the free-inertial covariance the filter carries (pf.h P_fi, F P F^T + Q per shot) against
     * the Lyapunov equation integrated by RK4, and the info of a cloud that measured nothing */
    double worst_fi = 0;
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j)
            if (P[i][i] > 0 && P[j][j] > 0)
                worst_fi = fmax(worst_fi, fabs(a.P_fi[i][j] - P[i][j]) / sqrt(P[i][i] * P[j][j]));
    printf("free-inertial covariance against Lyapunov: %.2e (relative); info without measurements, mean of %d "
           "seeds: %+.3f\n", worst_fi, seeds, info_sum);
    /* sampling error of a variance from 4000 draws: 2.2 % (less where P carries it) */
    assert_true(worst < 0.08);
    assert_true(worst_fi < 1e-6);
    assert_true(fabs(info_sum) < 0.05); /* 8 seeds of 500: ~2 % sampling error of the variance sum */
}

/* RBPF input and configuration checks: state untouched on bad input. */
static void test_rb_bad_input(void **state)
{
    (void)state;
    static gg_pf_t a, b;
    gg_pf_config_t c = rb_cfg();
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    memcpy(&b, &a, sizeof a);
    gg_pf_output_t o;
    gg_pf_input_t nan_v = {LAT0, LON0, H0, 0, 0, 0, NAN, 0};
    gg_pf_input_t fast = {LAT0, LON0, H0, 0, 0, 0, 0, 1500.0};
    assert_int_equal(gg_pf_step(&a, &nan_v, &o), GG_ERR_NONFINITE);
    assert_int_equal(gg_pf_step(&a, &fast, &o), GG_ERR_RANGE);
    assert_int_equal(memcmp(&a, &b, sizeof a), 0);
    c.q_vel = 0; /* the position prediction covariance would be singular */
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    c = rb_cfg(); c.sigma0_jerk = -1;
    assert_int_equal(gg_pf_init(&a, &c), GG_ERR_CONFIG);
    static double F[12][12], Q[12][12], T[12][12];
    c = rb_cfg();
    assert_int_equal(gg_pf_rb_model(&c, 1.6, H0, 0, 0, F, Q, T), GG_ERR_RANGE);
    assert_int_equal(gg_pf_rb_model(&c, NAN, H0, 0, 0, F, Q, T), GG_ERR_NONFINITE);
}

/* The split shot (begin / chunk / end) against gg_pf_step: 60 shots with failed shots and
 * resampling, chunks of 1..97 particles, every model: outputs and particle states bit-identical;
 * out-of-order calls refused with GG_ERR_SEQUENCE. */
static void test_chunked_step(void **state)
{
    (void)state;
    static gg_pf_t a, b;
    const int models[3] = {GG_PF_MODEL_RW, GG_PF_MODEL_INS, GG_PF_MODEL_RBPF};
    for (int mi = 0; mi < 3; ++mi) {
        gg_pf_config_t c = (models[mi] == GG_PF_MODEL_RBPF) ? rb_cfg() : base_cfg();
        c.model = models[mi]; c.sigma = 0.004; c.reg_bw = 0.8; c.ess_frac = 0.5;
        if (models[mi] != GG_PF_MODEL_RBPF) { c.q_pos = 0.5; c.q_vel = 2e-3; c.q_acc = 2e-5; c.sigma0_acc = 3e-4; }
        assert_int_equal(gg_pf_init(&a, &c), GG_OK);
        assert_int_equal(gg_pf_init(&b, &c), GG_OK);
        int resampled = 0, chunks = 0, end_splits = 0, resampled_split = 0;
        for (int k = 0; k < 60; ++k) {
            gg_pf_input_t in = {LAT0, LON0, H0, (k % 7) != 3, 0.5 - 0.25 * cos(0.7 * k), 0.5 - 0.25 * cos(0.7 * k + 1.16),
                                -90.0, 30.0};
            gg_pf_output_t oa, ob;
            memset(&oa, 0, sizeof oa); memset(&ob, 0, sizeof ob);
            assert_int_equal(gg_pf_step(&a, &in, &oa), GG_OK);
            assert_int_equal(gg_pf_step_begin(&b, &in), GG_OK);
            assert_int_equal(gg_pf_step_begin(&b, &in), GG_ERR_SEQUENCE); /* shot already open */
            int done = 0, m = 1 + (k * 37) % 97;
            assert_int_equal(gg_pf_step_end(&b, &ob), GG_ERR_SEQUENCE);   /* particles left */
            while (!done) {
                assert_int_equal(gg_pf_step_chunk(&b, m, &done), GG_OK);
                ++chunks;
            }
            if ((k % 2) == 0) {
                assert_int_equal(gg_pf_step_end(&b, &ob), GG_OK);
            } else { /* the end split too: 1..211 particle passes a call */
                const int me = 1 + (k * 53) % 211;
                int edone = 0, calls = 0;
                assert_int_equal(gg_pf_step_end_chunk(&b, 0, &ob, &edone), GG_ERR_RANGE);
                while (!edone) {
                    assert_int_equal(gg_pf_step_end_chunk(&b, me, &ob, &edone), GG_OK);
                    ++calls;
                }
                assert_true(calls >= (2 * c.n) / me); /* at least the normalisation and the mean */
                ++end_splits;
            }
            assert_int_equal(memcmp(&oa, &ob, sizeof oa), 0);
            resampled += (oa.health & GG_PF_H_RESAMPLED) != 0;
            resampled_split += ((k % 2) != 0) && ((oa.health & GG_PF_H_RESAMPLED) != 0);
        }
        assert_int_equal(memcmp(a.x, b.x, sizeof a.x), 0);
        assert_int_equal(memcmp(a.w, b.w, sizeof a.w), 0);
        assert_int_equal(memcmp(&a.rng, &b.rng, sizeof a.rng), 0);
        printf("chunked step, model %d: 60 shots in %d chunks (%d ends split), %d resamplings (%d in a split end), bit-identical\n",
               models[mi], chunks, end_splits, resampled, resampled_split);
        assert_true(resampled_split > 0);
        int done = 0;
        gg_pf_output_t o;
        assert_int_equal(gg_pf_step_chunk(&b, 10, &done), GG_ERR_SEQUENCE); /* no shot open */
        assert_int_equal(gg_pf_step_end(&b, &o), GG_ERR_SEQUENCE);
        assert_int_equal(gg_pf_step_end_chunk(&b, 10, &o, &done), GG_ERR_SEQUENCE);
        gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.5, 0.5, 0, 0};
        assert_int_equal(gg_pf_step_begin(&b, &in), GG_OK);
        assert_int_equal(gg_pf_step_chunk(&b, 0, &done), GG_ERR_RANGE);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
            cmocka_unit_test(test_rng),
        cmocka_unit_test(test_ellipse_distance),
        cmocka_unit_test(test_posterior_1d),
        cmocka_unit_test(test_determinism_and_skip),
        cmocka_unit_test(test_degenerate_and_bad_input),
        cmocka_unit_test(test_resampling_counts),
        cmocka_unit_test(test_gmap_adapter),
        cmocka_unit_test(test_ins_model_propagation),
        cmocka_unit_test(test_ins_model_spread),
        cmocka_unit_test(test_regularised_resampling),
        cmocka_unit_test(test_rb_model),
        cmocka_unit_test(test_rb_spread),
        cmocka_unit_test(test_rb_bad_input),
        cmocka_unit_test(test_chunked_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
