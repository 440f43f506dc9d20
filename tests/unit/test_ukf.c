/* UKF core against independent references:
 *  - LINEAR system: the UKF equals the Kalman filter (closed form, written
 *    here in long double with plain matrix products), for lambda = 0 (Gao's
 *    set) and lambda = 2, over 30 predict/update cycles;
 *  - quadratic measurement: the UT's predicted mean equals the closed-form
 *    E[h(x)] of a Gaussian (exact for degree 2);
 *  - nonlinear (range) measurement: posterior mean and covariance against a
 *    brute-force Bayesian posterior on a 601 x 601 grid;
 *  - Cholesky against a known factor; failures handled (non-PD P0, Q that
 *    destroys PD, R = 0 with a full-rank measurement, non-finite inputs and
 *    models): error returned, x and P untouched, health and counters set;
 *  - innovation gating. */
#include "test_common.h"
#include "ggins/ukf.h"

#define N GG_UKF_NX_MAX
#define M GG_UKF_NZ_MAX

static gg_ukf_t g_f;

/* ---- linear system: 2-D constant velocity, position measured ---- */
static const int kN = 4, kM = 2;
static double F[4][4] = {{1, 0, 0.5, 0}, {0, 1, 0, 0.5}, {0, 0, 1, 0}, {0, 0, 0.1, 0.95}};
static double H[2][4] = {{1, 0.2, 0, 0}, {0, 1, 0, 0.3}};

static gg_status_t lin_f(void *ctx, const double *x, double *y)
{
    (void)ctx;
    for (int i = 0; i < kN; ++i) {
        y[i] = 0;
        for (int j = 0; j < kN; ++j) y[i] += F[i][j] * x[j];
    }
    return GG_OK;
}
static gg_status_t lin_h(void *ctx, const double *x, double *z)
{
    (void)ctx;
    for (int i = 0; i < kM; ++i) {
        z[i] = 0;
        for (int j = 0; j < kN; ++j) z[i] += H[i][j] * x[j];
    }
    return GG_OK;
}

/* reference KF in long double */
typedef struct {
    long double x[4], P[4][4];
} kf_t;

static void kf_predict(kf_t *k, const double Q[N][N])
{
    long double x[4] = {0}, FP[4][4] = {{0}}, P[4][4] = {{0}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) x[i] += F[i][j] * k->x[j];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            for (int l = 0; l < 4; ++l) FP[i][j] += F[i][l] * k->P[l][j];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            for (int l = 0; l < 4; ++l) P[i][j] += FP[i][l] * F[j][l];
            P[i][j] += Q[i][j];
        }
    memcpy(k->x, x, sizeof x);
    memcpy(k->P, P, sizeof P);
}

static void kf_update(kf_t *k, const double z[2], const double R[M][M])
{
    long double PHt[4][2] = {{0}}, S[2][2], Si[2][2], K[4][2] = {{0}}, nu[2];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j)
            for (int l = 0; l < 4; ++l) PHt[i][j] += k->P[i][l] * H[j][l];
    for (int i = 0; i < 2; ++i) {
        for (int j = 0; j < 2; ++j) {
            S[i][j] = R[i][j];
            for (int l = 0; l < 4; ++l) S[i][j] += H[i][l] * PHt[l][j];
        }
        nu[i] = z[i];
        for (int l = 0; l < 4; ++l) nu[i] -= H[i][l] * k->x[l];
    }
    const long double det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
    Si[0][0] = S[1][1] / det;
    Si[1][1] = S[0][0] / det;
    Si[0][1] = -S[0][1] / det;
    Si[1][0] = -S[1][0] / det;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j)
            for (int l = 0; l < 2; ++l) K[i][j] += PHt[i][l] * Si[l][j];
    long double P[4][4];
    for (int i = 0; i < 4; ++i) {
        k->x[i] += K[i][0] * nu[0] + K[i][1] * nu[1];
        for (int j = 0; j < 4; ++j) P[i][j] = k->P[i][j] - (K[i][0] * PHt[j][0] + K[i][1] * PHt[j][1]);
    }
    memcpy(k->P, P, sizeof P);
}

static double lcg(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return ((double)(*s >> 8) / 16777216.0) - 0.5;
}

