/* Vertical channel module: gains from poles, sample validation, gate,
 * re-capture, coasting. (The closed-loop poles of the whole discrete loop
 * are checked in test_nav2d.) */
#include "test_common.h"
#include "ggins/frame.h"
#include "ggins/vchan.h"

static gg_vchan_config_t config(void)
{
    gg_vchan_config_t c = {{0.005L, 0.01L, 0.015L}, 1.5e-6L, 1000000, 500000, 10000000,
                           -500.0, 20000.0, 50.0, 3};
    return c;
}

/* Continuous-equivalent gains: k1, k2, k3 make
 * s^3 + k1 s^2 + (k2 - 2 w^2) s + k3 = (s+p1)(s+p2)(s+p3). */
static void test_continuous_gains_place_the_poles(void **state)
{
    (void)state;
    gg_vchan_config_t c = config();
    gg_vchan_t v;
    assert_int_equal(gg_vchan_init(&v, &c), GG_OK);
    const long double s_pts[] = {-0.01L, 0.5L, -2.0L, 3.0L};
    for (int i = 0; i < 4; ++i) {
        const long double s = s_pts[i];
        const long double lhs = s * s * s + v.k1 * s * s + (v.k2 - 2 * c.omega_s2) * s + v.k3;
        const long double rhs = (s + 0.005L) * (s + 0.01L) * (s + 0.015L);
        assert_near(lhs, rhs, 1e-15L * (1 + fabsl(rhs)));
    }
}

/* Discrete gains: with Phi = exp(A T) written in closed form here
 * (cosh/sinh of lambda T, lambda = sqrt(2 w^2)), the eigenvalues of
 * (I + K C) Phi are exp(-p_i T): det(z_i I - M) = 0. And for a short period
 * the gains tend to T (-k1, -k2, k3). */
static void check_discrete(long double period_s, int check_limit)
{
    gg_vchan_config_t c = config();
    c.period_us = (int64_t)(period_s * 1e6L + 0.5L);
    gg_vchan_t v;
    assert_int_equal(gg_vchan_init(&v, &c), GG_OK);
    const long double T = period_s, w = 2 * c.omega_s2, lam = sqrtl(w);
    const long double ch = coshl(lam * T), sh = sinhl(lam * T);
    const long double phi[3][3] = {{ch, sh / lam, -(ch - 1) / w},
                                   {lam * sh, ch, -sh / lam},
                                   {0, 0, 1}};
    long double m[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) m[i][j] = phi[i][j] + v.kd[i] * phi[0][j];
    for (int q = 0; q < 3; ++q) {
        const long double z = expl(-c.poles[q] * T);
        long double a[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) a[i][j] = (i == j ? z : 0) - m[i][j];
        const long double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                                a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                                a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        /* scale: the product of the distances between the z_i, ~(p T)^2 */
        assert_near(det, 0.0L, 1e-9L * powl(0.005L * T, 2));
    }
    if (check_limit) {
        assert_near(v.kd[0], -v.k1 * T, 0.02L * v.k1 * T);
        assert_near(v.kd[1], -v.k2 * T, 0.02L * v.k2 * T);
        assert_near(v.kd[2], v.k3 * T, 0.02L * v.k3 * T);
    }
}

static void test_discrete_gains_place_the_poles(void **state)
{
    (void)state;
    check_discrete(1.0L, 0);
    check_discrete(20.0L, 0);
    check_discrete(0.01L, 1);
}

static void test_config_rejected(void **state)
{
    (void)state;
    gg_vchan_t v;
    gg_vchan_config_t c = config();
    c.poles[1] = 0.0L;
    assert_int_equal(gg_vchan_init(&v, &c), GG_ERR_CONFIG);
    c = config();
    c.poles[2] = 1.5L; /* p T = 1.5 > 1 at 1 Hz */
    assert_int_equal(gg_vchan_init(&v, &c), GG_ERR_CONFIG);
    c = config();
    c.omega_s2 = -1.0L;
    assert_int_equal(gg_vchan_init(&v, &c), GG_ERR_CONFIG);
    c = config();
    c.alt_max_m = c.alt_min_m;
    assert_int_equal(gg_vchan_init(&v, &c), GG_ERR_CONFIG);
    c = config();
    c.gate_m = NAN;
    assert_int_equal(gg_vchan_init(&v, &c), GG_ERR_CONFIG);
    assert_int_equal(v.initialized, 0);
}

