/* Map-matching UKF (mmukf): its NED mechanization against closed forms, the
 * body-axes gradient prediction against a hand rotation, the error/apply pair,
 * and the filter on a synthetic map (linear gradients, reproduced exactly by
 * the bicubic tile) pulling a 50 m initial position error in.
 *  - at rest (ideal IMU of a body at rest on the rotating Earth): no motion;
 *  - Schuler: at the equator an initial north velocity error dv gives
 *    dN(t) = dv/w_s sin(w_s t), w_s^2 = g/(R_M + h) (vertical held);
 *  - invalid inputs rejected with the state kept. */
#include "test_common.h"
#include "ggins/mmukf.h"

static const double kW = 7.292115e-5;
static const double M_PI_ = 3.14159265358979323846;
#define M_PI M_PI_
static gg_mm_t g_mm;
static gg_gmap_t g_map;

static gg_mm_imu_t rest_imu(double lat, double h)
{
    gg_mm_imu_t m;
    double g;
    assert_int_equal(gg_mm_normal_gravity(lat, h, &g), GG_OK);
    /* level, facing north: body = NED */
    m.omega_b[0] = kW * cos(lat);
    m.omega_b[1] = 0;
    m.omega_b[2] = -kW * sin(lat);
    m.f_b[0] = 0;
    m.f_b[1] = 0;
    m.f_b[2] = -g;
    return m;
}

static void test_rest(void **state)
{
    (void)state;
    gg_mm_nav_t x;
    memset(&x, 0, sizeof x);
    x.q[0] = 1;
    x.lat = 0.6;
    x.lon = 2.0;
    x.h = -50;
    const gg_mm_imu_t m = rest_imu(x.lat, x.h);
    for (int k = 0; k < 72000; ++k) assert_int_equal(gg_mm_mech(&x, &m, 0.1, 0, 0, 0), GG_OK);
    const double dn = (x.lat - 0.6) * 6.36e6, de = (x.lon - 2.0) * 6.38e6 * cos(0.6);
    printf("  rest 2 h: dN %.2e m dE %.2e m dh %.2e m, v (%.1e %.1e %.1e), q (%.1e %.1e %.1e)\n", dn, de, x.h + 50,
           x.v[0], x.v[1], x.v[2], x.q[1], x.q[2], x.q[3]);
    assert_true(fabs(dn) < 1e-3 && fabs(de) < 1e-3 && fabs(x.h + 50) < 1e-3);
    assert_true(fabs(x.v[0]) < 1e-6 && fabs(x.v[1]) < 1e-6 && fabs(x.v[2]) < 1e-6);
    assert_true(fabs(x.q[1]) < 1e-9 && fabs(x.q[2]) < 1e-9 && fabs(x.q[3]) < 1e-9);
}

static void test_schuler(void **state)
{
    (void)state;
    gg_mm_nav_t x;
    memset(&x, 0, sizeof x);
    x.q[0] = 1;
    x.v[0] = 0.1;
    const gg_mm_imu_t m = rest_imu(0.0, 0.0);
    double g;
    gg_mm_normal_gravity(0.0, 0.0, &g);
    const double rm = 6378137.0 * (1 - 6.69437999014e-3);
    const double ws = sqrt(g / rm), T = 2 * M_PI / ws, dt = 0.05;
    const int n4 = (int)lround(T / 4 / dt);
    double worst = 0;
    for (int k = 1; k <= 4 * n4; ++k) {
        assert_int_equal(gg_mm_mech(&x, &m, dt, 1, 0.0, 0.0), GG_OK);
        if (k % (n4 / 4) == 0) {
            const double t = k * dt, want = 0.1 / ws * sin(ws * t), got = x.lat * rm;
            if (fabs(got - want) > worst) worst = fabs(got - want);
        }
    }
    printf("  Schuler (T = %.1f s, amplitude %.2f m): worst |dN - dv/ws sin(ws t)| %.3e m over one period\n", T,
           0.1 / ws, worst);
    assert_true(worst < 0.01 * 0.1 / ws);
}