static void run_linear(double lambda)
{
    static double P0[N][N], Q[N][N], R[M][M];
    memset(P0, 0, sizeof P0);
    memset(Q, 0, sizeof Q);
    memset(R, 0, sizeof R);
    const double p0[4][4] = {{4, 0.5, 0.1, 0}, {0.5, 3, 0, 0.2}, {0.1, 0, 1, 0.05}, {0, 0.2, 0.05, 0.8}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) P0[i][j] = p0[i][j];
    Q[0][0] = Q[1][1] = 0.01;
    Q[2][2] = Q[3][3] = 0.04;
    Q[2][3] = Q[3][2] = 0.01;
    R[0][0] = 0.25;
    R[1][1] = 0.5;
    R[0][1] = R[1][0] = 0.05;
    const double x0[4] = {1, -2, 0.5, 0.3};
    gg_ukf_config_t cfg = {.nx = 4, .lambda = lambda, .gate_nis = 0};
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_OK);
    kf_t k;
    for (int i = 0; i < 4; ++i) {
        k.x[i] = x0[i];
        for (int j = 0; j < 4; ++j) k.P[i][j] = P0[i][j];
    }
    uint32_t seed = 12345u;
    long double wx = 0, wp = 0;
    for (int step = 0; step < 30; ++step) {
        assert_int_equal(gg_ukf_predict(&g_f, lin_f, NULL, (const double(*)[N])Q), GG_OK);
        kf_predict(&k, (const double(*)[N])Q);
        const double z[2] = {3.0 * lcg(&seed) + 0.1 * step, 3.0 * lcg(&seed) - 0.05 * step};
        gg_ukf_update_info_t info;
        /* single-update NIS from the spread function against the KF's own S and nu */
        double spread[M], nis_sp = 0;
        assert_int_equal(gg_ukf_meas_spread(&g_f, 2, lin_h, NULL, spread, z, (const double(*)[M])R, &nis_sp), GG_OK);
        {
            long double PHt[4][2] = {{0}}, S[2][2], nu[2];
            for (int i = 0; i < 4; ++i)
                for (int j = 0; j < 2; ++j)
                    for (int l = 0; l < 4; ++l) PHt[i][j] += k.P[i][l] * H[j][l];
            for (int i = 0; i < 2; ++i) {
                for (int j = 0; j < 2; ++j) {
                    S[i][j] = R[i][j];
                    for (int l = 0; l < 4; ++l) S[i][j] += H[i][l] * PHt[l][j];
                }
                nu[i] = z[i];
                for (int l = 0; l < 4; ++l) nu[i] -= H[i][l] * k.x[l];
            }
            const long double det = S[0][0] * S[1][1] - S[0][1] * S[1][0];
            const long double nis_kf = (S[1][1] * nu[0] * nu[0] - 2 * S[0][1] * nu[0] * nu[1] + S[0][0] * nu[1] * nu[1]) / det;
            assert_near(nis_sp, nis_kf, 1e-10L * (1 + nis_kf));
            assert_near(spread[0] + R[0][0], S[0][0], 1e-10L * S[0][0]);
        }
        if (step % 3 == 2) {
            /* progressive: three passes with R / w, w = 0.2, 0.3, 0.5 (sum 1) = one KF update with R */
            const double w[3] = {0.2, 0.3, 0.5};
            for (int p = 0; p < 3; ++p) {
                double Rw[M][M];
                memset(Rw, 0, sizeof Rw);
                for (int i = 0; i < 2; ++i)
                    for (int j = 0; j < 2; ++j) Rw[i][j] = R[i][j] / w[p];
                assert_int_equal(gg_ukf_update(&g_f, 2, z, (const double(*)[M])Rw, lin_h, NULL, &info), GG_OK);
            }
        } else {
            assert_int_equal(gg_ukf_update(&g_f, 2, z, (const double(*)[M])R, lin_h, NULL, &info), GG_OK);
        }
        assert_int_equal(info.accepted, 1);
        kf_update(&k, z, (const double(*)[M])R);
        for (int i = 0; i < 4; ++i) {
            const long double ex = fabsl(g_f.x[i] - k.x[i]) / sqrtl(k.P[i][i]);
            if (ex > wx) wx = ex;
            for (int j = 0; j < 4; ++j) {
                const long double ep = fabsl(g_f.P[i][j] - k.P[i][j]) / sqrtl(k.P[i][i] * k.P[j][j]);
                if (ep > wp) wp = ep;
            }
            assert_true(g_f.P[i][i] > 0);
        }
    }
    printf("  linear, lambda %.0f: worst |x - x_KF| %.2Le sigma, worst |P - P_KF| %.2Le (correlation units)\n",
           lambda, wx, wp);
    assert_true(wx < 1e-12L);
    assert_true(wp < 1e-12L);
    assert_int_equal(g_f.n_updates, 50); /* 20 single + 10 x 3 passes */
}

