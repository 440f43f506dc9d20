/**
 * @file diff3d.h
 * @brief 3-D distributed-accelerometer differencing: six tri-axis
 *        accelerometers at +-a, +-b, +-c along the platform (body) axes ->
 *        the full gradient tensor, the centre specific force, the angular
 *        acceleration, and parity residuals.
 *
 * Layout (Welker, Pachter & Huffman, Fig. 1: six three-axis accelerometers):
 *   sensor 0 at (+a,0,0), 1 at (0,+b,0), 2 at (0,0,+c),
 *   sensor 3 at (-a,0,0), 4 at (0,-b,0), 5 at (0,0,-c),  readings in body axes.
 * On a rigid body rotating at Omega with angular acceleration Omega' (body
 * axes), an accelerometer at offset d reads (Gao et al., eqs. 20-24)
 *   f(d) = f_c + (W - Gamma) d + O(d^2),  W = [Omega' x] + [Omega x][Omega x],
 * so the differenced readings give, column by column,
 *   M[:,k] = (f(+d_k) - f(-d_k)) / (2 d_k) = (W - Gamma)[:,k]       (Gao eq. 24/25)
 * Gamma and [Omega x]^2 are symmetric and [Omega' x] antisymmetric (Gao eq. 26-27):
 *   Gamma = [Omega x]^2 - (M + M^T)/2        (Omega from the gyros)
 *   [Omega' x] = (M - M^T)/2                 (the measured angular acceleration)
 * On the space-stabilized platform Omega = Omega' = 0: the antisymmetric
 * part must vanish (three parity residuals) and, outside masses, the trace
 * of Gamma too (a fourth) - what later detects a faulty accelerometer.
 * The centre specific force is the mean of the six (the rotation terms
 * cancel pair by pair). Readings are hi/lo pairs as in diff2d.h.
 * Note: Gao et al.'s eq. 30 writes the strapdown measurement with the
 * opposite overall sign to their eqs. 24-27; this module follows 24-27.
 */
#ifndef GGINS_DIFF3D_H
#define GGINS_DIFF3D_H

#include "ggins/real.h"
#include "ggins/status.h"

typedef struct {
    gg_real_t half_base_m[3]; /**< a, b, c: half-baselines along x, y, z, m (> 0) */
} gg_diff3d_config_t;

typedef struct {
    gg_diff3d_config_t cfg;
    int initialized;
} gg_diff3d_t;

typedef struct {
    double f[6][3];         /**< readings, body axes, m/s^2 (sensor order above) */
    double f_lo[6][3];      /**< sub-ulp residuals, m/s^2 */
    gg_real_t omega_b[3];   /**< body angular rate from the gyros, rad/s (0 on a stabilized platform) */
} gg_diff3d_input_t;

typedef struct {
    gg_real_t gamma[3][3];  /**< gradient dG_j/dx_k, body axes, s^-2 (symmetric) */
    gg_real_t f_c[3];       /**< centre specific force, body axes, m/s^2 */
    gg_real_t omega_dot[3]; /**< angular acceleration from the antisymmetric part, rad/s^2 */
    gg_real_t trace;        /**< trace of gamma, s^-2 (parity: 0 outside masses) */
} gg_diff3d_output_t;

gg_status_t gg_diff3d_init(gg_diff3d_t *st, const gg_diff3d_config_t *cfg);

/** GG_ERR_NONFINITE on NaN/Inf input (out untouched). */
gg_status_t gg_diff3d_step(const gg_diff3d_t *st, const gg_diff3d_input_t *in,
                           gg_diff3d_output_t *out);

#endif /* GGINS_DIFF3D_H */
