/* ggmath (sin, cos, atan2 without libm) against the C library's sinl, cosl,
 * atan2l: an independent implementation; likewise the double-precision exp,
 * log, sin and cos against exp, log, sin, cos. */
#include "test_common.h"
#include "ggins/ggmath.h"

#include <float.h>

/* error bound: a few units in the last place of long double at |value| <= 1 */
#define ULPS 8.0L

static void test_sincos_vs_libm(void **state)
{
    (void)state;
    long double worst = 0.0L;
    /* dense sweep over [-40, 40] rad plus large and tiny arguments */
    for (int i = -20000; i <= 20000; ++i) {
        const long double x = (long double)i * 0.002L + 1.0e-7L * (long double)(i % 7);
        long double s, c;
        assert_int_equal(gg_sincos(x, &s, &c), GG_OK);
        const long double es = fabsl(s - sinl(x));
        const long double ec = fabsl(c - cosl(x));
        worst = fmaxl(worst, fmaxl(es, ec));
    }
    const long double big[] = {1.0e3L, -2.5e4L, 9.99e5L, 0.2625L * 3600.0L * 10.0L, 1.0e-30L, 0.0L,
                               0.785398163397448309615660845819875721L};
    for (size_t i = 0; i < sizeof big / sizeof big[0]; ++i) {
        long double s, c;
        assert_int_equal(gg_sincos(big[i], &s, &c), GG_OK);
        /* libm reduces exactly; our reduction error is k * 2^-128 relative */
        worst = fmaxl(worst, fmaxl(fabsl(s - sinl(big[i])), fabsl(c - cosl(big[i]))));
    }
    print_message("sin/cos worst |error| vs libm: %.3Lg (ulp 1 = %.3Lg)\n", worst, LDBL_EPSILON);
    assert_true(worst <= ULPS * LDBL_EPSILON);
}

static void test_sincos_identities(void **state)
{
    (void)state;
    /* s^2 + c^2 = 1 and the addition theorem, which libm need not be consulted for */
    for (int i = 0; i < 1000; ++i) {
        const long double a = -7.0L + 0.0141L * i, b = 0.37L;
        long double sa, ca, sb, cb, sab, cab;
        assert_int_equal(gg_sincos(a, &sa, &ca), GG_OK);
        assert_int_equal(gg_sincos(b, &sb, &cb), GG_OK);
        assert_int_equal(gg_sincos(a + b, &sab, &cab), GG_OK);
        assert_near(sa * sa + ca * ca, 1.0L, 4.0L * LDBL_EPSILON);
        assert_near(sab, sa * cb + ca * sb, 8.0L * LDBL_EPSILON);
        assert_near(cab, ca * cb - sa * sb, 8.0L * LDBL_EPSILON);
    }
}

static void test_sincos_bad_input(void **state)
{
    (void)state;
    long double s = 5.0L, c = 5.0L;
    assert_int_equal(gg_sincos(NAN, &s, &c), GG_ERR_NONFINITE);
    assert_int_equal(gg_sincos(INFINITY, &s, &c), GG_ERR_NONFINITE);
    assert_int_equal(gg_sincos(2.0e6L, &s, &c), GG_ERR_RANGE);
    assert_int_equal(gg_sincos(1.0L, NULL, &c), GG_ERR_NULL);
    assert_true(s == 5.0L && c == 5.0L); /* untouched */
}

static void test_atan2_vs_libm(void **state)
{
    (void)state;
    long double worst = 0.0L;
    for (int i = 0; i < 3600; ++i) {
        const long double ang = -3.14159L + (long double)i * (6.28318L / 3600.0L);
        const long double rad[] = {1.0e-3L, 1.0L, 6.4e6L};
        for (size_t k = 0; k < 3; ++k) {
            const long double y = rad[k] * sinl(ang), x = rad[k] * cosl(ang);
            long double a;
            assert_int_equal(gg_atan2(y, x, &a), GG_OK);
            worst = fmaxl(worst, fabsl(a - atan2l(y, x)));
        }
    }
    /* axes and the origin */
    const long double pts[][2] = {{0, 1}, {1, 0}, {0, -1}, {-1, 0}, {1e-300L, 1}, {1, 1e-300L}};
    for (size_t k = 0; k < sizeof pts / sizeof pts[0]; ++k) {
        long double a;
        assert_int_equal(gg_atan2(pts[k][0], pts[k][1], &a), GG_OK);
        worst = fmaxl(worst, fabsl(a - atan2l(pts[k][0], pts[k][1])));
    }
    long double z = 9.0L;
    assert_int_equal(gg_atan2(0.0L, 0.0L, &z), GG_OK);
    assert_true(z == 0.0L);
    print_message("atan2 worst |error| vs libm: %.3Lg\n", worst);
    assert_true(worst <= ULPS * LDBL_EPSILON * 4.0L);
    assert_int_equal(gg_atan2(NAN, 1.0L, &z), GG_ERR_NONFINITE);
    assert_int_equal(gg_atan2(1.0L, INFINITY, &z), GG_ERR_NONFINITE);
}

static double rel(double a, double b) { return fabs(a - b) / fmax(fabs(b), 1e-300); }

/* the double-precision set (gg_exp_d, gg_log_d, gg_sincos_d) against libm */
static void test_double_vs_libm(void **state)
{
    (void)state;
    double worst_e = 0, worst_l = 0, worst_s = 0;
    for (int i = 0; i <= 20000; ++i) {
        const double x = -740.0 + 1449.0 * i / 20000.0, y = 0;
        double e = 0;
        assert_int_equal(gg_exp_d(x, &e), GG_OK);
        if (x > -700) worst_e = fmax(worst_e, rel(e, exp(x)));
        const double lx = exp(-700.0 + 1400.0 * i / 20000.0) * (1.0 + 0.37 * (i % 7));
        double l = 0;
        assert_int_equal(gg_log_d(lx, &l), GG_OK);
        worst_l = fmax(worst_l, fabs(l - log(lx)) / fmax(1.0, fabs(log(lx))));
        const double a = -1000.0 + 2000.0 * i / 20000.0 + 1e-3 * i;
        double s = 0, c = 0;
        assert_int_equal(gg_sincos_d(a, &s, &c), GG_OK);
        worst_s = fmax(worst_s, fmax(fabs(s - sin(a)), fabs(c - cos(a))));
        (void)y;
    }
    printf("exp rel %.2e, log %.2e, sincos abs %.2e\n", worst_e, worst_l, worst_s);
    assert_true(worst_e < 1e-14);
    assert_true(worst_l < 1e-15);
    assert_true(worst_s < 1e-13); /* |x| up to 1e3: reduction error ~ |x| eps */
    double y = 0, s = 0, c = 0;
    assert_int_equal(gg_log_d(0.0, &y), GG_ERR_RANGE);
    assert_int_equal(gg_log_d(NAN, &y), GG_ERR_NONFINITE);
    assert_int_equal(gg_exp_d(710.0, &y), GG_ERR_RANGE);
    assert_int_equal(gg_exp_d(-800.0, &y), GG_OK);
    assert_true(y == 0.0);
    assert_int_equal(gg_sincos_d(INFINITY, &s, &c), GG_ERR_NONFINITE);
    assert_int_equal(gg_log_d(4.9e-324, &y), GG_OK); /* subnormal */
    assert_true(fabs(y - log(4.9e-324)) < 1e-12);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sincos_vs_libm),
        cmocka_unit_test(test_sincos_identities),
        cmocka_unit_test(test_sincos_bad_input),
        cmocka_unit_test(test_atan2_vs_libm),
        cmocka_unit_test(test_double_vs_libm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
