/* Unit tests of the aids' integrity monitor (firmware/include/ggins/aid_integ.h).
 *
 * Independent truth:
 *  - the band against the exact tail of chi-square with an even number k = 2m
 *    of degrees of freedom, P(chi2_k > x) = exp(-x/2) sum_{j<m} (x/2)^j / j!
 *    (the Poisson form), and against the printed 0.99 quantiles of
 *    chi2(8) = 20.090 and chi2(48) = 73.683 (e.g. Abramowitz & Stegun, Table 26.8);
 *  - the false-alarm rate of the window test on simulated chi-square draws
 *    (sums of squared normal deviates from Box-Muller on a fixed-seed generator)
 *    against 1 - Phi(z);
 *  - the ladder OK -> SUSPECT -> ISOLATED -> SUSPECT -> OK counted by hand on
 *    a window of one, and the window's memory of one outlier (exactly `window`
 *    windows outside);
 *  - bad statistics (NaN, negative, infinite) taken as outside, bad settings refused.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "ggins/aid_integ.h"

/* P(chi2_k > x) for even k. */
static double chi2_sf_even(double x, int k)
{
    double s = 0.0, t = 1.0;
    for (int j = 0; j < k / 2; ++j) {
        s += t;
        t *= (x / 2.0) / (double)(j + 1);
    }
    return exp(-x / 2.0) * s;
}

static double normal_sf(double z) { return 0.5 * erfc(z / sqrt(2.0)); }

static void test_band(void **state)
{
    (void)state;
    gg_integ_t m;
    gg_integ_config_t c = {1, 64, 4.265, 0, 0};
    /* dof 6 (the map UKF's epoch): windows of 1..64 epochs, k = 6..384 */
    assert_int_equal(gg_integ_init(&m, &c, 6.0), GG_OK);
    const double p = normal_sf(4.265);
    double r_first = 0.0, r_last = 0.0;
    for (int n = 1; n <= 64; ++n) {
        const double r = chi2_sf_even(m.band[n - 1], 6 * n) / p;
        if (n == 1) r_first = r;
        r_last = r;
        /* Wilson-Hilferty overstates the far-tail quantile a little: the exact tail at the
         * band is below the nominal 1e-5, by less than a factor 0.55 for k >= 6 */
        assert_true(r <= 1.0);
        assert_true(r >= 0.55);
        if (n >= 8) assert_true(r >= 0.92);
    }
    /* dof 1 (the particle filter's shot), z at 0.99 */
    c.z = 2.3263478740;
    c.window = 8;
    assert_int_equal(gg_integ_init(&m, &c, 1.0), GG_OK);
    const double q8 = m.band[7];
    assert_true(fabs(q8 - 20.090) < 0.05);
    for (int n = 2; n <= 8; n += 2) {
        const double r = chi2_sf_even(m.band[n - 1], n) / 0.01;
        assert_true(fabs(r - 1.0) < 0.02);
    }
    assert_int_equal(gg_integ_init(&m, &c, 6.0), GG_OK);
    assert_true(fabs(m.band[7] - 73.683) < 0.05);
    printf("band: chi2(8) 0.99 %.3f (table 20.090), chi2(48) 0.99 %.3f (table 73.683); "
           "z 4.265: exact tail / 1e-5 from %.3f (k 6) to %.3f (k 384)\n",
           q8, m.band[7], r_first, r_last);
}

/* xorshift64* and Box-Muller: chi-square draws for the false-alarm test */
static uint64_t g_rng = 0x9E3779B97F4A7C15ULL;
static double uni(void)
{
    g_rng ^= g_rng >> 12;
    g_rng ^= g_rng << 25;
    g_rng ^= g_rng >> 27;
    return ((double)((g_rng * 2685821657736338717ULL) >> 11) + 0.5) / 9007199254740992.0;
}
static double gauss(void) { return sqrt(-2.0 * log(uni())) * cos(6.283185307179586 * uni()); }

static void test_false_alarm_rate(void **state)
{
    (void)state;
    gg_integ_t m;
    /* z = 2.326 (1 %) so that the rate is measurable; recover at once so the ladder never
     * stands still; the count of windows outside is what is tested */
    const gg_integ_config_t c = {1, 8, 2.3263478740, 1000, 1};
    for (int dof = 1; dof <= 6; dof += 5) {
        assert_int_equal(gg_integ_init(&m, &c, (double)dof), GG_OK);
        const int n_draws = 200000;
        for (int i = 0; i < n_draws; ++i) {
            double s = 0.0;
            for (int j = 0; j < dof; ++j) {
                const double g = gauss();
                s += g * g;
            }
            assert_int_equal(gg_integ_test(&m, s), GG_OK);
        }
        const double rate = (double)m.n_outside / (double)n_draws;
        /* consecutive windows share 7 of 8 draws: the count's sd is at most sqrt(8) that of
         * independent trials, 6.3e-4 here; 4 of those */
        printf("false alarms, dof %d, window 8, 1 %%: %.5f of %d windows\n", dof, rate, n_draws);
        assert_true(fabs(rate - 0.01) < 2.5e-3);
        assert_int_equal(m.n_tests, (uint32_t)n_draws);
    }
}