static void test_linear_equals_kalman(void **state)
{
    (void)state;
    run_linear(0.0);
    run_linear(2.0);
}

/* ---- quadratic measurement: E[x0^2] = m0^2 + P00, E[x0 x1] = m0 m1 + P01 ---- */
static gg_status_t quad_h(void *ctx, const double *x, double *z)
{
    (void)ctx;
    z[0] = x[0] * x[0];
    z[1] = x[0] * x[1];
    z[2] = x[2] * x[2] - 3.0 * x[1];
    return GG_OK;
}

static void test_quadratic_mean_exact(void **state)
{
    (void)state;
    static double P0[N][N], R[M][M];
    memset(P0, 0, sizeof P0);
    memset(R, 0, sizeof R);
    const double p[3][3] = {{2.0, 0.7, -0.3}, {0.7, 1.5, 0.2}, {-0.3, 0.2, 0.9}};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) P0[i][j] = p[i][j];
    for (int i = 0; i < 3; ++i) R[i][i] = 1.0;
    const double x0[3] = {0.4, -1.1, 2.0};
    const double z[3] = {0, 0, 0};
    const double want[3] = {x0[0] * x0[0] + p[0][0], x0[0] * x0[1] + p[0][1], x0[2] * x0[2] + p[2][2] - 3.0 * x0[1]};
    for (int l = 0; l < 2; ++l) {
        gg_ukf_config_t cfg = {.nx = 3, .lambda = l == 0 ? 0.0 : 1.5, .gate_nis = 0};
        assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_OK);
        gg_ukf_update_info_t info;
        assert_int_equal(gg_ukf_update(&g_f, 3, z, (const double(*)[M])R, quad_h, NULL, &info), GG_OK);
        for (int k = 0; k < 3; ++k) assert_near(z[k] - info.innov[k], want[k], 1e-13);
    }
}

/* ---- range measurement vs the brute-force posterior on a grid ---- */
static gg_status_t range_h(void *ctx, const double *x, double *z)
{
    (void)ctx;
    const double dx = x[0] - 3.0, dy = x[1] - 1.0;
    z[0] = sqrt(dx * dx + dy * dy);
    return GG_OK;
}

