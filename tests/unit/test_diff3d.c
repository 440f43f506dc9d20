/* 3-D differencing on a spinning, tumbling body in the closed-form
 * point-mass field: readings built from rigid-body kinematics at each
 * sensor's own position (no Taylor series), exact gyros. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/diff3d.h"

static void cross(const long double a[3], const long double b[3], long double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* rotation body -> nav from a unit quaternion (w, x, y, z) */
static void quat_to_dcm(const long double q[4], long double c[3][3])
{
    const long double w = q[0], x = q[1], y = q[2], z = q[3];
    c[0][0] = 1 - 2 * (y * y + z * z); c[0][1] = 2 * (x * y - w * z);     c[0][2] = 2 * (x * z + w * y);
    c[1][0] = 2 * (x * y + w * z);     c[1][1] = 1 - 2 * (x * x + z * z); c[1][2] = 2 * (y * z - w * x);
    c[2][0] = 2 * (x * z - w * y);     c[2][1] = 2 * (y * z + w * x);     c[2][2] = 1 - 2 * (x * x + y * y);
}

static void make_input(const long double r_n[3], const long double c_bn[3][3],
                       const long double acc_b[3], const long double w[3], const long double wd[3],
                       const long double hb[3], gg_diff3d_input_t *in)
{
    memset(in, 0, sizeof *in);
    for (int s = 0; s < 6; ++s) {
        long double d[3] = {0, 0, 0}, p[3], g_n[3], t1[3], t2[3], t3[3];
        d[s % 3] = (s < 3 ? 1 : -1) * hb[s % 3];
        for (int i = 0; i < 3; ++i) {
            p[i] = r_n[i];
            for (int j = 0; j < 3; ++j) p[i] += c_bn[i][j] * d[j];
        }
        t_point_mass_g(p, g_n);
        cross(wd, d, t1);
        cross(w, d, t2);
        cross(w, t2, t3);
        for (int i = 0; i < 3; ++i) {
            long double g_b = 0;
            for (int j = 0; j < 3; ++j) g_b += c_bn[j][i] * g_n[j]; /* C_nb = C_bn^T */
            const long double f = acc_b[i] + t1[i] + t3[i] - g_b;
            in->f[s][i] = (double)f;
            in->f_lo[s][i] = (double)(f - (long double)in->f[s][i]);
        }
    }
    for (int i = 0; i < 3; ++i) in->omega_b[i] = w[i];
}

static void check_body(const long double w[3], const long double wd[3], const long double q[4])
{
    const long double hb[3] = {0.5L, 0.4L, 0.6L};
    const gg_diff3d_config_t cfg = {{hb[0], hb[1], hb[2]}};
    gg_diff3d_t d3;
    assert_int_equal(gg_diff3d_init(&d3, &cfg), GG_OK);
    const long double r_n[3] = {3.1e6L, -2.2e6L, 5.0e6L};
    const long double acc_b[3] = {0.3L, -1.2L, 2.5L};
    long double c_bn[3][3], gam_n[3][3], g_n[3];
    quat_to_dcm(q, c_bn);
    t_point_mass_gamma(r_n, gam_n);
    t_point_mass_g(r_n, g_n);
    gg_diff3d_input_t in;
    gg_diff3d_output_t out;
    make_input(r_n, c_bn, acc_b, w, wd, hb, &in);
    assert_int_equal(gg_diff3d_step(&d3, &in, &out), GG_OK);
    long double worst_g = 0, worst_w = 0, worst_f = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            long double gb = 0; /* C_nb Gamma_n C_bn */
            for (int k = 0; k < 3; ++k)
                for (int l = 0; l < 3; ++l) gb += c_bn[k][i] * gam_n[k][l] * c_bn[l][j];
            worst_g = fmaxl(worst_g, fabsl(out.gamma[i][j] - gb));
        }
        worst_w = fmaxl(worst_w, fabsl(out.omega_dot[i] - wd[i]));
        long double g_b = 0;
        for (int j = 0; j < 3; ++j) g_b += c_bn[j][i] * g_n[j];
        worst_f = fmaxl(worst_f, fabsl(out.f_c[i] - (acc_b[i] - g_b)));
    }
    printf("|w| = %.2Lf rad/s: worst |dGamma| = %.3Lg E, |d omega_dot| = %.3Lg rad/s^2, "
           "|df_c| = %.3Lg m/s^2, trace = %.3Lg E\n",
           sqrtl(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]), worst_g * 1e9L, worst_w, worst_f,
           out.trace * 1e9L);
    assert_true(worst_g < 1e-13L);          /* 1e-4 E */
    assert_true(fabsl(out.trace) < 1e-13L); /* Laplace */
    assert_true(worst_w < 1e-12L);
    assert_true(worst_f < 1e-13L);
}