static gg_vchan_output_t step(gg_vchan_t *v, int64_t now, long double h_ins, double alt,
                              int64_t t_s, int32_t status)
{
    gg_vchan_sample_t s = {alt, t_s, status};
    gg_vchan_output_t o;
    assert_int_equal(gg_vchan_step(v, now, h_ins, &s, &o), GG_OK);
    return o;
}

static void test_validation_gate_recapture_coast(void **state)
{
    (void)state;
    gg_vchan_config_t c = config();
    gg_vchan_t v;
    assert_int_equal(gg_vchan_init(&v, &c), GG_OK);
    gg_vchan_output_t o;
    /* no sample yet: coasting */
    o = step(&v, 0, 100.0L, 0, 0, GG_SENSOR_ABSENT);
    assert_true((o.health & GG_VCHAN_COAST) != 0U);
    /* first sample starts the loop without correcting */
    o = step(&v, 1000000, 100.0L, 99.0, 1000000, GG_SENSOR_OK);
    assert_int_equal(o.accepted, 1);
    assert_true(o.dh_m == 0.0L && o.health == 0U);
    /* second: e = +1 m after one period -> dh = K0, dv = K1, a_c = K2, with
     * the signs of a loop that pulls a too-high INS down */
    o = step(&v, 2000000, 100.0L, 99.0, 2000000, GG_SENSOR_OK);
    assert_near(o.dh_m, v.kd[0], 1e-18L);
    assert_near(o.dv_mps, v.kd[1], 1e-18L);
    assert_near(o.a_c, v.kd[2], 1e-18L);
    assert_true(v.kd[0] < 0 && v.kd[1] < 0 && v.kd[2] > 0);
    const long double a_c = o.a_c;
    /* the same sample again: nothing */
    o = step(&v, 2010000, 100.0L, 99.0, 2000000, GG_SENSOR_OK);
    assert_true(o.accepted == 0 && o.dh_m == 0.0L && o.health == 0U);
    /* NaN, out of range, flagged bad: invalid, state held */
    o = step(&v, 3000000, 100.0L, NAN, 3000000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_INVALID) != 0U && o.a_c == a_c && o.dh_m == 0.0L);
    o = step(&v, 3100000, 100.0L, 1e6, 3100000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_INVALID) != 0U);
    o = step(&v, 3200000, 100.0L, 99.0, 3200000, GG_SENSOR_BAD);
    assert_true((o.health & GG_VCHAN_INVALID) != 0U);
    /* stale: sample 0.6 s old (max 0.5 s) */
    o = step(&v, 4000000, 100.0L, 99.0, 3400000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_STALE) != 0U && o.accepted == 0);
    /* outlier: 200 m off, gate 50 m: rejected twice, re-captured the third time */
    o = step(&v, 5000000, 100.0L, -100.0, 5000000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_OUTLIER) != 0U && o.accepted == 0 && o.a_c == a_c);
    o = step(&v, 6000000, 100.0L, -100.0, 6000000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_OUTLIER) != 0U && o.accepted == 0);
    o = step(&v, 7000000, 100.0L, -100.0, 7000000, GG_SENSOR_OK);
    assert_true((o.health & GG_VCHAN_RECAPTURE) != 0U && o.accepted == 1);
    assert_true(o.dh_m < 0.0L);
    /* a dropout longer than coast_us (10 s) is flagged; the next sample
     * corrects over one nominal period, not over the whole gap */
    o = step(&v, 18000000, 100.0L, 0, 0, GG_SENSOR_ABSENT);
    assert_true((o.health & GG_VCHAN_COAST) != 0U);
    const long double a_before = o.a_c;
    o = step(&v, 19000000, 100.0L, 99.0, 19000000, GG_SENSOR_OK);
    assert_int_equal(o.accepted, 1);
    assert_near(o.a_c - a_before, v.kd[2], 1e-15L);
    assert_int_equal(o.health & GG_VCHAN_COAST, 0);
    /* a non-finite inertial altitude is refused */
    gg_vchan_output_t o2;
    assert_int_equal(gg_vchan_step(&v, 20000000, NAN, NULL, &o2), GG_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_continuous_gains_place_the_poles),
        cmocka_unit_test(test_discrete_gains_place_the_poles),
        cmocka_unit_test(test_config_rejected),
        cmocka_unit_test(test_validation_gate_recapture_coast),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