static void test_range_vs_grid_posterior(void **state)
{
    (void)state;
    static double P0[N][N], R[M][M];
    memset(P0, 0, sizeof P0);
    memset(R, 0, sizeof R);
    const double m0[2] = {0.0, 0.0}, p00 = 0.36, p11 = 0.25, p01 = 0.06, r = 0.04;
    P0[0][0] = p00;
    P0[1][1] = p11;
    P0[0][1] = P0[1][0] = p01;
    R[0][0] = r;
    const double z[1] = {2.9}; /* prior predicts ~3.16 */
    /* grid posterior: prior density x likelihood, +-6 sigma, 601 x 601 */
    const double det = p00 * p11 - p01 * p01;
    long double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    const int G = 601;
    const double h0 = 12.0 * sqrt(p00) / (G - 1), h1 = 12.0 * sqrt(p11) / (G - 1);
    for (int i = 0; i < G; ++i) {
        const double x = m0[0] - 6.0 * sqrt(p00) + i * h0;
        for (int j = 0; j < G; ++j) {
            const double y = m0[1] - 6.0 * sqrt(p11) + j * h1;
            const double q = (p11 * x * x - 2 * p01 * x * y + p00 * y * y) / det;
            double zz[1];
            const double xv[2] = {x, y};
            range_h(NULL, xv, zz);
            const long double w = expl(-0.5L * q - 0.5L * (z[0] - zz[0]) * (z[0] - zz[0]) / r);
            sw += w;
            sx += w * x;
            sy += w * y;
            sxx += w * x * x;
            syy += w * y * y;
            sxy += w * x * y;
        }
    }
    const long double mx = sx / sw, my = sy / sw;
    const long double cxx = sxx / sw - mx * mx, cyy = syy / sw - my * my, cxy = sxy / sw - mx * my;
    gg_ukf_config_t cfg = {.nx = 2, .lambda = 1.0, .gate_nis = 0};
    assert_int_equal(gg_ukf_init(&g_f, &cfg, m0, (const double(*)[N])P0), GG_OK);
    gg_ukf_update_info_t info;
    assert_int_equal(gg_ukf_update(&g_f, 1, z, (const double(*)[M])R, range_h, NULL, &info), GG_OK);
    const long double sx_ = sqrtl(cxx), sy_ = sqrtl(cyy);
    const long double ex = fabsl(g_f.x[0] - mx) / sx_, ey = fabsl(g_f.x[1] - my) / sy_;
    const long double exx = fabsl(g_f.P[0][0] / cxx - 1), eyy = fabsl(g_f.P[1][1] / cyy - 1);
    const long double prior_off = fabsl(m0[0] - mx) / sx_;
    printf("  range: grid posterior mean (%.4Lf, %.4Lf) sd (%.4Lf, %.4Lf) rho %.3Lf; UKF (%.4f, %.4f) sd (%.4f, %.4f)\n",
           mx, my, sx_, sy_, cxy / (sx_ * sy_), g_f.x[0], g_f.x[1], sqrt(g_f.P[0][0]), sqrt(g_f.P[1][1]));
    printf("  range: UKF mean error %.3Lf / %.3Lf posterior sigma (prior mean was %.3Lf off), var ratio error %.3Lf / %.3Lf\n",
           ex, ey, prior_off, exx, eyy);
    assert_true(prior_off > 0.5L); /* the measurement moves the posterior: a real test */
    assert_true(ex < 0.05L && ey < 0.05L);
    assert_true(exx < 0.05L && eyy < 0.05L);
}

/* ---- Cholesky and failure handling ---- */
static void test_cholesky_known(void **state)
{
    (void)state;
    static double A[N][N], L[N][N];
    const double L0[3][3] = {{2, 0, 0}, {-1, 3, 0}, {0.5, 0.25, 1.5}};
    memset(A, 0, sizeof A);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) A[i][j] += L0[i][k] * L0[j][k];
    assert_int_equal(gg_ukf_cholesky(3, (const double(*)[N])A, L), GG_OK);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) assert_near(L[i][j], L0[i][j], 1e-15);
    /* indefinite: L untouched */
    A[2][2] = 0.0;
    L[0][0] = 42.0;
    assert_int_equal(gg_ukf_cholesky(3, (const double(*)[N])A, L), GG_ERR_RANGE);
    assert_true(L[0][0] == 42.0);
    A[2][2] = NAN;
    assert_int_equal(gg_ukf_cholesky(3, (const double(*)[N])A, L), GG_ERR_RANGE);
    /* badly scaled but well conditioned after scaling (position 1e2 m^2 beside a
     * gyro-bias variance 2e-15): accepted, L exact; the pivot test is per row */
    memset(A, 0, sizeof A);
    A[0][0] = 100.0;
    A[1][1] = 2.0e-15;
    A[0][1] = A[1][0] = 0.5 * sqrt(100.0 * 2.0e-15);
    assert_int_equal(gg_ukf_cholesky(2, (const double(*)[N])A, L), GG_OK);
    assert_near(L[0][0], 10.0, 1e-14);
    assert_near(L[1][0], 0.5 * sqrt(2.0e-15), 1e-22);
    assert_near(L[1][1], sqrt(0.75 * 2.0e-15), 1e-22);
    /* the same with a correlation of 1 - 1e-17: singular to working precision, refused */
    A[0][1] = A[1][0] = sqrt(100.0 * 2.0e-15);
    assert_int_equal(gg_ukf_cholesky(2, (const double(*)[N])A, L), GG_ERR_RANGE);
}

/* O = T S T^T against the closed form: a rotation by th in the x-y plane of
 * diag(s1, s2, s3) is [[c^2 s1 + s^2 s2, c s (s1 - s2), 0], [., s^2 s1 + c^2 s2, 0],
 * [0, 0, s3]]; a shear [[1, 2], [0, 1]] of I is [[5, 2], [2, 1]]; O may be S. */
