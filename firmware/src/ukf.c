/* Unscented Kalman filter core (see ukf.h). */
/* MISRA notes (inline suppressions below): 17.7 is a cppcheck 2.10 false positive on the
 * array-pointer casts (const double(*)[N]) required to pass a non-const matrix to a const
 * parameter in C11 (the cast is parsed as a call whose value is discarded; every returned
 * status is checked). */
#include "ggins/ukf.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define NX GG_UKF_NX_MAX
#define NZ GG_UKF_NZ_MAX

static double usqrt(double v)
{
    return (double)sqrtl((long double)v);
}

static int finite_d(double v)
{
    return isfinite(v) ? 1 : 0;
}

gg_status_t gg_ukf_cholesky(int32_t n, const double A[NX][NX], double L[NX][NX])
{
    if ((A == NULL) || (L == NULL)) {
        return GG_ERR_NULL;
    }
    if ((n < 1) || (n > NX)) {
        return GG_ERR_CONFIG;
    }
    double dmax = 0.0;
    for (int32_t i = 0; i < n; ++i) {
        if (!finite_d(A[i][i])) {
            return GG_ERR_RANGE;
        }
        if (A[i][i] > dmax) {
            dmax = A[i][i];
        }
    }
    if (!(dmax > 0.0)) {
        return GG_ERR_RANGE;
    }
    double T[NX][NX];
    (void)memset(T, 0, sizeof T);
    for (int32_t j = 0; j < n; ++j) {
        double d = A[j][j];
        for (int32_t k = 0; k < j; ++k) {
            d -= T[j][k] * T[j][k];
        }
        /* pivot relative to its own diagonal element: the states may differ in
         * scale by many orders (bias variances ~1e-15 beside position ~1e2) */
        if (!finite_d(d) || !(A[j][j] > 0.0) || (d <= (GG_UKF_PIVOT_MIN * A[j][j]))) {
            return GG_ERR_RANGE;
        }
        const double ljj = usqrt(d);
        T[j][j] = ljj;
        for (int32_t i = j + 1; i < n; ++i) {
            double s = A[i][j];
            for (int32_t k = 0; k < j; ++k) {
                s -= T[i][k] * T[j][k];
            }
            T[i][j] = s / ljj;
            if (!finite_d(T[i][j])) {
                return GG_ERR_RANGE;
            }
        }
    }
    (void)memcpy(L, T, sizeof T);
    return GG_OK;
}

/* Cholesky of a small nz x nz matrix (same algorithm, own storage). */
gg_status_t gg_ukf_congruence(int32_t n, const double T[NX][NX], const double S[NX][NX], double O[NX][NX])
{
    if ((T == NULL) || (S == NULL) || (O == NULL)) {
        return GG_ERR_NULL;
    }
    if ((n < 1) || (n > NX)) {
        return GG_ERR_CONFIG;
    }
    double U[NX][NX];
    for (int32_t j = 0; j < n; ++j) {
        for (int32_t k = 0; k < n; ++k) {
            double s = 0.0;
            for (int32_t l = 0; l < n; ++l) {
                s += T[j][l] * S[l][k];
            }
            U[j][k] = s;
        }
    }
    for (int32_t j = 0; j < n; ++j) {
        for (int32_t k = 0; k < n; ++k) {
            double s = 0.0;
            for (int32_t l = 0; l < n; ++l) {
                s += U[j][l] * T[k][l];
            }
            O[j][k] = s;
        }
    }
    return GG_OK;
}

static gg_status_t chol_nz(int32_t n, const double A[NZ][NZ], double L[NZ][NZ])
{
    double B[NX][NX];
    double T[NX][NX];
    (void)memset(B, 0, sizeof B);
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t j = 0; j < n; ++j) {
            B[i][j] = A[i][j];
        }
    }
    /* cppcheck-suppress misra-c2012-17.7 */
    const gg_status_t s = gg_ukf_cholesky(n, (const double(*)[NX])B, T);
    if (s != GG_OK) {
        return s;
    }
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t j = 0; j < n; ++j) {
            L[i][j] = T[i][j];
        }
    }
    return GG_OK;
}

static void weights(const gg_ukf_config_t *cfg, double *w0, double *wi, double *c)
{
    const double nl = (double)cfg->nx + cfg->lambda;
    *w0 = cfg->lambda / nl;
    *wi = 0.5 / nl;
    *c = usqrt(nl);
}

