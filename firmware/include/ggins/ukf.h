/**
 * @file ukf.h
 * @brief Unscented Kalman filter core: fixed-size (compile-time maximum state
 *        and measurement dimensions), no heap, robust square roots.
 *
 * Used by the map-matching filter (Gao et al., "An Aided
 * Navigation Method Based on Strapdown Gravity Gradiometer", Sensors 21, 829,
 * 2021, section 4) but independent of it: the process and measurement models
 * are supplied by the caller.
 *
 * Unscented transform (symmetric set, Gao eqs. 34-35, 39 generalised by one
 * spread parameter lambda >= 0, Julier & Uhlmann's kappa):
 *   P = L L^T (Cholesky, lower),  c = sqrt(n + lambda),
 *   chi_0 = x,  chi_i = x + c L_{:,i},  chi_{n+i} = x - c L_{:,i}  (i = 1..n),
 *   weights W_0 = lambda/(n + lambda), W_i = 1/(2(n + lambda)) (mean and covariance).
 * lambda = 0 is exactly Gao's set (2n points, weights 1/2n, spread sqrt(n));
 * the central point then has weight 0 and is still computed (it is the
 * propagated mean of a caller that wants it).
 *
 * Prediction (Gao eqs. 36-38): sigma points from (x, P), propagated by the
 * caller (gg_ukf_predict with a model callback, or gg_ukf_sigma_points, then
 * the caller moves st->chi itself, e.g. through many strapdown steps, then
 * gg_ukf_predict_finish):  x = sum W_i chi_i,
 *   P = sum W_i (chi_i - x)(chi_i - x)^T + Q.
 * Update (Gao eqs. 39-44): fresh sigma points from (x, P), zeta_i = h(chi_i),
 *   z^ = sum W_i zeta_i,  S = sum W_i (zeta_i - z^)(...)^T + R,
 *   C = sum W_i (chi_i - x)(zeta_i - z^)^T,  K = C S^-1,  nu = z - z^,
 *   x+ = x + K nu,  P+ = P - (K L_S)(K L_S)^T  with S = L_S L_S^T
 * (eq. 44 written as a symmetric rank-nz downdate: P+ is formed from the
 * product U U^T, U = K L_S, and computed on and above the diagonal then
 * mirrored, so it is exactly symmetric).
 *
 * Robustness: every new covariance (predicted or updated) is Cholesky
 * factorised before it is accepted; if the factorisation fails (a pivot
 * <= GG_UKF_PIVOT_MIN times its own diagonal element A_jj, or not finite; a
 * per-row test because the states may differ in scale by many orders) the
 * operation is rejected: x, P and L keep their previous values, the function
 * returns GG_ERR_RANGE and GG_UKF_H_CHOL_FAIL is set in health. The same holds
 * for S. Innovation gating: the normalised innovation squared
 * NIS = nu^T S^-1 nu is compared with cfg.gate_nis (a chi-square quantile for
 * nz degrees of freedom, e.g. 22.46 = 99.9 % for nz = 6); above it the update
 * is skipped (x, P unchanged), GG_UKF_H_GATED set, and GG_OK returned with
 * info->accepted = 0. A model callback that fails or returns a non-finite
 * value rejects the operation (GG_UKF_H_MODEL).
 * Error contract: on error x, P, L are untouched; health bits and counters
 * record the event. health holds the bits of the last operation; the
 * counters accumulate.
 *
 * Working precision: double (the Cortex-M7 has a double-precision FPU).
 */
#ifndef GGINS_UKF_H
#define GGINS_UKF_H

#include <stdint.h>

#include "ggins/limits.h"
#include "ggins/status.h"

/* array sizes GG_UKF_NX_MAX, GG_UKF_NZ_MAX: limits.h */
#define GG_UKF_NSIG_MAX ((2 * GG_UKF_NX_MAX) + 1)
/** relative pivot threshold of the Cholesky factorisation */
#define GG_UKF_PIVOT_MIN 1.0e-15

/* health bits */
#define GG_UKF_H_CHOL_FAIL 0x01u /**< a covariance was not positive definite: operation rejected */
#define GG_UKF_H_GATED 0x02u     /**< the last update failed the innovation gate: skipped */
#define GG_UKF_H_MODEL 0x04u     /**< a model callback failed or returned a non-finite value */
#define GG_UKF_H_INPUT 0x08u     /**< non-finite measurement, noise or dimension error */

typedef struct {
    int32_t nx;        /**< state dimension, 1..GG_UKF_NX_MAX */
    double lambda;     /**< UT spread (>= 0); 0 = Gao eqs. 35-38 */
    double gate_nis;   /**< NIS gate (chi-square quantile); <= 0 disables gating */
} gg_ukf_config_t;

