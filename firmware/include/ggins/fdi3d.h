/**
 * @file fdi3d.h
 * @brief Fault detection, isolation and accommodation for the six tri-axis
 *        accelerometers of the 3-D platform (diff3d.h layout), from the
 *        redundancy of opposite pairs, the trace and the antisymmetric part.
 *
 * Sensors p and p + 3 (p = 0, 1, 2) sit at +-h_p on body axis p. On a rigid
 * body the rotation terms of a reading are linear in the offset (diff3d.h:
 * f(d) = f_c + (W - Gamma) d + O(d^2)), so each pair's mean
 *   m_p,j = (f_p,j + f_p+3,j) / 2 = f_c,j - (h_p^2 / 2) d2G_j/dx_p^2 + O(h^4)
 * is the centre specific force up to the field's curvature along that axis,
 * whatever the rotation: on each axis j the three pair means agree to the
 * curvature differences (< 1e-12 m/s^2 at 0.6 m near the Earth, anomalies
 * included: GG_FDI3D_FLOOR_MPS2 covers them).
 *
 * Detection (parity_f_max > 0): |m_p,j - m_q,j| above the threshold on any
 * axis. Isolation: with the three pairs of that axis whole, the pair whose
 * mean leaves the other two (which must agree: otherwise a double fault,
 * rejected) carries a fault of size d = 2 (m_p,j - (m_q,j + m_r,j)/2); which
 * of its two sensors, from the column it corrupts in
 * M[:,p] = (f_p - f_p+3) / (2 h_p) (diff3d.h):
 *  - j = p (a reading along its own offset): the trace of Gamma,
 *    -2|w|^2 - tr M, must vanish (Laplace); sensor p moves it by -d/(2 h_p),
 *    sensor p + 3 by +d/(2 h_p);
 *  - j != p: the antisymmetric part (M[j][p] - M[p][j])/2 must equal
 *    [w' x][j][p] - zero on a stabilized platform, the gyro-derived angular
 *    acceleration on a strapdown one; sensor p moves it by +d/(4 h_p),
 *    sensor p + 3 by -d/(4 h_p).
 * The residual must have moved by at least half the expected amount, else the
 * pair is ambiguous. An isolated reading is excluded for good and rebuilt
 * every step; an ambiguous pair-axis is excluded as a pair and both its
 * readings are rebuilt: the mean from the other pairs, the column entry
 * M[j][p] from symmetry, M[j][p] = M[p][j] + 2 [w' x][j][p] (j != p), or from
 * the trace, M[p][p] = -2|w|^2 - sum of the other diagonal entries (j = p).
 *
 * Rebuilding (a reading known unusable - NaN/Inf, out of range, its sensor
 * flagged bad - or excluded): from its partner and the other whole pairs'
 * means on the same axis, keeping the curvature difference the pairs had at
 * the last frame used:
 *   m_p,j := mean over whole pairs q of (m_q,j + (m_p,j - m_q,j)_last),
 *   f_i,j := 2 m_p,j - f_i',j      (i' the partner of i)
 * so the rebuilt reading is right to the change of that difference since.
 *
 * Degraded rebuild (GG_FDI3D_DEGRADED), when more is lost than one reading
 * per pair-axis with the axis' other pairs whole - both readings of a pair,
 * every pair of an axis touched, an excluded pair-axis whose symmetry or
 * trace partner is lost too, or readings set aside for a fault no single
 * reading explains. Twelve quantities make the 18 readings: the nine pair
 * means m_p,j (one centre force per axis up to the kept curvature
 * differences) and the nine column entries M[j][p]. Each is taken from what
 * is left, repeatedly until nothing more follows:
 *  - a whole pair gives its mean and entry;
 *  - a known pair mean on an axis gives the others (differences kept);
 *  - a pair with one usable reading gives its entry from its mean, or its
 *    mean from its entry (f = m +- h M);
 *  - symmetry, M[j][p] = M[p][j] + 2 [w' x][j][p] (j != p; needs the angular
 *    acceleration: stabilized, or the gyro-derived one on a strapdown
 *    platform), and the trace, M[p][p] = -2|w|^2 - the other two;
 * and what still is unknown is held: first the entry of a pair with a usable
 * reading on an axis without any mean (so the reading gives the centre
 * force), then the centre force of an axis without any usable reading
 * (GG_FDI3D_HOLD_FORCE, its last frame's pair means), then any entry
 * (GG_FDI3D_HOLD_GRAD: its last frame's value, or the onboard model's,
 * gg_fdi3d_set_prior). The lost readings are synthesised
 * f_p = m + h_p M[j][p], f_p+3 = m - h_p M[j][p].
 * A fault no single reading or pair explains (detected with fewer than three
 * whole pairs to compare, the other two pairs disagreeing, or an isolation
 * whose residual did not drop) sets aside, for that frame only, the readings
 * it may hide in (GG_FDI3D_SUSPECT): the compared pairs; for two faulty
 * pairs of one axis, or an ambiguous pair exclusion that verification
 * refuses, the whole axis; for a refused reading isolation, its pair and the
 * residual's readings. A set-aside pair of an axis whose two readings agree
 * (to parity_f_max) with its column entry from the symmetry or trace of the
 * usable readings, and whose mean agrees with the other such pairs', is given
 * back: with two faulty pairs on an axis the third is kept, and that axis
 * needs nothing held. Then detection runs again on what is left.
 * What the geometry cannot isolate: an equal fault on every reading of an
 * axis (a change of the centre force: moves nothing); a fault on the partner
 * of a lost reading (its pair has no second reading and detection compares
 * whole pairs only); two faults that move one residual (two diagonal
 * readings, both in the trace, or two readings of one antisymmetric entry):
 * detected, isolated to their pairs, the rebuilt entry then rests on the
 * residual the other fault moves. Only before a first frame was used
 * (nothing to hold) is a set refused: GG_ERR_SENSOR, the frame rejected.
 * Readings are hi/lo pairs.
 */