static void test_error_apply_and_rotation(void **state)
{
    (void)state;
    gg_mm_nav_t b, a;
    memset(&b, 0, sizeof b);
    b.q[0] = cos(0.3);
    b.q[3] = sin(0.3);
    b.lat = 0.5;
    b.lon = -1.0;
    b.h = -80;
    const double d[GG_MM_NX] = {1e-3, -2e-3, 5e-3, 0.5, -0.2, 0.1, 30, -40, 5, 1e-8, 2e-8, -1e-8, 1e-4, 0, -2e-4};
    double e[GG_MM_NX];
    assert_int_equal(gg_mm_apply(&b, d, &a), GG_OK);
    assert_int_equal(gg_mm_error(&a, &b, e), GG_OK);
    for (int k = 0; k < GG_MM_NX; ++k) assert_near(e[k], d[k], 1e-9 * (fabs(d[k]) + 1e-6));
    /* body-axes gradient: constant map, yaw 90 deg (body x = east, body y = south) */
    static gg_gmap_tile_t t;
    memset(&t, 0, sizeof t);
    t.nlat = t.nlon = 4;
    t.lat0_rad = 0.49;
    t.lon0_rad = -1.01;
    t.dlat_rad = t.dlon_rad = 0.01;
    t.h0_m = -80;
    t.h_range_m = 100;
    const double G6[6] = {-1.5e-6, -1.6e-6, 3.1e-6, 2e-9, 3e-9, -4e-9}; /* NN EE DD NE ND ED */
    for (int i = 0; i < 16; ++i)
        for (int c = 0; c < 6; ++c) t.node[i][c] = G6[c];
    assert_int_equal(gg_gmap_init(&g_map, &t), GG_OK);
    gg_mm_nav_t y = b;
    y.q[0] = cos(M_PI / 4);
    y.q[3] = sin(M_PI / 4);
    double z[6];
    assert_int_equal(gg_mm_predict_gradient(&g_map, &y, z), GG_OK);
    const double want[6] = {G6[1], G6[0], G6[2], -G6[3], G6[5], -G6[4]};
    for (int k = 0; k < 6; ++k) assert_near(z[k], want[k], 1e-20);
}

/* synthetic map: normal-like diagonal + linear horizontal variation (1e-3 E/m) */
static void field(double lat, double lon, double g6[6])
{
    const double dn = (lat - 0.5) * 6.36e6, de = (lon + 1.0) * 5.6e6;
    g6[0] = -1.54e-6 + 1e-12 * dn + 0.5e-12 * de;
    g6[1] = -1.54e-6 - 0.7e-12 * dn + 1e-12 * de;
    g6[2] = -(g6[0] + g6[1]);
    g6[3] = 1e-9 + 0.8e-12 * de;
    g6[4] = 2e-9 - 0.6e-12 * dn;
    g6[5] = -1e-9 + 0.9e-12 * dn - 0.4e-12 * de;
}

/* 9 x 9 tile of the linear field above around (0.5, -1.0) rad, -100 m, into g_map */
static void synthetic_tile(void)
{
    static gg_gmap_tile_t t;
    memset(&t, 0, sizeof t);
    t.nlat = t.nlon = 9;
    t.lat0_rad = 0.5 - 4e-4;
    t.lon0_rad = -1.0 - 4e-4;
    t.dlat_rad = t.dlon_rad = 1e-4;
    t.h0_m = -100;
    t.h_range_m = 300;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) field(t.lat0_rad + i * 1e-4, t.lon0_rad + j * 1e-4, t.node[i * 9 + j]);
    assert_int_equal(gg_gmap_init(&g_map, &t), GG_OK);
}