static void test_congruence_known(void **state)
{
    (void)state;
    static double T[N][N], S[N][N], O[N][N];
    const double th = 0.3, c = cos(th), s = sin(th), s1 = 4.0, s2 = 0.25, s3 = 9.0;
    memset(T, 0, sizeof T);
    memset(S, 0, sizeof S);
    T[0][0] = c;
    T[0][1] = -s;
    T[1][0] = s;
    T[1][1] = c;
    T[2][2] = 1.0;
    S[0][0] = s1;
    S[1][1] = s2;
    S[2][2] = s3;
    assert_int_equal(gg_ukf_congruence(3, (const double(*)[N])T, (const double(*)[N])S, O), GG_OK);
    assert_near(O[0][0], c * c * s1 + s * s * s2, 1e-15);
    assert_near(O[0][1], c * s * (s1 - s2), 1e-15);
    assert_near(O[1][0], c * s * (s1 - s2), 1e-15);
    assert_near(O[1][1], s * s * s1 + c * c * s2, 1e-15);
    assert_near(O[2][2], s3, 0.0);
    assert_near(O[0][2], 0.0, 0.0);
    assert_near(O[1][2], 0.0, 0.0);
    /* in place (O = S), exact in binary */
    memset(T, 0, sizeof T);
    memset(S, 0, sizeof S);
    T[0][0] = 1.0;
    T[0][1] = 2.0;
    T[1][1] = 1.0;
    S[0][0] = 1.0;
    S[1][1] = 1.0;
    assert_int_equal(gg_ukf_congruence(2, (const double(*)[N])T, (const double(*)[N])S, S), GG_OK);
    assert_true(S[0][0] == 5.0 && S[0][1] == 2.0 && S[1][0] == 2.0 && S[1][1] == 1.0);
    /* dimension out of range or NULL: O untouched */
    O[0][0] = 42.0;
    assert_int_equal(gg_ukf_congruence(0, (const double(*)[N])T, (const double(*)[N])S, O), GG_ERR_CONFIG);
    assert_int_equal(gg_ukf_congruence(N + 1, (const double(*)[N])T, (const double(*)[N])S, O), GG_ERR_CONFIG);
    assert_int_equal(gg_ukf_congruence(2, NULL, (const double(*)[N])S, O), GG_ERR_NULL);
    assert_true(O[0][0] == 42.0);
}

static gg_status_t nan_h(void *ctx, const double *x, double *z)
{
    (void)ctx;
    z[0] = x[0] > 1.5 ? NAN : x[0];
    return GG_OK;
}
static gg_status_t fail_f(void *ctx, const double *x, double *y)
{
    (void)ctx;
    (void)x;
    (void)y;
    return GG_ERR_RANGE;
}
static gg_status_t ident_h(void *ctx, const double *x, double *z)
{
    (void)ctx;
    z[0] = x[0];
    z[1] = x[1];
    return GG_OK;
}

