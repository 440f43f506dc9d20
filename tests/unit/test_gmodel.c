/* Onboard zonal gravitation model against (a) the closed-form point mass and
 * (b) central finite differences of an independently written potential
 * V = GM/r [1 - J2 (a/r)^2 P2(u) - J4 (a/r)^4 P4(u)] with P2, P4 spelled out. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/gmodel.h"

static const long double kJ2 = 1.08262982131e-3L, kJ4 = -2.37091120053e-6L;

static long double potential(const long double r[3])
{
    const long double rn = sqrtl(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const long double u = r[2] / rn, q = T_RE / rn;
    const long double p2 = 0.5L * (3.0L * u * u - 1.0L);
    const long double p4 = (35.0L * u * u * u * u - 30.0L * u * u + 3.0L) / 8.0L;
    return T_GM / rn * (1.0L - kJ2 * q * q * p2 - kJ4 * q * q * q * q * p4);
}

static void test_point_mass_when_no_zonals(void **state)
{
    (void)state;
    static gg_gmodel_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.gm = T_GM;
    cfg.a_m = T_RE;
    gg_gmodel_t m;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    const long double pts[3][3] = {{T_RE, 0, 0}, {0, 0, T_RE + 1e4L}, {3e6L, 1e6L, -5e6L}};
    for (int i = 0; i < 3; ++i) {
        gg_real_t g[3];
        long double gt[3];
        assert_int_equal(gg_gmodel_eval(&m, &cfg, pts[i], g, NULL), GG_OK);
        t_point_mass_g(pts[i], gt);
        for (int j = 0; j < 3; ++j) assert_near(g[j], gt[j], 1e-15L);
    }
}

/* G = grad V by 4th-order central differences (step 100 m): the difference
 * error is ~h^4 V(5)/30 ~ 1e-18 m/s^2, round-off ~1e-13; 1e-12 m/s^2 checks every
 * term and sign, including at the pole (no singularity). */
static void test_j2_j4_against_potential_gradient(void **state)
{
    (void)state;
    static gg_gmodel_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.gm = T_GM;
    cfg.a_m = T_RE;
    cfg.j[2] = kJ2;
    cfg.j[4] = kJ4;
    gg_gmodel_t m;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    const long double pts[5][3] = {{T_RE, 0, 0},
                                   {0, 0, 6356752.0L},
                                   {4e6L, 2e6L, 4.5e6L},
                                   {-3e6L, 0, -5.6e6L},
                                   {1.0L, 0, 7e6L}};
    const long double h = 100.0L;
    long double worst = 0;
    for (int i = 0; i < 5; ++i) {
        gg_real_t g[3];
        assert_int_equal(gg_gmodel_eval(&m, &cfg, pts[i], g, NULL), GG_OK);
        for (int j = 0; j < 3; ++j) {
            long double p[4][3];
            const long double k[4] = {-2, -1, 1, 2};
            for (int s = 0; s < 4; ++s) {
                memcpy(p[s], pts[i], sizeof p[s]);
                p[s][j] += k[s] * h;
            }
            const long double d = (potential(p[0]) - 8 * potential(p[1]) + 8 * potential(p[2]) -
                                   potential(p[3])) / (12 * h);
            const long double e = fabsl(g[j] - d);
            if (e > worst) worst = e;
        }
    }
    printf("worst |G - grad V| = %.3Lg m/s^2\n", worst);
    assert_true(worst < 1e-12L);
}

static void test_bad_config_and_input(void **state)
{
    (void)state;
    static gg_gmodel_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.gm = T_GM;
    cfg.a_m = T_RE;
    gg_gmodel_t m;
    cfg.gm = 0;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    cfg.gm = T_GM;
    cfg.j[1] = 1e-3L;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    cfg.j[1] = 0;
    cfg.j[3] = NAN;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    cfg.j[3] = 0;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    gg_real_t g[3] = {1, 2, 3};
    const gg_real_t centre[3] = {0, 0, 0}, bad[3] = {NAN, 0, 0};
    assert_int_equal(gg_gmodel_eval(&m, &cfg, centre, g, NULL), GG_ERR_RANGE);
    assert_int_equal(gg_gmodel_eval(&m, &cfg, bad, g, NULL), GG_ERR_NONFINITE);
    assert_true(g[0] == 1 && g[1] == 2 && g[2] == 3);
}

