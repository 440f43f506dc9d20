/**
 * @file mech.h
 * @brief Space-stabilized platform mechanization r'' = f + G
 *        (Welker, Pachter & Huffman, section V, with the sign convention of
 *        docs/design.md: f = a - G, so a = f + G).
 *
 * Fixed-step velocity Verlet with end corrections (h = dt, a_k = f_k + G_k):
 *   position:  dr = v_k h + h^2/2 a_k + h^2/6 (a_k - a_{k-1});  r_{k+1} = r_k + dr
 *   (the caller now obtains G_{k+1} at r_{k+1}, e.g. gg_gravdr_step with dr)
 *   velocity:  a_{k+1} = f_{k+1} + G_{k+1};
 *              v_{k+1} = v_k + h/2 (a_k + a_{k+1}) - h/12 (a_{k+1} - 2 a_k + a_{k-1})
 * so G at the end of the step is the one at the end-of-step position. The
 * correction terms are the Taylor jerk term (backward difference) and the
 * Euler-Maclaurin end correction of the trapezoid: local error O(h^4), third
 * order globally (plain Verlet, second order, left 7e-8 m after a 10 h
 * flight at 100 Hz). The first step, with no a_{k-1}, is plain Verlet.
 * Position and velocity are compensated accumulators (real.h).
 * Frame: inertial (platform axes = inertial axes). Vectors are 3-D.
 */
#ifndef GGINS_MECH_H
#define GGINS_MECH_H

#include "ggins/real.h"
#include "ggins/status.h"

typedef struct {
    gg_real_t dt_s;        /**< fixed step, s (> 0) */
    gg_real_t r0[3];       /**< initial position, m */
    gg_real_t v0[3];       /**< initial velocity, m/s */
    gg_real_t a0[3];       /**< initial acceleration f0 + G0, m/s^2 */
} gg_mech_config_t;

typedef struct {
    gg_real_t dt_s;
    gg_acc_t r[3];         /**< position, m */
    gg_acc_t v[3];         /**< velocity, m/s */
    gg_real_t a[3];        /**< acceleration at the current step, m/s^2 */
    gg_real_t a_prev[3];   /**< acceleration one step earlier, m/s^2 */
    int have_prev;         /**< a_prev valid */
    gg_real_t dr[3];       /**< displacement of the pending step, m */
    gg_acc_t r_prev[3];    /**< position before the pending step (for roll-back) */
    int pending;           /**< 1 between position and velocity half-steps */
    int initialized;
} gg_mech_t;

gg_status_t gg_mech_init(gg_mech_t *st, const gg_mech_config_t *cfg);

/** First half of a step: advance position, return the displacement dr (m). */
gg_status_t gg_mech_step_position(gg_mech_t *st, gg_real_t dr[3]);

/** Second half: specific force f_next (m/s^2) and gravitation g_next (m/s^2,
 *  as compensated values so no precision is lost in f + G) at the end of the
 *  step. On error the pending step is rolled back (state as before the step). */
gg_status_t gg_mech_step_velocity(gg_mech_t *st, const gg_real_t f_next[3],
                                  const gg_acc_t g_next[3]);

/** Apply an external correction (e.g. the barometric loop) between steps:
 *  dr (m) to the position, dv (m/s) to the velocity, da (m/s^2) to the
 *  stored current acceleration. GG_ERR_NONFINITE leaves the state untouched. */
gg_status_t gg_mech_correct(gg_mech_t *st, const gg_real_t dr[3], const gg_real_t dv[3],
                            const gg_real_t da[3]);

gg_status_t gg_mech_get(const gg_mech_t *st, gg_real_t r[3], gg_real_t v[3]);

/** Position and velocity as compensated values (hi + lo). */
gg_status_t gg_mech_get_acc(const gg_mech_t *st, gg_acc_t r[3], gg_acc_t v[3]);

#endif /* GGINS_MECH_H */
