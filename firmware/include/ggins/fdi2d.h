/**
 * @file fdi2d.h
 * @brief Fault detection, isolation and accommodation for the four dual-axis
 *        accelerometers of the 2-D platform, from the redundancy of their
 *        readings.
 *
 * Eight readings measure six things (two centre specific forces, four
 * gradient components), so three parity relations hold for any field and
 * any motion, up to the finite-baseline curvature terms, which the caller
 * supplies as the expected residuals p_exp (for p_x, p_z; ~3e-13 m/s^2 at
 * 0.5 m; gg_fdi2d_expected_parity computes them for a point-mass field):
 *   p_x = ((f1x + f3x) - (f2x + f4x)) / 2        [m/s^2]  both pairs see the same mean
 *   p_z = ((f1z + f3z) - (f2z + f4z)) / 2        [m/s^2]
 *   p_s = Gxz - Gzx = (f4x - f2x)/2b - (f3z - f1z)/2a   [s^-2]  a gradient is symmetric
 * A fault d on one reading moves them along its signature:
 *   f1x (+1/2, 0, 0)       f2x (-1/2, 0, -1/2b)    f3x (+1/2, 0, 0)      f4x (-1/2, 0, +1/2b)
 *   f1z (0, +1/2, +1/2a)   f2z (0, -1/2, 0)        f3z (0, +1/2, -1/2a)  f4z (0, -1/2, 0)
 * so 2x, 4x, 1z and 3z are isolable; 1x/3x and 2z/4z are not told apart
 * (same signature): the geometry allows no more.
 *
 * Accommodation (degraded modes), by synthesising readings so that the
 * differencing downstream needs no special case:
 *  - a reading known bad (sensor status, NaN/Inf, out of range) or isolated
 *    (and then excluded for the rest of the run) is rebuilt from its group's
 *    parity relation, e.g. f2x := f1x + f3x - f4x - 2 p_x,exp (with p = 0
 *    the curvature term would go into the gradient); one per axis group;
 *  - a fault isolated only to a pair (1x/3x or 2z/4z): the centre force of
 *    that axis comes from the other pair, and Gxx (or Gzz) coasts on its
 *    last good value;
 *  - a group that lost more readings than its parity relation can rebuild
 *    (two or more known bad or excluded, e.g. 2x excluded and 4x NaN) is
 *    degraded: each of its three quantities - the centre mean, the diagonal
 *    difference (x: Gxx from 1x/3x; z: Gzz from 2z/4z) and the off-diagonal
 *    difference (x: Gxz from 2x/4x; z: Gzx from 1z/3z) - comes from its own
 *    usable readings where a whole pair (or, for the centre mean, one reading
 *    and the pair's difference) is left, the off-diagonal otherwise from the
 *    symmetry of the gradient (Gxz = Gzx, from the other group's pair), and
 *    otherwise from its value of the last frame used (held: GRAD_COAST for a
 *    gradient component, HOLD_FORCE for the centre specific force); the four
 *    readings are then synthesised consistently (GG_FDI_DEGRADED);
 *  - residuals that no single reading explains (several faults at once):
 *    every reading of the parity tests that fired is suspect on that frame
 *    (GG_FDI_SUSPECT), and so is the whole group of a suspect whose own group
 *    test passed (a second fault may cancel in it: two stuck z readings
 *    leave p_z at 0) or which holds a rebuilt reading (built from all the
 *    others); the groups are rebuilt or degraded as above. Conservative: the
 *    error is then that of the held components, whatever the faults' size;
 *    only before a first frame was used (nothing to hold) is the set refused.
 * Error of a held component: it drifts with the field along the path,
 * |dGamma/dt| <= |grad Gamma| |v| (point mass: 3 GM/r^4 |v| = 2.2e-10 s^-2/s
 * at 300 m/s near the Earth's surface), so G errs by <= 1/2 (3 GM/r^4) |v|^2 t^2
 * and the position by <= 1/24 (3 GM/r^4) |v|^2 t^4 after t seconds held; a
 * held centre force drifts with the vehicle's turn rate (|f| |omega| t). In
 * gravity-model mode G does not depend on the gradient at all.
 * Detection thresholds come from the configuration; a threshold of 0 turns
 * that parity check off.
 */
#ifndef GGINS_FDI2D_H
#define GGINS_FDI2D_H

#include <stdint.h>
#include "ggins/diff2d.h"
#include "ggins/real.h"
#include "ggins/status.h"

