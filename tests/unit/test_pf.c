/* Particle filter (pf.h) against independent truth: its math kernels against
 * libm; the generator's sample statistics and a Kolmogorov-Smirnov test against
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

static double rel(double a, double b) { return fabs(a - b) / fmax(fabs(b), 1e-300); }

static void test_math(void **state)
{
    (void)state;
    double worst_e = 0, worst_l = 0, worst_s = 0;
    for (int i = 0; i <= 20000; ++i) {
        const double x = -740.0 + 1449.0 * i / 20000.0, y = 0;
        double e = 0;
        assert_int_equal(gg_pf_exp(x, &e), GG_OK);
        if (x > -700) worst_e = fmax(worst_e, rel(e, exp(x)));
        const double lx = exp(-700.0 + 1400.0 * i / 20000.0) * (1.0 + 0.37 * (i % 7));
        double l = 0;
        assert_int_equal(gg_pf_log(lx, &l), GG_OK);
        worst_l = fmax(worst_l, fabs(l - log(lx)) / fmax(1.0, fabs(log(lx))));
        const double a = -1000.0 + 2000.0 * i / 20000.0 + 1e-3 * i;
        double s = 0, c = 0;
        assert_int_equal(gg_pf_sincos(a, &s, &c), GG_OK);
        worst_s = fmax(worst_s, fmax(fabs(s - sin(a)), fabs(c - cos(a))));
        (void)y;
    }
    printf("exp rel %.2e, log %.2e, sincos abs %.2e\n", worst_e, worst_l, worst_s);
    assert_true(worst_e < 1e-14);
    assert_true(worst_l < 1e-15);
    assert_true(worst_s < 1e-13); /* |x| up to 1e3: reduction error ~ |x| eps */
    double y = 0, s = 0, c = 0;
    assert_int_equal(gg_pf_log(0.0, &y), GG_ERR_RANGE);
    assert_int_equal(gg_pf_log(NAN, &y), GG_ERR_NONFINITE);
    assert_int_equal(gg_pf_exp(710.0, &y), GG_ERR_RANGE);
    assert_int_equal(gg_pf_exp(-800.0, &y), GG_OK);
    assert_true(y == 0.0);
    assert_int_equal(gg_pf_sincos(INFINITY, &s, &c), GG_ERR_NONFINITE);
    assert_int_equal(gg_pf_log(4.9e-324, &y), GG_OK); /* subnormal */
    assert_true(fabs(y - log(4.9e-324)) < 1e-12);
}

static int cmp_d(const void *a, const void *b)
{
    const double x = *(const double *)a, z = *(const double *)b;
    return (x > z) - (x < z);
}

static void test_rng(void **state)
{
    (void)state;
    static double z[100000];
    gg_pf_rng_t r;
    const int n = 100000;
    assert_int_equal(gg_pf_rng_seed(&r, 42), GG_OK);
    double mu = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
        double u = 0;
        assert_int_equal(gg_pf_rng_uniform(&r, &u), GG_OK);
        assert_true(u >= 0.0 && u < 1.0);
        mu += u; m2 += u * u;
    }
    mu /= n; m2 /= n;
    assert_near(mu, 0.5, 5 * sqrt(1.0 / 12 / n));
    assert_near(m2 - mu * mu, 1.0 / 12, 5 * sqrt(1.0 / 180 / n));
    double m1 = 0, v = 0, k4 = 0;
    for (int i = 0; i < n; ++i) {
        assert_int_equal(gg_pf_rng_normal(&r, &z[i]), GG_OK);
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
    gg_pf_rng_t r;
    gg_pf_rng_seed(&r, 9);
    double worst = 0, worst_near = 0;
    for (int k = 0; k < 3000; ++k) {
        double u1 = 0, u2 = 0, u3 = 0, z = 0;
        gg_pf_rng_uniform(&r, &u1); gg_pf_rng_uniform(&r, &u2); gg_pf_rng_uniform(&r, &u3);
        gg_pf_rng_normal(&r, &z);
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
    gg_pf_rng_t r;
    gg_pf_rng_seed(&r, 77);
    for (int k = 0; k < NS; ++k) {
        double u = 0, z0 = 0, z1 = 0;
        gg_pf_rng_uniform(&r, &u); gg_pf_rng_normal(&r, &z0); gg_pf_rng_normal(&r, &z1);
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
            gg_pf_input_t in = {LAT0, LON0, H0, 1, s0[k], s1[k]};
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
        gg_pf_input_t in = {LAT0, LON0, H0, (k % 5) != 0, 0.5 + 0.25 * cos(k), 0.5 - 0.25 * cos(k + 1.16)};
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
    double before[GG_PF_MAX][4];
    memcpy(before, a.x, sizeof before);
    gg_pf_input_t fail = {LAT0, LON0, H0, 0, NAN, NAN}; /* the pair is not read */
    assert_int_equal(gg_pf_step(&a, &fail, &oa), GG_OK);
    assert_true(oa.health & GG_PF_H_SKIPPED);
    assert_near(oa.ess, 500.0, 1e-9);
    for (int i = 0; i < c.n; ++i)
        for (int k = 0; k < 4; ++k) assert_true(before[i][k] == a.x[i][k]); /* +0 == -0 */
}

static void test_degenerate_and_bad_input(void **state)
{
    (void)state;
    static gg_pf_t a, snap;
    gg_pf_config_t c = base_cfg();
    c.map.gzz = map_off;
    gg_pf_output_t o;
    assert_int_equal(gg_pf_init(&a, &c), GG_OK);
    gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.6, 0.4};
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
    gg_pf_input_t far = {LAT0, LON0, H0, 1, 3.0, -3.0};
    assert_int_equal(gg_pf_step(&a, &far, &o), GG_OK);
    assert_true(isfinite(o.corr[0]) && isfinite(o.ess) && o.ess >= 1.0);
    /* bad input: state untouched */
    memcpy(&snap, &a, sizeof a);
    gg_pf_input_t bad = {LAT0, LON0, H0, 1, NAN, 0.5};
    assert_int_equal(gg_pf_step(&a, &bad, &o), GG_ERR_NONFINITE);
    gg_pf_input_t bad2 = {2.0, LON0, H0, 1, 0.5, 0.5};
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
    gg_pf_input_t in = {LAT0, LON0, H0, 1, 0.5 - 0.25 * cos(0.3), 0.5 - 0.25 * cos(0.3 + 1.2)};
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_math),
        cmocka_unit_test(test_rng),
        cmocka_unit_test(test_ellipse_distance),
        cmocka_unit_test(test_posterior_1d),
        cmocka_unit_test(test_determinism_and_skip),
        cmocka_unit_test(test_degenerate_and_bad_input),
        cmocka_unit_test(test_resampling_counts),
        cmocka_unit_test(test_gmap_adapter),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