typedef struct {
    gg_ukf_config_t cfg;
    double x[GG_UKF_NX_MAX];                    /**< state estimate */
    double P[GG_UKF_NX_MAX][GG_UKF_NX_MAX];     /**< covariance (symmetric, PD) */
    double L[GG_UKF_NX_MAX][GG_UKF_NX_MAX];     /**< its Cholesky factor, lower */
    double chi[GG_UKF_NSIG_MAX][GG_UKF_NX_MAX]; /**< sigma points (caller may propagate them) */
    double zeta[GG_UKF_NSIG_MAX][GG_UKF_NZ_MAX];/**< measurement sigma points (work) */
    uint32_t health;                            /**< GG_UKF_H_* of the last operation */
    uint32_t n_updates;                         /**< accepted updates */
    uint32_t n_gated;                           /**< gated (skipped) updates */
    uint32_t n_chol_fail;                       /**< rejected operations: not PD */
    uint32_t n_model_fail;                      /**< rejected operations: model callback */
    int32_t sigma_ready;                        /**< chi holds points drawn by gg_ukf_sigma_points */
    int32_t initialized;
} gg_ukf_t;

/** Result of one update. */
typedef struct {
    int32_t accepted;                     /**< 1 if x, P were updated */
    double nis;                           /**< nu^T S^-1 nu */
    double innov[GG_UKF_NZ_MAX];          /**< nu = z - z^ */
    double s_diag[GG_UKF_NZ_MAX];         /**< diagonal of S */
} gg_ukf_update_info_t;

/** Process model: x_out = f(x_in), both of length GG_UKF_NX_MAX (first nx used). */
typedef gg_status_t (*gg_ukf_fx_t)(void *ctx, const double *x_in, double *x_out);
/** Measurement model: z = h(x), z of length GG_UKF_NZ_MAX (first nz used). */
typedef gg_status_t (*gg_ukf_hx_t)(void *ctx, const double *x, double *z);

/** x0 (nx values), P0[GG_UKF_NX_MAX][GG_UKF_NX_MAX] (top-left nx x nx used,
 *  must be symmetric PD). GG_ERR_CONFIG for bad cfg, GG_ERR_NONFINITE,
 *  GG_ERR_RANGE if P0 is not symmetric positive definite. */
gg_status_t gg_ukf_init(gg_ukf_t *st, const gg_ukf_config_t *cfg, const double *x0,
                        const double P0[GG_UKF_NX_MAX][GG_UKF_NX_MAX]);

/** Draws the 2 nx + 1 sigma points of (x, P) into st->chi; *nsig = 2 nx + 1. */
gg_status_t gg_ukf_sigma_points(gg_ukf_t *st, int32_t *nsig);

/** Mean and covariance from the (propagated) st->chi plus Q (symmetric, nx x nx
 *  used). Needs a preceding gg_ukf_sigma_points. */
gg_status_t gg_ukf_predict_finish(gg_ukf_t *st, const double Q[GG_UKF_NX_MAX][GG_UKF_NX_MAX]);

/** gg_ukf_sigma_points + f on every point + gg_ukf_predict_finish. */
gg_status_t gg_ukf_predict(gg_ukf_t *st, gg_ukf_fx_t f, void *ctx,
                           const double Q[GG_UKF_NX_MAX][GG_UKF_NX_MAX]);

/** Measurement update with nz (1..GG_UKF_NZ_MAX) values z, noise covariance R
 *  (nz x nz used), model h. info may be NULL. */
gg_status_t gg_ukf_update(gg_ukf_t *st, int32_t nz, const double *z,
                          const double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX], gg_ukf_hx_t h, void *ctx,
                          gg_ukf_update_info_t *info);

/** Diagonal of the predicted measurement spread sum W_i (zeta_i - z^)^2 (S
 *  without R) of the model h at the current (x, P); x, P untouched. If z, R
 *  and nis are all non-NULL, *nis = nu^T S^-1 nu with S = spread + R (the NIS
 *  a single update with R would have). Used to schedule progressive
 *  (multi-pass) updates. */
gg_status_t gg_ukf_meas_spread(gg_ukf_t *st, int32_t nz, gg_ukf_hx_t h, void *ctx, double *spread,
                               const double *z, const double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX],
                               double *nis);

/** Replace the mean (nx finite values) keeping P, e.g. the reset of an
 *  error-state filter after the estimate was injected into the nominal state.
 *  Invalidates drawn sigma points. */
gg_status_t gg_ukf_set_mean(gg_ukf_t *st, const double *x);

/** Cholesky factor L (lower) of the symmetric n x n matrix A (A = L L^T), with
 *  the pivot test above. GG_ERR_RANGE when A is not positive definite (L
 *  untouched). Exposed for tests and for the map-matching filter. */
gg_status_t gg_ukf_cholesky(int32_t n, const double A[GG_UKF_NX_MAX][GG_UKF_NX_MAX],
                            double L[GG_UKF_NX_MAX][GG_UKF_NX_MAX]);

/** Congruence O = T S T^T of n x n matrices (n = 1..GG_UKF_NX_MAX, top-left
 *  n x n used): the covariance of T x for x of covariance S. Computed as
 *  U = T S, then O = U T^T, each element a sum over l = 0 .. n-1 in that
 *  order (so a caller that wrote the two products out gets the same bits).
 *  O may be S (S is read only while U is formed), not T. GG_ERR_NULL,
 *  GG_ERR_CONFIG for n out of range (O untouched). */
gg_status_t gg_ukf_congruence(int32_t n, const double T[GG_UKF_NX_MAX][GG_UKF_NX_MAX],
                              const double S[GG_UKF_NX_MAX][GG_UKF_NX_MAX],
                              double O[GG_UKF_NX_MAX][GG_UKF_NX_MAX]);

#endif /* GGINS_UKF_H */
