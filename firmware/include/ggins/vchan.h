/**
 * @file vchan.h
 * @brief Baro-damped vertical channel: a third-order baro-inertial loop on
 *        the vertical (radial) channel of the mechanization.
 *
 * The free vertical channel is unstable: d2(dh)/dt2 = +2 w_s^2 dh + da
 * (w_s^2 = g/r; with the gradiometer the +2 w_s^2 is the radial gradient
 * Gamma_uu; Welker, Pachter & Huffman, section VI: eigenvalue +sqrt(2) w_s).
 * Each accepted barometer sample gives e = h_ins - h_baro, and the loop
 *    dh' = dv - k1 e,   dv' = 2 w_s^2 dh - k2 e - a_c,   a_c' = k3 e
 * where a_c is the integral acceleration-error state. Its characteristic
 * polynomial is s^3 + k1 s^2 + (k2 - 2 w_s^2) s + k3, so for closed-loop
 * poles -p1, -p2, -p3:
 *    k1 = p1 + p2 + p3,  k2 = p1 p2 + p1 p3 + p2 p3 + 2 w_s^2,  k3 = p1 p2 p3
 * (the design accounts for the open-loop +2 w_s^2 term).
 * In gravity-model mode a_c settles on minus the vertical gravity
 * disturbance (the airborne gravimeter of Rubenstein & Winter, Fig. 4 and
 * eq. 10); in gradiometer mode on the vertical accelerometer-bias and
 * dead-reckoned-gravity error.
 *
 * Discrete design: the loop is corrected once per barometer sample (period
 * T). Between samples the error state x = (dh, dv, a_c) evolves as
 * x' = A x with A = [[0,1,0],[2 w_s^2,0,-1],[0,0,0]], so x_{n+1}^- = Phi x_n,
 * Phi = exp(A T); each sample applies x^+ = x^- + K e with e = C x^-,
 * C = [1 0 0]. The gain K places the eigenvalues of (I + K C) Phi at
 * z_i = exp(-p_i T) exactly (Ackermann's formula for the pair (Phi, C Phi):
 * K = -alpha(Phi) O^-1 [0 0 1]^T, O = [C Phi; C Phi^2; C Phi^3], alpha the
 * desired characteristic polynomial), so the implemented discrete loop has
 * the configured poles, not an Euler approximation of them (an Euler
 * version, K = T (-k1, -k2, k3), missed clustered poles by 5 %). For small
 * T, K -> T (-k1, -k2, k3) with the continuous gains above. A sample that
 * arrives after a span other than T scales K by span/T (first order).
 * exp() is a bounded Taylor series (no libm); init requires p_i T <= 1.
 *
 * Sample validation: status, NaN/Inf, altitude range, age (utime of the
 * sample against the frame's), repeat (no new sample = nothing to do), and
 * an innovation gate; after max_rejects consecutive gated samples the loop
 * re-captures (accepts) and flags it. With no accepted sample for longer
 * than coast_us the loop coasts (a_c held, no corrections) and flags it.
 */
#ifndef GGINS_VCHAN_H
#define GGINS_VCHAN_H

#include <stdint.h>
#include "ggins/real.h"
#include "ggins/status.h"

typedef struct {
    gg_real_t poles[3];      /**< closed-loop poles -p_i: the p_i > 0, rad/s */
    gg_real_t omega_s2;      /**< w_s^2 = g/r at the operating point, s^-2 (> 0) */
    int64_t period_us;       /**< nominal barometer sample period, microseconds (> 0) */
    int64_t max_age_us;      /**< oldest acceptable sample age, microseconds (>= 0) */
    int64_t coast_us;        /**< no accepted sample for this long = coasting, microseconds */
    double alt_min_m;        /**< plausible altitude range, m */
    double alt_max_m;
    double gate_m;           /**< innovation gate |h_ins - h_baro|, m (> 0) */
    int32_t max_rejects;     /**< consecutive gated samples before re-capture (>= 1) */
} gg_vchan_config_t;

/** Health bits of the vertical channel (mapped into the nav health word). */
#define GG_VCHAN_INVALID   0x00000001u /**< sample NaN/Inf, out of range or flagged bad */
#define GG_VCHAN_STALE     0x00000002u /**< sample older than max_age_us */
#define GG_VCHAN_OUTLIER   0x00000004u /**< sample rejected by the innovation gate */
#define GG_VCHAN_RECAPTURE 0x00000008u /**< gate overridden after max_rejects rejections */
#define GG_VCHAN_COAST     0x00000010u /**< no accepted sample for longer than coast_us */

typedef struct {
    gg_vchan_config_t cfg;
    gg_real_t k1;            /**< continuous-equivalent gain, s^-1 (documentation, tests) */
    gg_real_t k2;            /**< s^-2 */
    gg_real_t k3;            /**< s^-3 */
    gg_real_t kd[3];         /**< discrete gain K per sample: dh = K0 e, dv = K1 e, a_c += K2 e */
    gg_real_t a_c;           /**< integral acceleration-error state, m/s^2 (along up) */
    int64_t last_accept_utime;
    int64_t last_sample_utime;
    int32_t rejects;         /**< consecutive gated samples */
    int started;             /**< a sample has been accepted */
    int initialized;
} gg_vchan_t;

/** Barometer sample offered to the loop. */
typedef struct {
    double alt_m;            /**< barometric altitude, m */
    int64_t utime;           /**< sample time, microseconds */
    int32_t status;          /**< GG_SENSOR_* (frame.h) */
} gg_vchan_sample_t;

/** Corrections to apply along the local up direction after a step. */
typedef struct {
    gg_real_t dh_m;          /**< position correction along up, m */
    gg_real_t dv_mps;        /**< velocity correction along up, m/s */
    gg_real_t a_c;           /**< integral state to subtract from the up acceleration, m/s^2 */
    gg_real_t innov_m;       /**< last innovation h_ins - h_baro, m (0 when none) */
    gg_real_t k_applied[3];  /**< the gains this call applied, K span / T: dh = k0 e, dv = k1 e,
                                  a_c += k2 e (all 0 when it applied none); the map aid's error
                                  model takes the loop's correction from them (aid_mmukf.h) */
    uint32_t health;         /**< GG_VCHAN_* */
    int accepted;            /**< 1 when this call accepted a sample */
} gg_vchan_output_t;

/** Compute the gains. GG_ERR_CONFIG on non-positive poles or w_s^2,
 *  non-positive period, p_max * period > 1, an inconsistent range/gate, or a
 *  singular design (unobservable pair). */
gg_status_t gg_vchan_init(gg_vchan_t *st, const gg_vchan_config_t *cfg);

/** One navigation step at time now_us with inertial altitude h_ins_m (m);
 *  sample may be NULL (no barometer this step). */
gg_status_t gg_vchan_step(gg_vchan_t *st, int64_t now_us, gg_real_t h_ins_m,
                          const gg_vchan_sample_t *sample, gg_vchan_output_t *out);

#endif /* GGINS_VCHAN_H */
