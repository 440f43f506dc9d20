/* Gravity dead reckoning against the closed-form point-mass field along the
 * analytic north flight: exact gradients at each step, exact displacements,
 * and the final G compared with the field itself at the final position. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/gravdr.h"

static const t_flight_t kFlight = {300.0L, 0.0L, 0.0L};

/* Run the integrator over [0, T] with n steps; return |G - G_true(r(T))|. */
static long double dr_error(long double T, long n, int trapezoid_only)
{
    gg_gravdr_config_t cfg;
    gg_gravdr_t st;
    long double r[3], v[3], a[3], g[3], gam[3][3];
    t_flight(&kFlight, 0.0L, r, v, a);
    t_point_mass_g(r, g);
    t_point_mass_gamma(r, gam);
    memcpy(cfg.g0, g, sizeof g);
    memcpy(cfg.gamma0, gam, sizeof gam);
    cfg.trapezoid_only = trapezoid_only;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_OK);
    long double r_prev[3];
    memcpy(r_prev, r, sizeof r);
    for (long k = 1; k <= n; ++k) {
        const long double t = T * (long double)k / (long double)n;
        long double dr[3];
        t_flight(&kFlight, t, r, v, a);
        for (int j = 0; j < 3; ++j) dr[j] = r[j] - r_prev[j];
        memcpy(r_prev, r, sizeof r);
        t_point_mass_gamma(r, gam);
        assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])gam, dr), GG_OK);
    }
    gg_real_t gd[3];
    assert_int_equal(gg_gravdr_get(&st, gd), GG_OK);
    t_point_mass_g(r, g);
    long double gdl[3] = {gd[0], gd[1], gd[2]};
    return norm3l(gdl, g);
}

/* Bound: 1 h at 100 Hz, V = 300 m/s, |G - G_true| < 1e-13 m/s^2. */
static void test_flight_1h_100hz(void **state)
{
    (void)state;
    const long double e = dr_error(3600.0L, 360000, 0);
    const long double e_trap = dr_error(3600.0L, 360000, 1);
    printf("1 h, 100 Hz: |G - G_true| = %.3Lg m/s^2 (corrected), %.3Lg m/s^2 (trapezoid only)\n",
           e, e_trap);
    assert_true(e < 1e-13L);
}

/* The trapezoid's error is the h^3/12 (Gamma'' v - Gamma' v') term: second
 * order, so halving the step quarters it; the corrected scheme's local error
 * is O(h^4) (its finite differences are centred half a step early), so it is
 * third order globally: halving the step divides the error by 8. Coarse steps make the
 * truncation error dominate round-off. */
static void test_convergence_order(void **state)
{
    (void)state;
    const long double T = 3600.0L;
    const long double t1 = dr_error(T, 360, 1), t2 = dr_error(T, 720, 1);
    const long double c1 = dr_error(T, 90, 0), c2 = dr_error(T, 180, 0);
    printf("trapezoid: h=10 s %.3Lg, h=5 s %.3Lg, ratio %.2Lf\n", t1, t2, t1 / t2);
    printf("corrected: h=40 s %.3Lg, h=20 s %.3Lg, ratio %.2Lf\n", c1, c2, c1 / c2);
    assert_true(t1 / t2 > 3.8L && t1 / t2 < 4.2L);
    assert_true(c1 / c2 > 7.5L && c1 / c2 < 8.5L);
}

/* Uniform gradient: G(r) = G0 + M (r - r0) exactly, for any path. */
static void test_linear_field_exact(void **state)
{
    (void)state;
    gg_gravdr_config_t cfg = {{-1.0L, 0.0L, -9.8L},
                              {{-3e-6L, 0, 1e-6L}, {0, 0, 0}, {1e-6L, 0, 3e-6L}}, 0};
    gg_gravdr_t st;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_OK);
    long double pos[3] = {0, 0, 0};
    for (int k = 0; k < 1000; ++k) {
        const gg_real_t dr[3] = {sinl(0.01L * k) * 3.0L, 0.0L, cosl(0.003L * k) * 2.0L};
        for (int j = 0; j < 3; ++j) pos[j] += dr[j];
        assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])cfg.gamma0, dr), GG_OK);
    }
    gg_real_t g[3];
    assert_int_equal(gg_gravdr_get(&st, g), GG_OK);
    for (int j = 0; j < 3; j += 2) {
        long double want = cfg.g0[j];
        for (int k = 0; k < 3; ++k) want += cfg.gamma0[j][k] * pos[k];
        assert_near(g[j], want, 1e-15L);
    }
}

static void test_rejects_bad_input_state_untouched(void **state)
{
    (void)state;
    gg_gravdr_config_t cfg = {{0, 0, -9.8L}, {{0}}, 0};
    gg_gravdr_t st;
    cfg.g0[0] = NAN;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.g0[0] = 0.0L;
    cfg.trapezoid_only = 7;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.trapezoid_only = 0;
    assert_int_equal(gg_gravdr_init(&st, &cfg), GG_OK);
    const gg_real_t dr_ok[3] = {1, 0, 1};
    assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])cfg.gamma0, dr_ok), GG_OK);
    const gg_gravdr_t before = st;
    gg_real_t gam[3][3] = {{0}};
    gam[2][2] = INFINITY;
    assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])gam, dr_ok), GG_ERR_NONFINITE);
    assert_memory_equal(&st, &before, sizeof st);
    const gg_real_t dr_bad[3] = {0, 0, NAN};
    assert_int_equal(gg_gravdr_step(&st, (const gg_real_t(*)[3])cfg.gamma0, dr_bad),
                     GG_ERR_NONFINITE);
    assert_memory_equal(&st, &before, sizeof st);
    assert_int_equal(gg_gravdr_step(NULL, (const gg_real_t(*)[3])cfg.gamma0, dr_ok), GG_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flight_1h_100hz),
        cmocka_unit_test(test_convergence_order),
        cmocka_unit_test(test_linear_field_exact),
        cmocka_unit_test(test_rejects_bad_input_state_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
