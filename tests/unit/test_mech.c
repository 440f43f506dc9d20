/* Mechanization against the analytic north flight: exact specific force
 * f = a - G(r_true) at each step, and exact gravity G(r) of the point-mass
 * field evaluated at the mechanization's own end-of-step position (so the
 * loop carries the vertical instability of a free INS). */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/mech.h"

static const t_flight_t kFlight = {300.0L, 0.0L, 0.0L};

/* Fly [0, T] in n steps; return |r - r_true(T)| (m), and velocity error in *ev. */
static long double mech_error(long double T, long n, long double *ev)
{
    gg_mech_config_t cfg;
    gg_mech_t st;
    long double r[3], v[3], a[3], g[3];
    t_flight(&kFlight, 0.0L, r, v, a);
    for (int j = 0; j < 3; ++j) {
        cfg.r0[j] = r[j];
        cfg.v0[j] = v[j];
        cfg.a0[j] = a[j];
    }
    cfg.dt_s = T / (long double)n;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_OK);
    for (long k = 1; k <= n; ++k) {
        const long double t = T * (long double)k / (long double)n;
        gg_real_t dr[3], rc[3], vc[3], f[3];
        gg_acc_t gacc[3];
        assert_int_equal(gg_mech_step_position(&st, dr), GG_OK);
        assert_int_equal(gg_mech_get(&st, rc, vc), GG_OK);
        long double rcl[3] = {rc[0], rc[1], rc[2]};
        t_point_mass_g(rcl, g); /* gravity at the computed position */
        t_flight(&kFlight, t, r, v, a);
        long double gt[3];
        t_point_mass_g(r, gt);
        for (int j = 0; j < 3; ++j) {
            f[j] = a[j] - gt[j]; /* specific force at the true position */
            gg_acc_set(&gacc[j], g[j]);
        }
        assert_int_equal(gg_mech_step_velocity(&st, f, gacc), GG_OK);
    }
    gg_real_t rc[3], vc[3];
    assert_int_equal(gg_mech_get(&st, rc, vc), GG_OK);
    long double rcl[3] = {rc[0], rc[1], rc[2]}, vcl[3] = {vc[0], vc[1], vc[2]};
    if (ev != NULL) *ev = norm3l(vcl, v);
    return norm3l(rcl, r);
}

/* Bound: 1 h at 100 Hz ends within 0.1 mm of the analytic position. */
static void test_flight_1h_100hz(void **state)
{
    (void)state;
    long double ev;
    const long double e = mech_error(3600.0L, 360000, &ev);
    printf("1 h, 100 Hz: |r - r_true| = %.3Lg m, |v - v_true| = %.3Lg m/s\n", e, ev);
    assert_true(e < 1e-4L);
}

/* Third order (Verlet with end corrections, mech.h): halving the step
 * divides the error by 8 (coarse steps, so the truncation error dominates
 * round-off). */
static void test_convergence_order(void **state)
{
    (void)state;
    const long double e1 = mech_error(3600.0L, 180, NULL);
    const long double e2 = mech_error(3600.0L, 360, NULL);
    const long double e3 = mech_error(3600.0L, 720, NULL);
    printf("h = 20, 10, 5 s: %.4Lg %.4Lg %.4Lg m; ratios %.3Lf %.3Lf\n", e1, e2, e3, e1 / e2,
           e2 / e3);
    assert_true(e1 / e2 > 7.5L && e1 / e2 < 8.5L);
    assert_true(e2 / e3 > 7.5L && e2 / e3 < 8.5L);
}

static void test_config_and_input_errors(void **state)
{
    (void)state;
    gg_mech_config_t cfg = {0.01L, {6378137.0L, 0, 0}, {0, 0, 300.0L}, {0, 0, 0}};
    gg_mech_t st;
    cfg.dt_s = 0.0L;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.dt_s = -0.01L;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.dt_s = NAN;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.dt_s = 0.01L;
    cfg.v0[1] = INFINITY;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_ERR_CONFIG);
    cfg.v0[1] = 0.0L;
    assert_int_equal(gg_mech_init(&st, &cfg), GG_OK);

    /* a NaN at the velocity half-step rolls the position back */
    const gg_mech_t before = st;
    gg_real_t dr[3];
    assert_int_equal(gg_mech_step_position(&st, dr), GG_OK);
    const gg_real_t f_bad[3] = {0, 0, NAN};
    gg_acc_t g[3];
    for (int j = 0; j < 3; ++j) gg_acc_set(&g[j], 0.0L);
    assert_int_equal(gg_mech_step_velocity(&st, f_bad, g), GG_ERR_NONFINITE);
    gg_real_t r0[3], v0[3], r1[3], v1[3];
    assert_int_equal(gg_mech_get(&before, r0, v0), GG_OK);
    assert_int_equal(gg_mech_get(&st, r1, v1), GG_OK);
    for (int j = 0; j < 3; ++j) {
        /* compare values: long double carries padding bytes */
        assert_true(r0[j] == r1[j] && v0[j] == v1[j]);
    }
    assert_int_equal(st.pending, 0);
    /* velocity half-step without a position half-step is refused */
    const gg_real_t f_ok[3] = {0, 0, 9.8L};
    assert_int_equal(gg_mech_step_velocity(&st, f_ok, g), GG_ERR_NOT_INIT);
    assert_int_equal(gg_mech_step_position(NULL, dr), GG_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flight_1h_100hz),
        cmocka_unit_test(test_convergence_order),
        cmocka_unit_test(test_config_and_input_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