static void test_filter_pulls_position_in(void **state)
{
    (void)state;
    synthetic_tile();
    gg_mm_config_t c;
    memset(&c, 0, sizeof c);
    c.dt_s = 0.1;
    c.update_period_s = 10;
    c.sigma_meas_s2 = 1e-11;
    c.sigma_db_s2 = 1e-12;
    c.sig0_att_rad = 1e-3;
    c.sig0_vel_mps = 0.1;
    c.sig0_pos_m = 100;
    c.sig0_bg_rps = 1e-9;
    c.sig0_ba_mps2 = 1e-5;
    c.max_passes = 8;
    c.init.q[0] = 1;
    c.init.lat = 0.5 + 50.0 / 6.36e6; /* 50 m north, 50 m east of the truth */
    c.init.lon = -1.0 + 50.0 / 5.6e6;
    c.init.h = -100;
    /* an anomaly tile is refused */
    g_map.tile.flags = GG_GMAP_ANOMALY;
    assert_int_equal(gg_mm_init(&g_mm, &c, &g_map), GG_ERR_CONFIG);
    g_map.tile.flags = 0;
    assert_int_equal(gg_mm_init(&g_mm, &c, &g_map), GG_OK);
    const gg_mm_imu_t m = rest_imu(0.5, -100);
    gg_mm_meas_t z;
    memset(&z, 0, sizeof z);
    field(0.5, -1.0, z.gamma_b); /* truth at rest, level, facing north: body = NED */
    gg_mm_output_t out;
    for (int k = 0; k < 600; ++k) assert_int_equal(gg_mm_step(&g_mm, &m, &z, &out), GG_OK);
    const double en = (out.nav.lat - 0.5) * 6.36e6, ee = (out.nav.lon + 1.0) * 5.6e6;
    printf("  synthetic map, 60 s, %u updates: position error N %.2f m E %.2f m (from 50, 50), sigma %.2f %.2f m\n",
           out.n_updates, en, ee, out.sigma[6], out.sigma[7]);
    assert_int_equal(out.n_updates, 6);
    assert_true(fabs(en) < 5 && fabs(ee) < 5);
    assert_true(fabs(en) < 3 * out.sigma[6] + 1 && fabs(ee) < 3 * out.sigma[7] + 1);
    /* bad IMU: rejected, state kept */
    gg_mm_imu_t bad = m;
    bad.f_b[1] = NAN;
    const gg_mm_nav_t before = g_mm.sig[0];
    assert_int_equal(gg_mm_step(&g_mm, &bad, NULL, &out), GG_ERR_RANGE);
    assert_true(g_mm.health & GG_MM_H_BAD_INPUT);
    assert_memory_equal(&g_mm.sig[0], &before, sizeof before);
    z.gamma_b[2] = INFINITY;
    assert_int_equal(gg_mm_step(&g_mm, &m, &z, &out), GG_ERR_RANGE);
    assert_memory_equal(&g_mm.sig[0], &before, sizeof before);
}

/* an update at every 0.1 s step, one pass, a prior so tight that the predicted
 * spread is negligible next to R (the NIS then shows R itself); at the tile's
 * centre, level, facing north */
static gg_mm_config_t tiny_prior_config(double sm, double sdb)
{
    gg_mm_config_t c;
    memset(&c, 0, sizeof c);
    c.dt_s = 0.1;
    c.update_period_s = 0.1;
    c.sigma_meas_s2 = sm;
    c.sigma_db_s2 = sdb;
    c.sig0_att_rad = 1e-10;
    c.sig0_vel_mps = 1e-9;
    c.sig0_pos_m = 1e-6;
    c.sig0_bg_rps = 1e-15;
    c.sig0_ba_mps2 = 1e-12;
    c.max_passes = 1;
    c.init.q[0] = 1;
    c.init.lat = 0.5;
    c.init.lon = -1.0;
    c.init.h = -100;
    return c;
}

/* Measurement noise per component: with offdiag_ratio = 1/sqrt(2) the
 * off-diagonal components get R_off = sigma^2/2 + sigma_db^2. Checked through
 * the NIS of a single update with a tiny prior (the predicted spread is
 * negligible next to R): a known innovation of 1e-11 s^-2 on each component
 * gives NIS = 3 d^2/R_diag + 3 d^2/R_off (8.852 here; 5.941 with equal R). */