static void test_failures_keep_state(void **state)
{
    (void)state;
    static double P0[N][N], Q[N][N], R[M][M];
    memset(P0, 0, sizeof P0);
    memset(Q, 0, sizeof Q);
    memset(R, 0, sizeof R);
    P0[0][0] = 1;
    P0[1][1] = 2;
    P0[0][1] = P0[1][0] = 1.5; /* det < 0: not PD */
    const double x0[2] = {1, 2};
    gg_ukf_config_t cfg = {.nx = 2, .lambda = 0, .gate_nis = 10.0};
    memset(&g_f, 0, sizeof g_f);
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_ERR_RANGE);
    assert_int_equal(g_f.initialized, 0);
    P0[0][1] = 0.5; /* not symmetric */
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_ERR_RANGE);
    P0[1][0] = 0.5;
    cfg.lambda = -1;
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_ERR_CONFIG);
    cfg.lambda = 0;
    cfg.nx = N + 1; /* beyond GG_UKF_NX_MAX */
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_ERR_CONFIG);
    cfg.nx = 2;
    assert_int_equal(gg_ukf_init(&g_f, &cfg, x0, (const double(*)[N])P0), GG_OK);
    gg_ukf_t saved = g_f;

    /* Q that makes the predicted covariance indefinite */
    Q[0][0] = -5.0;
    assert_int_equal(gg_ukf_predict(&g_f, lin_f, NULL, (const double(*)[N])Q), GG_ERR_RANGE);
    assert_true(g_f.health & GG_UKF_H_CHOL_FAIL);
    assert_int_equal(g_f.n_chol_fail, 1);
    assert_memory_equal(g_f.x, saved.x, sizeof g_f.x);
    assert_memory_equal(g_f.P, saved.P, sizeof g_f.P);
    assert_memory_equal(g_f.L, saved.L, sizeof g_f.L);
    Q[0][0] = 0.0;
    /* a failing process model */
    assert_int_equal(gg_ukf_predict(&g_f, fail_f, NULL, (const double(*)[N])Q), GG_ERR_RANGE);
    assert_true(g_f.health & GG_UKF_H_MODEL);
    assert_memory_equal(g_f.x, saved.x, sizeof g_f.x);
    /* finish without sigma points */
    assert_int_equal(gg_ukf_predict_finish(&g_f, (const double(*)[N])Q), GG_ERR_SEQUENCE);
    /* R = 0 and a full-rank exact measurement: P+ = 0, not PD: rejected */
    const double z2[2] = {1.1, 2.1};
    assert_int_equal(gg_ukf_update(&g_f, 2, z2, (const double(*)[M])R, ident_h, NULL, NULL), GG_ERR_RANGE);
    assert_true(g_f.health & GG_UKF_H_CHOL_FAIL);
    assert_memory_equal(g_f.x, saved.x, sizeof g_f.x);
    assert_memory_equal(g_f.P, saved.P, sizeof g_f.P);
    /* NaN from the model at some sigma points, NaN measurement, NaN R */
    R[0][0] = R[1][1] = 0.1;
    const double z1[1] = {1.0};
    assert_int_equal(gg_ukf_update(&g_f, 1, z1, (const double(*)[M])R, nan_h, NULL, NULL), GG_ERR_NONFINITE);
    assert_true(g_f.health & GG_UKF_H_MODEL);
    const double zn[2] = {NAN, 0};
    assert_int_equal(gg_ukf_update(&g_f, 2, zn, (const double(*)[M])R, ident_h, NULL, NULL), GG_ERR_NONFINITE);
    assert_true(g_f.health & GG_UKF_H_INPUT);
    assert_int_equal(gg_ukf_update(&g_f, 7, z2, (const double(*)[M])R, ident_h, NULL, NULL), GG_ERR_CONFIG);
    assert_memory_equal(g_f.x, saved.x, sizeof g_f.x);
    assert_memory_equal(g_f.P, saved.P, sizeof g_f.P);
    /* gating: an innovation of 30 sigma is skipped, GG_OK, state kept */
    const double zg[2] = {x0[0] + 30.0 * sqrt(1.1), x0[1]};
    gg_ukf_update_info_t info;
    assert_int_equal(gg_ukf_update(&g_f, 2, zg, (const double(*)[M])R, ident_h, NULL, &info), GG_OK);
    assert_int_equal(info.accepted, 0);
    assert_true(info.nis > 10.0);
    assert_true(g_f.health & GG_UKF_H_GATED);
    assert_int_equal(g_f.n_gated, 1);
    assert_memory_equal(g_f.x, saved.x, sizeof g_f.x);
    /* and a consistent one passes: NIS of nu = (0.5, 0) with S = P + R */
    const double zo[2] = {x0[0] + 0.5, x0[1]};
    assert_int_equal(gg_ukf_update(&g_f, 2, zo, (const double(*)[M])R, ident_h, NULL, &info), GG_OK);
    assert_int_equal(info.accepted, 1);
    const double s00 = 1.1, s11 = 2.1, s01 = 0.5;
    assert_near(info.nis, 0.25 * s11 / (s00 * s11 - s01 * s01), 1e-14);
    assert_int_equal(g_f.health, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linear_equals_kalman),
        cmocka_unit_test(test_quadratic_mean_exact),
        cmocka_unit_test(test_range_vs_grid_posterior),
        cmocka_unit_test(test_cholesky_known),
        cmocka_unit_test(test_congruence_known),
        cmocka_unit_test(test_failures_keep_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
