/**
 * @file gravdr.h
 * @brief Gravity dead reckoning: G(t) = G(0) + integral of Gamma dr
 *        (Welker, Pachter & Huffman, section IV, eqs. 5-6).
 *
 * Per step k -> k+1, with dr_k = r_{k+1} - r_k:
 *   G_{k+1} = G_k + 1/2 (Gamma_k + Gamma_{k+1}) dr_k                 (trapezoid)
 *           + 1/12 [ (Gamma_{k+1} - Gamma_k)(dr_k - dr_{k-1})
 *                    - (Gamma_{k+1} - 2 Gamma_k + Gamma_{k-1}) dr_k ]  (end correction)
 * Using the displacement rather than Gamma*v*dt keeps G consistent with the
 * position at the end of the step. The trapezoid alone leaves a systematic
 * error of -(h^3/12)(Gamma'' v - Gamma' v') per step (h = step, primes =
 * time derivatives along the path): for the 300 m/s flight at 100 Hz that is
 * ~8e-19 m/s^2 a step, 3e-13 m/s^2 an hour, above the 1e-13 budget. The end
 * correction (Euler-Maclaurin, with the time derivatives taken as finite
 * differences of the last three gradients and displacements, centred one
 * half-step early) leaves a local error of O(h^4): third order globally
 * (measured: 8x per halving; 9e-19 m/s^2 after the 1 h, 100 Hz flight).
 * It needs one earlier step, so the first step is a plain trapezoid. Its sum over steps telescopes, so it does not accumulate
 * gradient noise or bias. G is held in compensated accumulators (real.h).
 * Frame: whatever frame Gamma and dr are given in (inertial for the
 * space-stabilized platform). Vectors are 3-D (index 0 = x, 1 = y, 2 = z).
 */
#ifndef GGINS_GRAVDR_H
#define GGINS_GRAVDR_H

#include "ggins/real.h"
#include "ggins/status.h"

typedef struct {
    gg_real_t g0[3];           /**< gravitation at the start point, m/s^2 */
    gg_real_t gamma0[3][3];    /**< gradient at the start point, s^-2 */
    int trapezoid_only;        /**< 1: plain trapezoid (paper-literal, 2nd order); 0: corrected (default) */
} gg_gravdr_config_t;

typedef struct {
    gg_acc_t g[3];             /**< dead-reckoned gravitation, m/s^2 */
    gg_real_t gamma[3][3];     /**< gradient at the current point k, s^-2 */
    gg_real_t gamma_prev[3][3];/**< gradient at point k-1, s^-2 */
    gg_real_t dr_prev[3];      /**< displacement of step k-1 -> k, m */
    int have_prev;             /**< gamma_prev / dr_prev valid */
    int trapezoid_only;
    int initialized;
} gg_gravdr_t;

/** Start from a known G and Gamma. GG_ERR_CONFIG on non-finite values. */
gg_status_t gg_gravdr_init(gg_gravdr_t *st, const gg_gravdr_config_t *cfg);

/** Advance over one step with displacement dr (m) to a point where the
 *  gradient is gamma_new. GG_ERR_NONFINITE leaves the state untouched. */
gg_status_t gg_gravdr_step(gg_gravdr_t *st, const gg_real_t gamma_new[3][3],
                           const gg_real_t dr[3]);

/** Add dg (m/s^2) to G: keeps G consistent with a position correction dr
 *  applied elsewhere (dg = Gamma dr). GG_ERR_NONFINITE leaves the state untouched. */
gg_status_t gg_gravdr_correct(gg_gravdr_t *st, const gg_real_t dg[3]);

/** Current G (m/s^2), rounded to working precision. */
gg_status_t gg_gravdr_get(const gg_gravdr_t *st, gg_real_t g[3]);

/** Current G as compensated values (hi + lo), for sums that must not lose it. */
gg_status_t gg_gravdr_get_acc(const gg_gravdr_t *st, gg_acc_t g[3]);

#endif /* GGINS_GRAVDR_H */
