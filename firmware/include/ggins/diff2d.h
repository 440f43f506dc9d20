/**
 * @file diff2d.h
 * @brief 2-D distributed-accelerometer differencing (Welker, Pachter &
 *        Huffman, section III, eqs. 1-4 and the averages after them).
 *
 * Four dual-axis accelerometers on a space-stabilized platform at offsets
 * 1:(+a,0) 2:(0,+b) 3:(-a,0) 4:(0,-b) in the (x,z) plane. Each reads
 * f_i = a - G(r + d_i). Then (docs/design.md)
 *   Gxx = (f3x - f1x)/2a   Gxz = (f4x - f2x)/2b
 *   Gzx = (f3z - f1z)/2a   Gzz = (f4z - f2z)/2b
 * and the centre specific force is the mean of the four readings.
 * Outputs are 3-D shaped (axis 0 = x, 1 = y unused = 0, 2 = z).
 * Each reading is f + f_lo (hi/lo pair). Differences are formed as
 * (hi - hi) + (lo - lo): the hi parts of neighbouring sensors agree to a
 * few ppm, so their difference is exact (Sterbenz) even where long double
 * is only a double, and the lo parts keep the sub-ulp resolution.
 */
#ifndef GGINS_DIFF2D_H
#define GGINS_DIFF2D_H

#include "ggins/real.h"
#include "ggins/status.h"

typedef struct {
    gg_real_t a_m;       /**< half-baseline along x, m (> 0) */
    gg_real_t b_m;       /**< half-baseline along z, m (> 0) */
} gg_diff2d_config_t;

typedef struct {
    gg_diff2d_config_t cfg;
    int initialized;
} gg_diff2d_t;

typedef struct {
    double f[4][2];      /**< sensors 1..4 at index 0..3; [.][0] = x, [.][1] = z; m/s^2 */
    double f_lo[4][2];   /**< residual of each reading below double resolution, m/s^2 */
} gg_diff2d_input_t;

typedef struct {
    gg_real_t gamma[3][3]; /**< Gamma[j][k] = dG_j/dx_k, s^-2 (y row/column zero) */
    gg_real_t f_c[3];      /**< specific force at the platform centre, m/s^2 */
    gg_real_t asym;        /**< symmetry residual Gxz - Gzx, s^-2 (zero for a true gradient) */
} gg_diff2d_output_t;

/** Check and store the configuration. GG_ERR_CONFIG on a non-positive or non-finite baseline. */
gg_status_t gg_diff2d_init(gg_diff2d_t *st, const gg_diff2d_config_t *cfg);

/** Difference one set of readings. GG_ERR_NONFINITE on NaN/Inf input (out untouched). */
gg_status_t gg_diff2d_step(const gg_diff2d_t *st, const gg_diff2d_input_t *in,
                           gg_diff2d_output_t *out);

#endif /* GGINS_DIFF2D_H */
