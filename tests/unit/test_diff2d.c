/* Accelerometer differencing against the closed-form point-mass field:
 * readings are computed at each sensor's own position (no Taylor series)
 * and rounded to double, as a real frame carries them. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/diff2d.h"

/* Readings rounded to double; with_lo = 1 also carries the residual. */
static void make_input(const long double r[3], const long double acc[3], long double a_m,
                       long double b_m, int with_lo, gg_diff2d_input_t *in)
{
    long double f[4][3];
    t_sensor_forces(r, acc, a_m, b_m, f);
    memset(in, 0, sizeof *in);
    for (int i = 0; i < 4; ++i) {
        for (int k = 0; k < 2; ++k) {
            const long double x = f[i][2 * k];
            in->f[i][k] = (double)x;
            if (with_lo) in->f_lo[i][k] = (double)(x - (long double)in->f[i][k]);
        }
    }
}

static void test_init_rejects_bad_geometry(void **state)
{
    (void)state;
    gg_diff2d_t d = {0};
    const gg_diff2d_config_t zero_a = {0.0L, 0.5L}, neg_b = {0.5L, -0.5L},
                             nan_a = {NAN, 0.5L}, inf_b = {0.5L, INFINITY};
    assert_int_equal(gg_diff2d_init(&d, &zero_a), GG_ERR_CONFIG);
    assert_int_equal(gg_diff2d_init(&d, &neg_b), GG_ERR_CONFIG);
    assert_int_equal(gg_diff2d_init(&d, &nan_a), GG_ERR_CONFIG);
    assert_int_equal(gg_diff2d_init(&d, &inf_b), GG_ERR_CONFIG);
    assert_int_equal(gg_diff2d_init(NULL, &zero_a), GG_ERR_NULL);
    assert_int_equal(d.initialized, 0);
    gg_diff2d_input_t in = {0};
    gg_diff2d_output_t out;
    assert_int_equal(gg_diff2d_step(&d, &in, &out), GG_ERR_NOT_INIT);
}

/* Gamma to 1e-4 E (1e-13 s^-2) and the centre specific force to 1e-13 m/s^2
 * at a 0.5 m half-baseline, at points around the meridian and at altitude. */
static void check_point_mass(int with_lo, long double tol_gamma)
{
    const gg_diff2d_config_t cfg = {0.5L, 0.5L};
    gg_diff2d_t d;
    assert_int_equal(gg_diff2d_init(&d, &cfg), GG_OK);
    const long double lats[] = {0.0L, 0.3L, 0.785398L, 1.2L, 1.5707963267948966L, -0.7L, 2.5L};
    const long double hs[] = {0.0L, 10000.0L};
    long double worst_g = 0, worst_f = 0, worst_asym = 0;
    for (size_t il = 0; il < sizeof lats / sizeof lats[0]; ++il) {
        for (size_t ih = 0; ih < 2; ++ih) {
            const long double rho = T_RE + hs[ih];
            const long double r[3] = {rho * cosl(lats[il]), 0.0L, rho * sinl(lats[il])};
            const long double acc[3] = {0.0123L, 0.0L, -0.0456L};
            gg_diff2d_input_t in;
            gg_diff2d_output_t out;
            long double gam[3][3], g[3];
            make_input(r, acc, cfg.a_m, cfg.b_m, with_lo, &in);
            assert_int_equal(gg_diff2d_step(&d, &in, &out), GG_OK);
            t_point_mass_gamma(r, gam);
            t_point_mass_g(r, g);
            const int ax[2] = {0, 2};
            for (int j = 0; j < 2; ++j) {
                for (int k = 0; k < 2; ++k) {
                    const long double e = fabsl(out.gamma[ax[j]][ax[k]] - gam[ax[j]][ax[k]]);
                    if (e > worst_g) worst_g = e;
                }
                const long double ef = fabsl(out.f_c[ax[j]] - (acc[ax[j]] - g[ax[j]]));
                if (ef > worst_f) worst_f = ef;
            }
            if (fabsl(out.asym) > worst_asym) worst_asym = fabsl(out.asym);
            for (int k = 0; k < 3; ++k) {
                assert_true(out.gamma[1][k] == 0.0L && out.gamma[k][1] == 0.0L);
            }
            assert_true(out.f_c[1] == 0.0L);
        }
    }
    printf("%s: worst |dGamma| = %.3Lg E, worst |df_c| = %.3Lg m/s^2, worst asym = %.3Lg E\n",
           with_lo ? "hi+lo readings" : "double readings", worst_g * 1e9L, worst_f,
           worst_asym * 1e9L);
    assert_true(worst_g < tol_gamma);
    assert_true(worst_asym < tol_gamma);
    /* the mean of the four is the centre force up to the curvature term
     * (a^2 d2G/dx2 + b^2 d2G/dz2)/4, ~4.5e-14 m/s^2 at a = b = 0.5 m */
    assert_true(worst_f < 1e-13L);
}