gg_status_t gg_ukf_init(gg_ukf_t *st, const gg_ukf_config_t *cfg, const double *x0,
                        const double P0[NX][NX])
{
    if ((st == NULL) || (cfg == NULL) || (x0 == NULL) || (P0 == NULL)) {
        return GG_ERR_NULL;
    }
    if ((cfg->nx < 1) || (cfg->nx > NX) || !finite_d(cfg->lambda) || (cfg->lambda < 0.0) ||
        (cfg->lambda > 1.0e3) || !finite_d(cfg->gate_nis)) {
        return GG_ERR_CONFIG;
    }
    const int32_t n = cfg->nx;
    for (int32_t i = 0; i < n; ++i) {
        if (!finite_d(x0[i])) {
            return GG_ERR_NONFINITE;
        }
        for (int32_t j = 0; j < n; ++j) {
            if (!finite_d(P0[i][j])) {
                return GG_ERR_NONFINITE;
            }
            if (P0[i][j] != P0[j][i]) {
                return GG_ERR_RANGE;
            }
        }
    }
    double L[NX][NX];
    if (gg_ukf_cholesky(n, P0, L) != GG_OK) {
        return GG_ERR_RANGE;
    }
    (void)memset(st, 0, sizeof *st);
    st->cfg = *cfg;
    for (int32_t i = 0; i < n; ++i) {
        st->x[i] = x0[i];
        for (int32_t j = 0; j < n; ++j) {
            st->P[i][j] = P0[i][j];
        }
    }
    (void)memcpy(st->L, L, sizeof L);
    st->initialized = 1;
    return GG_OK;
}

/* Sigma points of (x, L) into chi. */
static void draw(const gg_ukf_t *st, double chi[GG_UKF_NSIG_MAX][NX])
{
    const int32_t n = st->cfg.nx;
    double w0;
    double wi;
    double c;
    weights(&st->cfg, &w0, &wi, &c);
    for (int32_t k = 0; k < n; ++k) {
        chi[0][k] = st->x[k];
    }
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t k = 0; k < n; ++k) {
            const double d = c * st->L[k][i];
            chi[1 + i][k] = st->x[k] + d;
            chi[1 + n + i][k] = st->x[k] - d;
        }
    }
}