/* Programmed point masses against the closed form, summed with the zonal
 * part (each term checked by switching the others off). */
static void test_programmed_point_masses(void **state)
{
    (void)state;
    static gg_gmodel_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.gm = T_GM;
    cfg.a_m = T_RE;
    cfg.n_pm = 2;
    const long double p0[3] = {T_RE - 3000.0L, 0, 1000.0L}, p1[3] = {T_RE - 5000.0L, 0, -8000.0L};
    memcpy(cfg.pm_pos[0], p0, sizeof p0);
    memcpy(cfg.pm_pos[1], p1, sizeof p1);
    cfg.pm_gm[0] = 6.674e-11L * 1e12L;  /* 1e12 kg excess */
    cfg.pm_gm[1] = -6.674e-11L * 5e11L; /* deficit */
    static gg_gmodel_t m;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    const long double r[3] = {T_RE + 2000.0L, 0, 500.0L};
    gg_real_t g[3];
    uint32_t fl = 99;
    assert_int_equal(gg_gmodel_eval(&m, &cfg, r, g, &fl), GG_OK);
    assert_int_equal(fl, 0);
    long double want[3];
    t_point_mass_g(r, want);
    const long double *ps[2] = {p0, p1};
    for (int n = 0; n < 2; ++n) {
        long double d[3], d2 = 0;
        for (int j = 0; j < 3; ++j) { d[j] = r[j] - ps[n][j]; d2 += d[j] * d[j]; }
        for (int j = 0; j < 3; ++j) want[j] -= cfg.pm_gm[n] * d[j] / (d2 * sqrtl(d2));
    }
    for (int j = 0; j < 3; ++j) assert_near(g[j], want[j], 1e-15L);
    /* the anomaly is the size of a real one: ~1e-5 m/s^2 */
    long double g0[3];
    t_point_mass_g(r, g0);
    assert_true(fabsl(g[0] - g0[0]) > 1e-6L && fabsl(g[0] - g0[0]) < 1e-3L);
    /* at a programmed mass: refused */
    assert_int_equal(gg_gmodel_eval(&m, &cfg, p0, g, NULL), GG_ERR_RANGE);
}

/* Polar anomaly grid: a disturbance bilinear in (theta, rho) with
 * (tangential, radial) components is reproduced exactly; theta and the
 * rotation into x-z computed here independently with atan2l/cosl/sinl.
 * Outside (in angle, in radius, behind the Earth's centre) contributes
 * nothing, flagged. */