/* Bound with plain double readings: 1e-4 E. */
static void test_point_mass_double_readings(void **state)
{
    (void)state;
    check_point_mass(0, 1e-13L);
}

/* With the sub-ulp residual the differencing error falls to ~1e-9 E
 * (x86-64) - the rounding of the readings was the whole error. */
static void test_point_mass_hilo_readings(void **state)
{
    (void)state;
    check_point_mass(1, (__LDBL_MANT_DIG__ > 53) ? 1e-17L : 1e-13L);
}

/* A uniform gradient (linear field) with unequal baselines: every component
 * lands in its own slot with its own sign (catches index and sign swaps). */
static void test_linear_field_components(void **state)
{
    (void)state;
    const gg_diff2d_config_t cfg = {0.25L, 0.75L};
    gg_diff2d_t d;
    assert_int_equal(gg_diff2d_init(&d, &cfg), GG_OK);
    /* G(r) = G0 + M r with M = [[1,2],[3,4]] * 1e-6 (not a gradient: asymmetric on purpose) */
    const double M[2][2] = {{1e-6, 2e-6}, {3e-6, 4e-6}};
    const double G0[2] = {-0.5, -9.8};
    const double acc[2] = {0.1, 0.2};
    const double off[4][2] = {{0.25, 0}, {0, 0.75}, {-0.25, 0}, {0, -0.75}};
    gg_diff2d_input_t in;
    memset(&in, 0, sizeof in);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j)
            in.f[i][j] = acc[j] - (G0[j] + M[j][0] * off[i][0] + M[j][1] * off[i][1]);
    gg_diff2d_output_t out;
    assert_int_equal(gg_diff2d_step(&d, &in, &out), GG_OK);
    assert_near(out.gamma[0][0], 1e-6L, 1e-15L);
    assert_near(out.gamma[0][2], 2e-6L, 1e-15L);
    assert_near(out.gamma[2][0], 3e-6L, 1e-15L);
    assert_near(out.gamma[2][2], 4e-6L, 1e-15L);
    assert_near(out.asym, -1e-6L, 1e-15L);
    assert_near(out.f_c[0], 0.1L + 0.5L, 1e-15L);
    assert_near(out.f_c[2], 0.2L + 9.8L, 1e-14L);
}

static void test_nonfinite_input_rejected_output_untouched(void **state)
{
    (void)state;
    const gg_diff2d_config_t cfg = {0.5L, 0.5L};
    gg_diff2d_t d;
    assert_int_equal(gg_diff2d_init(&d, &cfg), GG_OK);
    const double bad[] = {NAN, INFINITY, -INFINITY};
    for (int b = 0; b < 3; ++b) {
        for (int i = 0; i < 4; ++i) {
            for (int ax = 0; ax < 2; ++ax) {
                gg_diff2d_input_t in = {{{1, 9.8}, {1, 9.8}, {1, 9.8}, {1, 9.8}}, {{0}}};
                if ((b & 1) == 0) {
                    in.f[i][ax] = bad[b];
                } else {
                    in.f_lo[i][ax] = bad[b];
                }
                gg_diff2d_output_t out, before;
                memset(&out, 0x5a, sizeof out);
                before = out;
                assert_int_equal(gg_diff2d_step(&d, &in, &out), GG_ERR_NONFINITE);
                assert_memory_equal(&out, &before, sizeof out);
            }
        }
    }
    assert_int_equal(gg_diff2d_step(&d, NULL, NULL), GG_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init_rejects_bad_geometry),
        cmocka_unit_test(test_point_mass_double_readings),
        cmocka_unit_test(test_point_mass_hilo_readings),
        cmocka_unit_test(test_linear_field_components),
        cmocka_unit_test(test_nonfinite_input_rejected_output_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