static void test_offdiag_noise(void **state)
{
    (void)state;
    synthetic_tile();
    const double sm = 1e-11, sdb = 1e-12, d = 1e-11;
    for (int variant = 0; variant < 3; ++variant) {
        gg_mm_config_t c = tiny_prior_config(sm, sdb);
        c.offdiag_ratio = variant == 0 ? 0.0 : (variant == 1 ? 1.0 : 1.0 / sqrt(2.0));
        assert_int_equal(gg_mm_init(&g_mm, &c, &g_map), GG_OK);
        const gg_mm_imu_t m = rest_imu(0.5, -100);
        gg_mm_meas_t z;
        memset(&z, 0, sizeof z);
        field(0.5, -1.0, z.gamma_b);
        for (int k = 0; k < 6; ++k) z.gamma_b[k] += d;
        gg_mm_output_t out;
        memset(&out, 0, sizeof out);
        for (int k = 0; k < 3 && !out.updated; ++k) assert_int_equal(gg_mm_step(&g_mm, &m, &z, &out), GG_OK);
        assert_int_equal(out.updated, 1);
        const double rd = sm * sm + sdb * sdb;
        const double so = (variant == 2 ? sm / sqrt(2.0) : sm);
        const double ro = so * so + sdb * sdb;
        const double expect = 3 * d * d / rd + 3 * d * d / ro;
        printf("  offdiag_ratio %.4f: NIS %.4f, expected %.4f\n", c.offdiag_ratio, out.nis, expect);
        assert_true(fabs(out.nis - expect) < 1e-3 * expect);
    }
    gg_mm_config_t bad;
    memset(&bad, 0, sizeof bad);
    bad = g_mm.cfg;
    bad.offdiag_ratio = 11.0;
    assert_int_equal(gg_mm_init(&g_mm, &bad, &g_map), GG_ERR_CONFIG);
    bad.offdiag_ratio = -0.5;
    assert_int_equal(gg_mm_init(&g_mm, &bad, &g_map), GG_ERR_CONFIG);
}

static void skew(const double a[3], double m[3][3])
{
    m[0][0] = 0;     m[0][1] = -a[2]; m[0][2] = a[1];
    m[1][0] = a[2];  m[1][1] = 0;     m[1][2] = -a[0];
    m[2][0] = -a[1]; m[2][1] = a[0];  m[2][2] = 0;
}

static void mm3(const double a[3][3], const double b[3][3], double c[3][3])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            c[i][j] = 0;
            for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
        }
}

static void six(const double m[3][3], double v[6])
{
    v[0] = m[0][0]; v[1] = m[1][1]; v[2] = m[2][2]; v[3] = m[0][1]; v[4] = m[0][2]; v[5] = m[1][2];
}

/* The gradiometer's [w x]^2 removal with the gyro reading (gyro_term): with a
 * known bias b_g in the filter's state, the measurement Gamma + [w x]^2 -
 * [(w - b_g) x]^2 (built here from skew-matrix products) must give a zero
 * innovation, and a known innovation d must give NIS = d^T (R + Rg)^-1 d with
 * Rg = s^2 sum_i S_i S_i^T, S_i = [W x][e_i x] + [e_i x][W x] (products of skew
 * matrices here; the firmware uses the closed form W e^T + e W^T - 2 W.e I),
 * solved by Gaussian elimination. */