static void test_programmed_grid(void **state)
{
    (void)state;
    static gg_gmodel_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    cfg.gm = T_GM;
    cfg.a_m = T_RE;
    gg_gmodel_grid_t *gr = &cfg.grid;
    const long double lat0 = 0.6L; /* e0 at 34.4 deg */
    gr->n_th = 40;
    gr->n_rho = 3;
    gr->c0 = cosl(lat0);
    gr->s0 = sinl(lat0);
    gr->th0_rad = -0.01L;
    gr->dth_rad = 1e-3L;
    gr->rho0_m = T_RE + 2000.0L;
    gr->drho_m = 1000.0L;
    /* dG_t = A + B i + C k + D i k, dG_r = E + F k + H i k (i, k: node indices) */
    for (int k = 0; k < gr->n_rho; ++k)
        for (int i = 0; i < gr->n_th; ++i) {
            gr->dg[k * gr->n_th + i][0] = 1e-5 + 2e-7 * i - 3e-7 * k + 1e-8 * i * k;
            gr->dg[k * gr->n_th + i][1] = -2e-5 + 1e-7 * k + 4e-9 * i * k;
        }
    static gg_gmodel_t m;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    /* (theta from e0 in rad, height above rho0 in m) */
    const long double pts[5][2] = {{0.0123L, 700.0L}, {-0.0099999L, 1e-6L}, {0.0289999L, 1999.999L},
                                   {0.0L, 1500.0L}, {0.02L, 1999.0L}};
    long double worst = 0;
    for (int n = 0; n < 5; ++n) {
        const long double th = lat0 + pts[n][0], rho = gr->rho0_m + pts[n][1];
        const long double r[3] = {rho * cosl(th), 0, rho * sinl(th)};
        gg_real_t g[3];
        long double g0[3];
        uint32_t fl = 99;
        assert_int_equal(gg_gmodel_eval(&m, &cfg, r, g, &fl), GG_OK);
        assert_int_equal(fl, 0);
        t_point_mass_g(r, g0);
        const long double thr = atan2l(r[2], r[0]) - lat0; /* independent angle */
        const long double u = (thr + 0.01L) / 1e-3L, w = (sqrtl(r[0] * r[0] + r[2] * r[2]) - gr->rho0_m) / 1000.0L;
        const long double dgt = 1e-5L + 2e-7L * u - 3e-7L * w + 1e-8L * u * w;
        const long double dgr = -2e-5L + 1e-7L * w + 4e-9L * u * w;
        const long double want_x = dgr * cosl(th) - dgt * sinl(th);
        const long double want_z = dgr * sinl(th) + dgt * cosl(th);
        const long double ex = fabsl((g[0] - g0[0]) - want_x), ez = fabsl((g[2] - g0[2]) - want_z);
        if (ex > worst) worst = ex;
        if (ez > worst) worst = ez;
        assert_true(g[1] == (gg_real_t)g0[1]);
    }
    printf("polar grid: worst error against the bilinear field %.3Lg m/s^2\n", worst);
    assert_true(worst < 1e-17L);
    /* outside: before the first node, above the last radius, behind the centre */
    const long double outs[3][3] = {
        {(T_RE + 3000.0L) * cosl(lat0 - 0.0101L), 0, (T_RE + 3000.0L) * sinl(lat0 - 0.0101L)},
        {(T_RE + 4001.0L) * cosl(lat0), 0, (T_RE + 4001.0L) * sinl(lat0)},
        {-(T_RE + 3000.0L) * cosl(lat0), 0, -(T_RE + 3000.0L) * sinl(lat0)}};
    for (int n = 0; n < 3; ++n) {
        gg_real_t g[3];
        long double g0[3];
        uint32_t fl = 0;
        assert_int_equal(gg_gmodel_eval(&m, &cfg, outs[n], g, &fl), GG_OK);
        assert_int_equal(fl, GG_GMODEL_OUTSIDE_GRID);
        t_point_mass_g(outs[n], g0);
        for (int j = 0; j < 3; ++j) assert_near(g[j], g0[j], 1e-15L);
    }
    /* bad grids */
    gr->n_rho = 1;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    gr->n_rho = 3;
    gr->dg[3][1] = NAN;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    gr->dg[3][1] = 0;
    gr->dg[5][0] = 2.0;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_RANGE);
    gr->dg[5][0] = 0;
    gr->n_th = 600; /* 600 x 3 > GG_GMODEL_GRID_MAX */
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    gr->n_th = 40;
    gr->c0 = 1.0L; /* |e0| != 1 */
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    gr->c0 = cosl(lat0);
    gr->dth_rad = 0.1L; /* the grid would reach beyond 45 deg */
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_RANGE);
    gr->dth_rad = 1e-3L;
    gr->drho_m = -1.0L;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_ERR_CONFIG);
    gr->drho_m = 1000.0L;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    /* eval before init / with NULL config */
    static gg_gmodel_t fresh;
    memset(&fresh, 0, sizeof fresh);
    const long double r[3] = {T_RE, 0, 0};
    gg_real_t g[3];
    assert_int_equal(gg_gmodel_eval(&fresh, &cfg, r, g, NULL), GG_ERR_NOT_INIT);
    assert_int_equal(gg_gmodel_eval(&m, NULL, r, g, NULL), GG_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_mass_when_no_zonals),
        cmocka_unit_test(test_j2_j4_against_potential_gradient),
        cmocka_unit_test(test_bad_config_and_input),
        cmocka_unit_test(test_programmed_point_masses),
        cmocka_unit_test(test_programmed_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
