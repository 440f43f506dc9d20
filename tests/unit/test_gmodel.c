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
    gg_gmodel_config_t cfg = {T_GM, T_RE, {0}};
    gg_gmodel_t m;
    assert_int_equal(gg_gmodel_init(&m, &cfg), GG_OK);
    const long double pts[3][3] = {{T_RE, 0, 0}, {0, 0, T_RE + 1e4L}, {3e6L, 1e6L, -5e6L}};
    for (int i = 0; i < 3; ++i) {
        gg_real_t g[3];
        long double gt[3];
        assert_int_equal(gg_gmodel_eval(&m, pts[i], g), GG_OK);
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
    gg_gmodel_config_t cfg = {T_GM, T_RE, {0}};
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
        assert_int_equal(gg_gmodel_eval(&m, pts[i], g), GG_OK);
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
    gg_gmodel_config_t cfg = {T_GM, T_RE, {0}};
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
    assert_int_equal(gg_gmodel_eval(&m, centre, g), GG_ERR_RANGE);
    assert_int_equal(gg_gmodel_eval(&m, bad, g), GG_ERR_NONFINITE);
    assert_true(g[0] == 1 && g[1] == 2 && g[2] == 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_mass_when_no_zonals),
        cmocka_unit_test(test_j2_j4_against_potential_gradient),
        cmocka_unit_test(test_bad_config_and_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