gg_status_t gg_ukf_sigma_points(gg_ukf_t *st, int32_t *nsig)
{
    if ((st == NULL) || (nsig == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    draw(st, st->chi);
    st->sigma_ready = 1;
    *nsig = (2 * st->cfg.nx) + 1;
    return GG_OK;
}

/* Commit a new mean and covariance with the covariance's Cholesky factor; a
 * covariance that is not positive definite is counted (GG_UKF_H_CHOL_FAIL) and
 * leaves the state as it was. */
static gg_status_t commit(gg_ukf_t *st, int32_t n, const double x[NX], const double P[NX][NX])
{
    double L[NX][NX];
    if (gg_ukf_cholesky(n, P, L) != GG_OK) {
        st->health = GG_UKF_H_CHOL_FAIL;
        st->n_chol_fail++;
        return GG_ERR_RANGE;
    }
    (void)memcpy(st->x, x, sizeof(double) * (size_t)NX);
    (void)memcpy(st->P, P, sizeof(double) * (size_t)NX * (size_t)NX);
    (void)memcpy(st->L, L, sizeof L);
    st->health = 0u;
    return GG_OK;
}

gg_status_t gg_ukf_predict_finish(gg_ukf_t *st, const double Q[NX][NX])
{
    if ((st == NULL) || (Q == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (st->sigma_ready == 0) {
        return GG_ERR_SEQUENCE;
    }
    const int32_t n = st->cfg.nx;
    const int32_t ns = (2 * n) + 1;
    double w0;
    double wi;
    double c;
    weights(&st->cfg, &w0, &wi, &c);
    for (int32_t i = 0; i < ns; ++i) {
        for (int32_t k = 0; k < n; ++k) {
            if (!finite_d(st->chi[i][k])) {
                st->health = GG_UKF_H_MODEL;
                st->n_model_fail++;
                st->sigma_ready = 0;
                return GG_ERR_NONFINITE;
            }
        }
    }
    for (int32_t i = 0; i < n; ++i) {
        for (int32_t j = 0; j < n; ++j) {
            if (!finite_d(Q[i][j]) || (Q[i][j] != Q[j][i])) {
                st->health = GG_UKF_H_INPUT;
                st->sigma_ready = 0;
                return GG_ERR_RANGE;
            }
        }
    }
    double x[NX];
    double P[NX][NX];
    (void)memset(x, 0, sizeof x);
    (void)memset(P, 0, sizeof P);
    for (int32_t k = 0; k < n; ++k) {
        double s = 0.0;
        for (int32_t i = 1; i < ns; ++i) {
            s += st->chi[i][k];
        }
        x[k] = (w0 * st->chi[0][k]) + (wi * s);
    }
    for (int32_t i = 0; i < ns; ++i) {
        const double w = (i == 0) ? w0 : wi;
        if (w == 0.0) {
            continue;
        }
        double d[NX];
        for (int32_t k = 0; k < n; ++k) {
            d[k] = st->chi[i][k] - x[k];
        }
        for (int32_t a = 0; a < n; ++a) {
            for (int32_t b = a; b < n; ++b) {
                P[a][b] += w * d[a] * d[b];
            }
        }
    }
    for (int32_t a = 0; a < n; ++a) {
        for (int32_t b = a; b < n; ++b) {
            P[a][b] += Q[a][b];
            P[b][a] = P[a][b];
        }
    }
    st->sigma_ready = 0;
    {
        /* cppcheck-suppress misra-c2012-17.7 */
        const gg_status_t sc = commit(st, n, x, (const double(*)[NX])P);
        if (sc != GG_OK) {
            return sc;
        }
    }
    return GG_OK;
}

gg_status_t gg_ukf_predict(gg_ukf_t *st, gg_ukf_fx_t f, void *ctx, const double Q[NX][NX])
{
    if ((st == NULL) || (f == NULL) || (Q == NULL)) {
        return GG_ERR_NULL;
    }
    int32_t ns = 0;
    gg_status_t s = gg_ukf_sigma_points(st, &ns);
    if (s != GG_OK) {
        return s;
    }
    for (int32_t i = 0; i < ns; ++i) {
        double out[NX];
        (void)memset(out, 0, sizeof out);
        s = f(ctx, st->chi[i], out);
        if (s != GG_OK) {
            st->health = GG_UKF_H_MODEL;
            st->n_model_fail++;
            st->sigma_ready = 0;
            return s;
        }
        (void)memcpy(st->chi[i], out, sizeof out);
    }
    return gg_ukf_predict_finish(st, Q);
}

/* forward substitution L y = b (n x n lower) */
static void fwd(int32_t n, const double L[NZ][NZ], const double *b, double *y)
{
    for (int32_t i = 0; i < n; ++i) {
        double s = b[i];
        for (int32_t k = 0; k < i; ++k) {
            s -= L[i][k] * y[k];
        }
        y[i] = s / L[i][i];
    }
}

/* back substitution L^T y = b */
static void bwd(int32_t n, const double L[NZ][NZ], const double *b, double *y)
{
    for (int32_t i = n - 1; i >= 0; --i) {
        double s = b[i];
        for (int32_t k = i + 1; k < n; ++k) {
            s -= L[k][i] * y[k];
        }
        y[i] = s / L[i][i];
    }
}

/* Draw the sigma points of the current mean and covariance and pass each
 * through h into st->zeta. A model error or a non-finite output is counted
 * (GG_UKF_H_MODEL) and returned. */
static gg_status_t sigma_measure(gg_ukf_t *st, int32_t nz, gg_ukf_hx_t h, void *ctx)
{
    const int32_t ns = (2 * st->cfg.nx) + 1;
    draw(st, st->chi);
    st->sigma_ready = 0;
    for (int32_t i = 0; i < ns; ++i) {
        double zz[NZ];
        (void)memset(zz, 0, sizeof zz);
        const gg_status_t s = h(ctx, st->chi[i], zz);
        int32_t ok = 0;
        if (s == GG_OK) {
            ok = 1;
        }
        for (int32_t k = 0; k < nz; ++k) {
            if (!finite_d(zz[k])) {
                ok = 0;
            }
        }
        if (ok == 0) {
            st->health = GG_UKF_H_MODEL;
            st->n_model_fail++;
            return (s != GG_OK) ? s : GG_ERR_NONFINITE;
        }
        (void)memcpy(st->zeta[i], zz, sizeof zz);
    }
    return GG_OK;
}

gg_status_t gg_ukf_update(gg_ukf_t *st, int32_t nz, const double *z, const double R[NZ][NZ],
                          gg_ukf_hx_t h, void *ctx, gg_ukf_update_info_t *info)
{
    if ((st == NULL) || (z == NULL) || (R == NULL) || (h == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if ((nz < 1) || (nz > NZ)) {
        st->health = GG_UKF_H_INPUT;
        return GG_ERR_CONFIG;
    }
    for (int32_t i = 0; i < nz; ++i) {
        if (!finite_d(z[i])) {
            st->health = GG_UKF_H_INPUT;
            return GG_ERR_NONFINITE;
        }
        for (int32_t j = 0; j < nz; ++j) {
            if (!finite_d(R[i][j]) || (R[i][j] != R[j][i])) {
                st->health = GG_UKF_H_INPUT;
                return GG_ERR_RANGE;
            }
        }
    }
    const int32_t n = st->cfg.nx;
    const int32_t ns = (2 * n) + 1;
    double w0;
    double wi;
    double c;
    weights(&st->cfg, &w0, &wi, &c);
    {
        const gg_status_t sm = sigma_measure(st, nz, h, ctx);
        if (sm != GG_OK) {
            return sm;
        }
    }
    double zm[NZ];
    (void)memset(zm, 0, sizeof zm);
    for (int32_t k = 0; k < nz; ++k) {
        double s = 0.0;
        for (int32_t i = 1; i < ns; ++i) {
            s += st->zeta[i][k];
        }
        zm[k] = (w0 * st->zeta[0][k]) + (wi * s);
    }
    double S[NZ][NZ];
    double C[NX][NZ];
    (void)memset(S, 0, sizeof S);
    (void)memset(C, 0, sizeof C);
    for (int32_t i = 0; i < ns; ++i) {
        const double w = (i == 0) ? w0 : wi;
        if (w == 0.0) {
            continue;
        }
        double dz[NZ];
        double dx[NX];
        for (int32_t k = 0; k < nz; ++k) {
            dz[k] = st->zeta[i][k] - zm[k];
        }
        for (int32_t k = 0; k < n; ++k) {
            dx[k] = st->chi[i][k] - st->x[k];
        }
        for (int32_t a = 0; a < nz; ++a) {
            for (int32_t b = a; b < nz; ++b) {
                S[a][b] += w * dz[a] * dz[b];
            }
        }
        for (int32_t a = 0; a < n; ++a) {
            for (int32_t b = 0; b < nz; ++b) {
                C[a][b] += w * dx[a] * dz[b];
            }
        }
    }
    for (int32_t a = 0; a < nz; ++a) {
        for (int32_t b = a; b < nz; ++b) {
            S[a][b] += R[a][b];
            S[b][a] = S[a][b];
        }
    }
    double LS[NZ][NZ];
    /* cppcheck-suppress misra-c2012-17.7 */
    if (chol_nz(nz, (const double(*)[NZ])S, LS) != GG_OK) {
        st->health = GG_UKF_H_CHOL_FAIL;
        st->n_chol_fail++;
        return GG_ERR_RANGE;
    }
    double nu[NZ];
    double y[NZ];
    (void)memset(nu, 0, sizeof nu);
    for (int32_t k = 0; k < nz; ++k) {
        nu[k] = z[k] - zm[k];
    }
    /* cppcheck-suppress misra-c2012-17.7 */
    fwd(nz, (const double(*)[NZ])LS, nu, y);
    double nis = 0.0;
    for (int32_t k = 0; k < nz; ++k) {
        nis += y[k] * y[k];
    }
    if (info != NULL) {
        (void)memset(info, 0, sizeof *info);
        info->nis = nis;
        for (int32_t k = 0; k < nz; ++k) {
            info->innov[k] = nu[k];
            info->s_diag[k] = S[k][k];
        }
    }
    if ((st->cfg.gate_nis > 0.0) && !(nis <= st->cfg.gate_nis)) {
        st->health = GG_UKF_H_GATED;
        st->n_gated++;
        return GG_OK;
    }
    /* K = C S^-1 (row by row: S k_a = c_a), U = K L_S */
    double K[NX][NZ];
    double U[NX][NZ];
    for (int32_t a = 0; a < n; ++a) {
        double t[NZ];
        double ka[NZ];
        /* cppcheck-suppress misra-c2012-17.7 */
        fwd(nz, (const double(*)[NZ])LS, C[a], t);
        /* cppcheck-suppress misra-c2012-17.7 */
        bwd(nz, (const double(*)[NZ])LS, t, ka);
        for (int32_t b = 0; b < nz; ++b) {
            K[a][b] = ka[b];
        }
        /* U = K L_S = C L_S^-T: row a of U is t (L_S t = c_a) */
        for (int32_t b = 0; b < nz; ++b) {
            U[a][b] = t[b];
        }
    }
    double x[NX];
    double P[NX][NX];
    (void)memset(x, 0, sizeof x);
    (void)memset(P, 0, sizeof P);
    for (int32_t a = 0; a < n; ++a) {
        double s = 0.0;
        for (int32_t b = 0; b < nz; ++b) {
            s += K[a][b] * nu[b];
        }
        x[a] = st->x[a] + s;
    }
    for (int32_t a = 0; a < n; ++a) {
        for (int32_t b = a; b < n; ++b) {
            double s = 0.0;
            for (int32_t k = 0; k < nz; ++k) {
                s += U[a][k] * U[b][k];
            }
            P[a][b] = st->P[a][b] - s;
            P[b][a] = P[a][b];
        }
    }
    {
        /* cppcheck-suppress misra-c2012-17.7 */
        const gg_status_t sc = commit(st, n, x, (const double(*)[NX])P);
        if (sc != GG_OK) {
            return sc;
        }
    }
    st->n_updates++;
    if (info != NULL) {
        info->accepted = 1;
    }
    return GG_OK;
}

gg_status_t gg_ukf_set_mean(gg_ukf_t *st, const double *x)
{
    if ((st == NULL) || (x == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (int32_t k = 0; k < st->cfg.nx; ++k) {
        if (!finite_d(x[k])) {
            return GG_ERR_NONFINITE;
        }
    }
    for (int32_t k = 0; k < st->cfg.nx; ++k) {
        st->x[k] = x[k];
    }
    st->sigma_ready = 0;
    return GG_OK;
}

gg_status_t gg_ukf_meas_spread(gg_ukf_t *st, int32_t nz, gg_ukf_hx_t h, void *ctx, double *spread,
                               const double *z, const double R[NZ][NZ], double *nis)
{
    if ((st == NULL) || (h == NULL) || (spread == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if ((nz < 1) || (nz > NZ)) {
        return GG_ERR_CONFIG;
    }
    const int32_t n = st->cfg.nx;
    const int32_t ns = (2 * n) + 1;
    double w0;
    double wi;
    double c;
    double zmean[NZ];
    (void)memset(zmean, 0, sizeof zmean);
    weights(&st->cfg, &w0, &wi, &c);
    {
        const gg_status_t sm = sigma_measure(st, nz, h, ctx);
        if (sm != GG_OK) {
            return sm;
        }
    }
    for (int32_t k = 0; k < nz; ++k) {
        double m = 0.0;
        for (int32_t i = 1; i < ns; ++i) {
            m += st->zeta[i][k];
        }
        m = (w0 * st->zeta[0][k]) + (wi * m);
        double v = 0.0;
        for (int32_t i = 0; i < ns; ++i) {
            const double d = st->zeta[i][k] - m;
            v += ((i == 0) ? w0 : wi) * d * d;
        }
        spread[k] = v;
        zmean[k] = m;
    }
    if ((z != NULL) && (R != NULL) && (nis != NULL)) {
        double S[NZ][NZ];
        double LS[NZ][NZ];
        double nu[NZ];
        double y[NZ];
        (void)memset(S, 0, sizeof S);
        for (int32_t i = 0; i < ns; ++i) {
            const double w = (i == 0) ? w0 : wi;
            for (int32_t a = 0; a < nz; ++a) {
                for (int32_t b = 0; b < nz; ++b) {
                    S[a][b] += w * (st->zeta[i][a] - zmean[a]) * (st->zeta[i][b] - zmean[b]);
                }
            }
        }
        for (int32_t a = 0; a < nz; ++a) {
            for (int32_t b = 0; b < nz; ++b) {
                S[a][b] += R[a][b];
            }
            nu[a] = z[a] - zmean[a];
        }
        /* cppcheck-suppress misra-c2012-17.7 */
        if (chol_nz(nz, (const double(*)[NZ])S, LS) != GG_OK) {
            return GG_ERR_RANGE;
        }
        /* cppcheck-suppress misra-c2012-17.7 */
        fwd(nz, (const double(*)[NZ])LS, nu, y);
        double q = 0.0;
        for (int32_t k = 0; k < nz; ++k) {
            q += y[k] * y[k];
        }
        *nis = q;
    }
    return GG_OK;
}