static void test_ladder(void **state)
{
    (void)state;
    gg_integ_t m;
    const gg_integ_config_t c = {1, 1, 4.265, 3, 8};
    assert_int_equal(gg_integ_init(&m, &c, 1.0), GG_OK);
    const double in = 0.5, out = 1000.0;
    assert_int_equal(gg_integ_test(&m, in), GG_OK);
    assert_int_equal(m.state, GG_INTEG_OK);
    assert_true(m.ratio < 1.0);
    assert_int_equal(gg_integ_test(&m, out), GG_OK);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);
    assert_true(m.ratio > 1.0);
    assert_int_equal(m.n_suspect, 1);
    /* two outside, one inside: the run restarts */
    (void)gg_integ_test(&m, out);
    (void)gg_integ_test(&m, out);
    (void)gg_integ_test(&m, in);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);
    (void)gg_integ_test(&m, out);
    (void)gg_integ_test(&m, out);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);
    (void)gg_integ_test(&m, out);
    assert_int_equal(m.state, GG_INTEG_ISOLATED);
    assert_int_equal(m.n_isolated, 1);
    /* recovery: 8 inside per rung */
    for (int i = 0; i < 7; ++i) (void)gg_integ_test(&m, in);
    assert_int_equal(m.state, GG_INTEG_ISOLATED);
    (void)gg_integ_test(&m, in);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);
    for (int i = 0; i < 7; ++i) (void)gg_integ_test(&m, in);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);
    (void)gg_integ_test(&m, in);
    assert_int_equal(m.state, GG_INTEG_OK);
    assert_int_equal(m.n_outside, 6);
    assert_int_equal(m.n_tests, 24);

    /* a window of 8 remembers one outlier for exactly 8 windows */
    const gg_integ_config_t c8 = {1, 8, 4.265, 1000, 1000};
    assert_int_equal(gg_integ_init(&m, &c8, 6.0), GG_OK);
    for (int i = 0; i < 20; ++i) (void)gg_integ_test(&m, 6.0);
    assert_int_equal(m.n_outside, 0);
    (void)gg_integ_test(&m, 1.0e6);
    for (int i = 0; i < 20; ++i) (void)gg_integ_test(&m, 6.0);
    assert_int_equal(m.n_outside, 8);
    assert_int_equal(m.state, GG_INTEG_SUSPECT);

    /* off: tested and counted, never leaves OK */
    gg_integ_config_t off = c;
    off.enable = 0;
    assert_int_equal(gg_integ_init(&m, &off, 1.0), GG_OK);
    for (int i = 0; i < 10; ++i) (void)gg_integ_test(&m, out);
    assert_int_equal(m.state, GG_INTEG_OK);
    assert_true(m.ratio > 1.0);
    assert_int_equal(m.n_tests, 10);
}

static void test_bad_input(void **state)
{
    (void)state;
    gg_integ_t m;
    const gg_integ_config_t c = {1, 4, 0.0, 0, 0};
    assert_int_equal(gg_integ_init(&m, &c, 6.0), GG_OK);
    /* defaults filled */
    assert_true(m.cfg.z == GG_INTEG_Z_DEFAULT);
    assert_int_equal(m.cfg.isolate_after, GG_INTEG_ISOLATE_AFTER_DEFAULT);
    assert_int_equal(m.cfg.recover_after, GG_INTEG_RECOVER_AFTER_DEFAULT);
    const double bad[3] = {NAN, -1.0, INFINITY};
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(gg_integ_init(&m, &c, 6.0), GG_OK);
        assert_int_equal(gg_integ_test(&m, bad[i]), GG_OK);
        assert_true(isfinite(m.ratio));
        assert_true(m.ratio > 1.0);
        assert_int_equal(m.state, GG_INTEG_SUSPECT);
        assert_true(m.last_stat == GG_INTEG_STAT_MAX);
    }
    /* a window full of the largest statistic stays finite */
    for (int i = 0; i < 100; ++i) (void)gg_integ_test(&m, NAN);
    assert_true(isfinite(m.ratio));
    assert_int_equal(m.state, GG_INTEG_ISOLATED);

    gg_integ_config_t b = c;
    b.window = GG_INTEG_WINDOW_MAX + 1;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b = c;
    b.window = -1;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b = c;
    b.z = 0.5;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b.z = NAN;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b.z = 11.0;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b = c;
    b.isolate_after = -1;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b = c;
    b.recover_after = 1001;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    b = c;
    b.enable = 2;
    assert_int_equal(gg_integ_init(&m, &b, 6.0), GG_ERR_CONFIG);
    assert_int_equal(gg_integ_init(&m, &c, 0.0), GG_ERR_CONFIG);
    assert_int_equal(gg_integ_init(&m, &c, NAN), GG_ERR_CONFIG);
    assert_int_equal(gg_integ_init(&m, &c, 101.0), GG_ERR_CONFIG);
    assert_int_equal(gg_integ_init(NULL, &c, 6.0), GG_ERR_NULL);
    assert_int_equal(gg_integ_init(&m, NULL, 6.0), GG_ERR_NULL);
    assert_int_equal(gg_integ_test(NULL, 1.0), GG_ERR_NULL);
    gg_integ_t z = {0};
    assert_int_equal(gg_integ_test(&z, 1.0), GG_ERR_NOT_INIT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_band),
        cmocka_unit_test(test_false_alarm_rate),
        cmocka_unit_test(test_ladder),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