/** Reading index in masks: bit (2 * sensor + axis), sensor 0..3 = paper's 1..4, axis 0 = x, 1 = z. */
#define GG_FDI_BIT(sensor, axis) (1u << ((2u * (uint32_t)(sensor)) + (uint32_t)(axis)))

typedef struct {
    gg_real_t a_m;          /**< half-baseline along x, m (> 0) */
    gg_real_t b_m;          /**< half-baseline along z, m (> 0) */
    double parity_f_max;    /**< |p_x|, |p_z| detection threshold, m/s^2 (0: off) */
    double asym_max;        /**< |p_s| detection threshold, s^-2 (0: off) */
} gg_fdi2d_config_t;

typedef struct {
    gg_fdi2d_config_t cfg;
    uint32_t excluded;      /**< readings isolated as faulty, latched (GG_FDI_BIT mask) */
    gg_real_t held[2][3];   /**< per axis group (0 = x, 1 = z) of the last frame used: the
                                 centre mean of pair 1/3, the differences r3 - r1 and r4 - r2,
                                 m/s^2 (what a degraded group holds) */
    int have_good;
    int initialized;
} gg_fdi2d_t;

/** Outcome flags. */
#define GG_FDI_DETECTED   0x01u /**< a parity check exceeded its threshold this step */
#define GG_FDI_REBUILT    0x02u /**< one or more readings rebuilt from parity (degraded) */
#define GG_FDI_COAST_GXX  0x04u /**< Gxx coasting on its last good value (1x/3x ambiguous) */
#define GG_FDI_COAST_GZZ  0x08u /**< Gzz coasting likewise (2z/4z ambiguous) */
#define GG_FDI_NEW_EXCL   0x10u /**< a reading was newly isolated and excluded this step */
#define GG_FDI_DEGRADED   0x20u /**< a group lost more readings than parity rebuilds: synthesised */
#define GG_FDI_HOLD_FORCE 0x40u /**< a centre specific force held (no reading of that axis usable) */
#define GG_FDI_COAST_OFFD 0x80u /**< an off-diagonal gradient held (neither its pair nor symmetry) */
#define GG_FDI_SUSPECT    0x100u /**< residuals fit no single reading: the tested ones set aside */

typedef struct {
    gg_real_t p_x;          /**< parity residuals less the expected ones, before accommodation: m/s^2 */
    gg_real_t p_z;
    gg_real_t p_s;          /**< s^-2 */
    uint32_t flags;         /**< GG_FDI_* */
    uint32_t excluded;      /**< latched exclusions after this step */
    uint32_t rebuilt;       /**< readings rebuilt this step (known bad or excluded) */
} gg_fdi2d_output_t;

gg_status_t gg_fdi2d_init(gg_fdi2d_t *st, const gg_fdi2d_config_t *cfg);

/** Check and accommodate one set of readings in place. known_bad: readings
 *  the caller already knows are unusable (their values are ignored); p_exp:
 *  expected p_x, p_z (m/s^2). GG_ERR_SENSOR when the set cannot be
 *  accommodated (only before a first set was used: nothing to hold; in
 *  untouched, state untouched); GG_ERR_NONFINITE if a
 *  reading not marked known_bad, or p_exp, is not finite. */
gg_status_t gg_fdi2d_step(gg_fdi2d_t *st, uint32_t known_bad, const gg_real_t p_exp[2],
                          gg_diff2d_input_t *in, gg_fdi2d_output_t *out);

/** Expected parity residuals p_x, p_z (m/s^2) of the 2-D geometry at
 *  position r (m, axes 0 = x, 2 = z) in a point-mass field of parameter
 *  mu = GM (m^3/s^2): with D_ijk = d3(mu/r)/dx_i dx_j dx_k =
 *  mu (-15 x_i x_j x_k / r^7 + 3 (x_i d_jk + x_j d_ik + x_k d_ij) / r^5),
 *  each pair's mean is a - G - (half-baseline^2 / 2) D_i,kk, so
 *  p_i = -(a^2 D_ixx - b^2 D_izz) / 2. (Field beyond the point mass changes
 *  it by ~1e-3 relative: ~1e-16 m/s^2.) */
gg_status_t gg_fdi2d_expected_parity(gg_real_t a_m, gg_real_t b_m, gg_real_t mu,
                                     const gg_real_t r[3], gg_real_t p_exp[2]);

#endif /* GGINS_FDI2D_H */
