/* Compensated accumulation (firmware/include/ggins/real.h) against exact
 * arithmetic: many small increments onto a large value. */
#include "test_common.h"
#include "ggins/real.h"

/* G ~ 9.8 m/s^2 built from 3.6e5 steps of ~1e-8 m/s^2. The exact sum is
 * base + N d, formed here with one rounding (a product and a sum). A plain
 * double sum is off by ~1e-10 (each add rounds at ulp(9.8)/2 ~ 9e-16, with a
 * constant bias for a constant increment); the compensated one must be off
 * by no more than a few ulp of the result's low part. */
static void test_many_small_increments(void **state)
{
    (void)state;
    const long double base = 9.8L;
    const long double d = 1.2345678912345e-8L;
    const long N = 360000;
    gg_acc_t acc;
    gg_acc_set(&acc, base);
    for (long i = 0; i < N; ++i) gg_acc_add(&acc, d);
    const long double exact = base + (long double)N * d;
    const long double err = fabsl(gg_acc_value(&acc) - exact);
    printf("compensated sum error after %ld adds: %.3Lg (long double mantissa %d bits)\n", N, err,
           __LDBL_MANT_DIG__);
#ifdef GGINS_NAIVE_ACCUM
    /* naive build: show that it misses */
    assert_true(err > 1e-13L);
#else
    /* 4 ulp of the result in working precision covers the final rounding of
     * exact itself (base + N d rounds once or twice). */
    assert_true(err <= 4.0L * 9.8L * __LDBL_EPSILON__);
#endif
}

/* Alternating large and tiny terms: (1 + tiny) - 1 recovers tiny exactly. */
static void test_cancellation_keeps_low_part(void **state)
{
    (void)state;
    gg_acc_t acc;
    gg_acc_set(&acc, 0.0L);
    const long double tiny = 3.0e-25L;
    for (int i = 0; i < 1000; ++i) {
        gg_acc_add(&acc, 1.0L);
        gg_acc_add(&acc, tiny);
        gg_acc_add(&acc, -1.0L);
    }
#ifndef GGINS_NAIVE_ACCUM
    assert_near(gg_acc_value(&acc), 1000.0L * tiny, 1e-6L * 1000.0L * tiny);
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_many_small_increments),
        cmocka_unit_test(test_cancellation_keeps_low_part),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