#ifndef GGINS_FDI3D_H
#define GGINS_FDI3D_H

#include <stdint.h>
#include "ggins/real.h"
#include "ggins/status.h"

/** Reading index in masks: bit (3 * sensor + axis), sensor 0..5, axis 0..2. */
#define GG_FDI3D_BIT(sensor, axis) (1u << ((3u * (uint32_t)(sensor)) + (uint32_t)(axis)))

/** Smallest useful pair-mean threshold, m/s^2: the curvature differences of
 *  the pair means (point-mass Earth ~8e-13 at 0.6 m, anomalies less). */
#define GG_FDI3D_FLOOR_MPS2 2e-12

/** Outcome flags. */
#define GG_FDI3D_DETECTED  0x01u /**< a pair-mean parity exceeded its threshold this step */
#define GG_FDI3D_REBUILT   0x02u /**< one or more readings rebuilt (degraded) */
#define GG_FDI3D_NEW_EXCL  0x04u /**< a reading or a pair-axis was newly excluded this step */
#define GG_FDI3D_PAIR      0x08u /**< a pair-axis is excluded: its gradient entry from symmetry/trace */
#define GG_FDI3D_DEGRADED  0x10u /**< readings lost beyond one per pair-axis: the degraded rebuild */
#define GG_FDI3D_HOLD_GRAD 0x20u /**< a column entry M[j][p] held (last value, or the prior) */
#define GG_FDI3D_HOLD_FORCE 0x40u /**< no reading of an axis usable: its centre force held */
#define GG_FDI3D_SUSPECT   0x80u /**< a fault no single reading or pair explains: readings set aside */

typedef struct {
    gg_real_t half_base_m[3]; /**< h_0, h_1, h_2, m (> 0) */
    double parity_f_max;      /**< pair-mean detection threshold, m/s^2 (0: off) */
    int stabilized;           /**< 1: the angular acceleration is zero (stabilized platform) */
} gg_fdi3d_config_t;

typedef struct {
    gg_fdi3d_config_t cfg;
    gg_real_t mean_good[3][3]; /**< pair means m[p][j] of the last frame used (a rebuilt pair keeps
                                    the difference of its last whole frame), m/s^2 */
    uint32_t excluded;         /**< readings isolated as faulty, latched (GG_FDI3D_BIT) */
    uint32_t excluded_pairs;   /**< pair-axes (p, j) excluded as pairs, latched (bit GG_FDI3D_BIT(p, j)) */
    gg_real_t m_good[3][3];    /**< column entries M[j][p] of the last frame used, s^-2 (what a
                                    degraded rebuild holds) */
    gg_real_t m_prior[3][3];   /**< column entries from an onboard model (have_prior), s^-2 */
    int have_prior;            /**< 1: a held column entry takes m_prior (gg_fdi3d_set_prior) */
    int have_good;             /**< a frame has been used */
    int initialized;
} gg_fdi3d_t;

typedef struct {
    uint32_t flags;            /**< GG_FDI3D_* */
    uint32_t rebuilt;          /**< readings rebuilt this step */
    uint32_t excluded;         /**< latched exclusions after this step */
    uint32_t excluded_pairs;
    uint32_t held_m;           /**< column entries M[j][p] held this step, bit GG_FDI3D_BIT(p, j) */
    uint32_t held_force;       /**< axes whose centre force is held this step, bit j */
    gg_real_t parity_max;      /**< largest |m_p,j - m_q,j| over the whole pairs, m/s^2 */
} gg_fdi3d_output_t;

/** GG_ERR_CONFIG on a non-positive or non-finite half-baseline or a
 *  negative / non-finite threshold. */
gg_status_t gg_fdi3d_init(gg_fdi3d_t *st, const gg_fdi3d_config_t *cfg);

/** Column entries M = W - Gamma (diff3d.h) an onboard model predicts for
 *  the next step, s^-2 (NULL: none; a held entry then keeps its last
 *  value). GG_ERR_NONFINITE when one is not finite (nothing set). */
gg_status_t gg_fdi3d_set_prior(gg_fdi3d_t *st, gg_real_t m_prior[3][3]);

/** Check and accommodate one set of readings f/f_lo in place (rebuilt or,
 *  degraded, synthesised). known_bad:
 *  readings the caller knows are unusable (values ignored); omega_b: gyro
 *  rate, body axes, rad/s (0 on a stabilized platform); omega_dot_ref: the
 *  angular acceleration the antisymmetric part must show (rad/s^2; ignored
 *  when stabilized; NULL when unknown: cross-axis faults are then not
 *  isolated to a sensor). GG_ERR_SENSOR when the set cannot be accommodated:
 *  only before a first set was used (f, f_lo and the state untouched;
 *  out->flags still says whether a parity check fired); GG_ERR_NONFINITE
 *  when a reading not marked bad is not finite (out untouched). */
gg_status_t gg_fdi3d_step(gg_fdi3d_t *st, uint32_t known_bad, const gg_real_t omega_b[3],
                          const gg_real_t omega_dot_ref[3], double f[6][3], double f_lo[6][3],
                          gg_fdi3d_output_t *out);

#endif /* GGINS_FDI3D_H */
