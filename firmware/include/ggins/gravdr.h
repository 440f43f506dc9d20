/**
 * @file gravdr.h
 * @brief Gravity dead reckoning: G(t) = G(0) + integral of Gamma dr
 *        (Welker, Pachter & Huffman, section IV, eqs. 5-6).
 *
 * Per step: G_{k+1} = G_k + 1/2 (Gamma_k + Gamma_{k+1}) (r_{k+1} - r_k),
 * i.e. the trapezoidal rule along the step's chord. Using the displacement
 * rather than Gamma*v*dt keeps G consistent with the position at the end of
 * the step. G is held in compensated accumulators (real.h).
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
} gg_gravdr_config_t;

typedef struct {
    gg_acc_t g[3];             /**< dead-reckoned gravitation, m/s^2 */
    gg_real_t gamma[3][3];     /**< gradient at the current point, s^-2 */
    int initialized;
} gg_gravdr_t;

/** Start from a known G and Gamma. GG_ERR_CONFIG on non-finite values. */
gg_status_t gg_gravdr_init(gg_gravdr_t *st, const gg_gravdr_config_t *cfg);

/** Advance over one step with displacement dr (m) to a point where the
 *  gradient is gamma_new. GG_ERR_NONFINITE leaves the state untouched. */
gg_status_t gg_gravdr_step(gg_gravdr_t *st, const gg_real_t gamma_new[3][3],
                           const gg_real_t dr[3]);

/** Current G (m/s^2), rounded to working precision. */
gg_status_t gg_gravdr_get(const gg_gravdr_t *st, gg_real_t g[3]);

#endif /* GGINS_GRAVDR_H */