/* A body spinning at ~0.6 rad/s and tumbling (angular acceleration) at an
 * arbitrary attitude; then the space-stabilized case (no rotation). */
static void test_spinning_tumbling_body(void **state)
{
    (void)state;
    const long double w[3] = {0.3L, -0.2L, 0.5L}, wd[3] = {0.01L, 0.02L, -0.03L};
    const long double n = sqrtl(0.9L * 0.9L + 0.1L * 0.1L + 0.3L * 0.3L + 0.2L * 0.2L);
    const long double q[4] = {0.9L / n, 0.1L / n, -0.3L / n, 0.2L / n};
    check_body(w, wd, q);
    const long double w2[3] = {-2.0L, 1.5L, 3.0L}, wd2[3] = {-0.5L, 0.7L, 0.2L};
    check_body(w2, wd2, q);
    const long double z[3] = {0, 0, 0}, q0[4] = {1, 0, 0, 0};
    check_body(z, z, q0);
}

/* Linear field with unequal baselines and a known antisymmetric part:
 * every component in its slot with its sign. */
static void test_components_and_signs(void **state)
{
    (void)state;
    const gg_diff3d_config_t cfg = {{0.25L, 0.5L, 1.0L}};
    gg_diff3d_t d3;
    assert_int_equal(gg_diff3d_init(&d3, &cfg), GG_OK);
    /* readings f(d) = f0 + N d with N = W - Gamma chosen directly */
    const long double N[3][3] = {{1e-6L, 2e-6L, 3e-6L}, {4e-6L, 5e-6L, 6e-6L}, {7e-6L, 8e-6L, -6e-6L}};
    const long double f0[3] = {0.1L, 0.2L, 9.8L};
    gg_diff3d_input_t in;
    memset(&in, 0, sizeof in);
    for (int s = 0; s < 6; ++s) {
        long double d[3] = {0, 0, 0};
        d[s % 3] = (s < 3 ? 1 : -1) * cfg.half_base_m[s % 3];
        for (int i = 0; i < 3; ++i) {
            long double f = f0[i];
            for (int j = 0; j < 3; ++j) f += N[i][j] * d[j];
            in.f[s][i] = (double)f;
            in.f_lo[s][i] = (double)(f - (long double)in.f[s][i]);
        }
    }
    gg_diff3d_output_t out;
    assert_int_equal(gg_diff3d_step(&d3, &in, &out), GG_OK);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) assert_near(out.gamma[i][j], -0.5L * (N[i][j] + N[j][i]), 1e-18L);
    assert_near(out.omega_dot[0], 0.5L * (N[2][1] - N[1][2]), 1e-18L);
    assert_near(out.omega_dot[1], 0.5L * (N[0][2] - N[2][0]), 1e-18L);
    assert_near(out.omega_dot[2], 0.5L * (N[1][0] - N[0][1]), 1e-18L);
    assert_near(out.trace, 0.0L, 1e-18L);
    for (int i = 0; i < 3; ++i) assert_near(out.f_c[i], f0[i], 1e-15L);
}

static void test_bad_input(void **state)
{
    (void)state;
    gg_diff3d_t d3;
    const gg_diff3d_config_t bad = {{0.5L, 0.0L, 0.5L}}, good = {{0.5L, 0.5L, 0.5L}};
    assert_int_equal(gg_diff3d_init(&d3, &bad), GG_ERR_CONFIG);
    assert_int_equal(gg_diff3d_init(&d3, &good), GG_OK);
    gg_diff3d_input_t in;
    memset(&in, 0, sizeof in);
    gg_diff3d_output_t out, before;
    memset(&out, 0x5a, sizeof out);
    before = out;
    in.f[4][1] = NAN;
    assert_int_equal(gg_diff3d_step(&d3, &in, &out), GG_ERR_NONFINITE);
    in.f[4][1] = 0;
    in.omega_b[2] = INFINITY;
    assert_int_equal(gg_diff3d_step(&d3, &in, &out), GG_ERR_NONFINITE);
    assert_memory_equal(&out, &before, sizeof out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spinning_tumbling_body),
        cmocka_unit_test(test_components_and_signs),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