static void test_gyro_term(void **state)
{
    (void)state;
    synthetic_tile();
    const double sm = 1e-11, sdb = 1e-12;
    const double w[3] = {0.02, -0.05, 0.03}, b[3] = {2e-6, -1e-6, 3e-6};
    const double sw = 2e-5;
    for (int variant = 0; variant < 2; ++variant) {
        gg_mm_config_t c = tiny_prior_config(sm, sdb);
        for (int j = 0; j < 3; ++j) c.init.bg[j] = b[j];
        assert_int_equal(gg_mm_init(&g_mm, &c, &g_map), GG_OK);
        gg_mm_imu_t m = rest_imu(0.5, -100);
        for (int j = 0; j < 3; ++j) m.omega_b[j] += b[j]; /* the gyro reads the bias too */
        gg_mm_meas_t z;
        memset(&z, 0, sizeof z);
        field(0.5, -1.0, z.gamma_b);
        double W[3], Sw[3][3], Su[3][3], Mw[3][3], Mu[3][3], cw[6], cu[6];
        for (int j = 0; j < 3; ++j) W[j] = w[j] - b[j];
        skew(w, Sw);
        skew(W, Su);
        mm3(Sw, Sw, Mw);
        mm3(Su, Su, Mu);
        six(Mw, cw);
        six(Mu, cu);
        for (int k = 0; k < 6; ++k) z.gamma_b[k] += cw[k] - cu[k];
        z.gyro_term = 1;
        for (int j = 0; j < 3; ++j) z.omega_b[j] = w[j];
        z.sigma_omega_rps = variant == 0 ? 0.0 : sw;
        const double d = 1e-11;
        if (variant == 1)
            for (int k = 0; k < 6; ++k) z.gamma_b[k] += d;
        gg_mm_output_t out;
        memset(&out, 0, sizeof out);
        for (int k = 0; k < 3 && !out.updated; ++k) assert_int_equal(gg_mm_step(&g_mm, &m, &z, &out), GG_OK);
        assert_int_equal(out.updated, 1);
        if (variant == 0) {
            printf("  gyro term, consistent measurement: NIS %.3g (a 1 %% error in the term: %.3g)\n", out.nis,
                   (0.01 * (cw[0] - cu[0])) * (0.01 * (cw[0] - cu[0])) / (sm * sm));
            assert_true(out.nis < 1e-2);
        } else {
            double A[6][7];
            for (int a = 0; a < 6; ++a) {
                for (int bb = 0; bb < 6; ++bb) A[a][bb] = (a == bb) ? (sm * sm + sdb * sdb) : 0.0;
                A[a][6] = d;
            }
            for (int i = 0; i < 3; ++i) {
                double e[3] = {0, 0, 0}, Se[3][3], P1[3][3], P2[3][3], S[3][3], s6[6];
                e[i] = 1;
                skew(e, Se);
                mm3(Su, Se, P1);
                mm3(Se, Su, P2);
                for (int r = 0; r < 3; ++r)
                    for (int q = 0; q < 3; ++q) S[r][q] = P1[r][q] + P2[r][q];
                six(S, s6);
                for (int a = 0; a < 6; ++a)
                    for (int bb = 0; bb < 6; ++bb) A[a][bb] += sw * sw * s6[a] * s6[bb];
            }
            for (int col = 0; col < 6; ++col) /* Gauss-Jordan, SPD: no pivoting needed */
                for (int r = 0; r < 6; ++r) {
                    if (r == col) continue;
                    const double f = A[r][col] / A[col][col];
                    for (int q = col; q < 7; ++q) A[r][q] -= f * A[col][q];
                }
            double expect = 0;
            for (int a = 0; a < 6; ++a) expect += d * A[a][6] / A[a][a];
            printf("  gyro term, sigma_w %.1e rad/s: NIS %.5f, expected %.5f (without the rate noise 5.94)\n", sw,
                   out.nis, expect);
            assert_true(fabs(out.nis - expect) < 1e-3 * expect);
            assert_true(expect < 5.5); /* the rate noise matters at this size: the check can fail */
        }
    }
    gg_mm_meas_t bad;
    memset(&bad, 0, sizeof bad);
    bad.gyro_term = 2;
    const gg_mm_imu_t m = rest_imu(0.5, -100);
    gg_mm_output_t out;
    assert_int_equal(gg_mm_step(&g_mm, &m, &bad, &out), GG_ERR_RANGE);
    bad.gyro_term = 1;
    bad.omega_b[1] = NAN;
    assert_int_equal(gg_mm_step(&g_mm, &m, &bad, &out), GG_ERR_RANGE);
    bad.omega_b[1] = 0;
    bad.sigma_omega_rps = -1;
    assert_int_equal(gg_mm_step(&g_mm, &m, &bad, &out), GG_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rest),
        cmocka_unit_test(test_schuler),
        cmocka_unit_test(test_error_apply_and_rotation),
        cmocka_unit_test(test_filter_pulls_position_in),
        cmocka_unit_test(test_offdiag_noise),
        cmocka_unit_test(test_gyro_term),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
