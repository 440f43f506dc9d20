/**
 * @file aid_mmukf.h
 * @brief Gravity-gradient map matching as an aiding source of the 3-D task
 *        (nav3d.h): an error-state unscented Kalman filter (ukf.h) about the
 *        task's own INS solution, matching the gradient tensor the task
 *        measures by differencing its six accelerometers against an onboard
 *        map tile (gmap.h) that the HAL's map storage provides (hal.h).
 *        Gao, Hu, Chang, Qin & Lyu, "An Aided Navigation Method Based on
 *        Strapdown Gravity Gradiometer", Sensors 21, 829 (2021), eqs. 24-44;
 *        the unstable vertical mode of gravity dead reckoning from Welker,
 *        Pachter & Huffman.
 *
 * No mechanization of its own: the task propagates the navigation state; the
 * aid propagates only the error covariance with the linearised error
 * dynamics of the task's ECI mechanization, and corrects the task's state
 * (closed loop, docs/nav3d.md) after each measurement epoch.
 *
 * Error state x = true - estimate, ECI axes (the task's mechanization frame):
 *   x[0..2]  dr_i  position, m
 *   x[3..5]  dv_i  inertial velocity, m/s
 *   x[6..8]  psi_i attitude, rad: C_b_i(true) = (I + [psi x]) C_b_i(est)
 *   x[9..11] dg_i  gravitation error at the estimated position, m/s^2
 *            (gravity dead reckoning only; in model mode the gravitation is
 *            evaluated at the estimated position and dG = Gamma dr is already
 *            in the position term, so there is no such state: nx = 9)
 *   with bias states (cfg.bias_states = 1), after those (index nb = 12 or 9):
 *   x[nb..nb+2]   db_w  gyro bias, body axes, rad/s (true minus the task's estimate)
 *   x[nb+3..nb+5] db_f  accelerometer bias common to the six, body axes, m/s^2
 *            (a bias common to the six cancels in the differences: it is the
 *            centre specific force's; a differential one is the gradient's
 *            and is left to the fault isolation, fdi3d.h)
 *   so nx = 18 (dead reckoning) or 15 (model). The task subtracts its bias
 *   estimates from every gyro and accelerometer reading (nav3d.h) and the aid
 *   corrects those estimates with the rest of the state (closed loop).
 * Error dynamics (linearised r''_i = f_i + G_i):
 *   dr' = dv,
 *   dv' = Gamma_i dr - [f_i x] psi + dg       (Gamma_i = C_b_i Gamma_b C_i_b,
 *                                              the measured gradient),
 *   psi' = n_psi,                             (gyro white noise: q_att and sigma_gyro)
 *   dg' = [w_ie x] dg + n_g                   (dg is fixed in ECEF; n_g the
 *                                              gradient noise times the speed)
 * and with bias states dv' gains - C_b_i db_f, psi' gains - C_b_i db_w (the
 * task integrates the reading minus its estimate, so a bias it has not yet
 * learnt turns the estimate by -db_w), db_w' = n_bw, db_f' = n_bf (random walks).
 * The vertical block dr'' = Gamma_zz dr with Gamma_zz ~ +2 w_s^2 is Welker's
 * +sqrt(2) w_s mode: dead reckoning alone lets it grow, the map bounds it.
 * The task's barometric loop (vchan.h) is part of the error dynamics: at a
 * step where it corrected the state with the innovation e = h_ins - h_baro
 * = -(u^T dr + n_b) (u the up direction in ECI, n_b the barometer's error),
 * the aid applies the same correction to the error state, x <- x + b (u^T dr
 * + n_b) with b = (k0 u; k1 u + w_ie x k0 u; -k2 u) on (dr; dv; dg) (the
 * task's own correction, nav3d.c: position and velocity along up, Earth-
 * relative, and the integral a_c, which enters the acceleration as a_c u and
 * so is part of dg), i.e. Phi <- (I + b c^T) Phi, Q <- (I + b c^T) Q
 * (I + b c^T)^T + sigma_baro^2 b b^T with c^T x = u^T dr. Without it the
 * aid would take the loop's work for its own and its vertical velocity
 * variance would not follow the loop's (measured: velocity NEES 5.9 against
 * a band of 2.7-3.3 on a climbing route; 1.6 with the loop off). In model
 * mode (no dg state) the integral's share, k2, is left out. The barometer's
 * error is modelled as white (sigma_baro_m per sample); a bias or a slow
 * Gauss-Markov error is not a state of the aid.
 * Per navigation step of h the transition is F = I + A h + (A h)^2 / 2 (its
 * error is O((w_s h)^3), ~1e-15 at 100 Hz) and the process noise
 * Q <- F Q F^T + diag(q) h accumulates; at an epoch the UKF predict
 * (gg_ukf_predict) takes the state through the accumulated transition.
 *
 * Measurement (Gao eqs. 30-31): the six components xx, yy, zz, xy, xz, yz of
 * the gravitation gradient in body axes, measured by differencing (diff3d.h,
 * Gao eqs. 24-27, [w x]^2 removed with the gyro rate), predicted for a sigma
 * point x as Gamma_b = C_n_b Gamma_n(map at r_e + R3(-theta) dr_i) C_b_n with
 * C_b_n = C_e_n (I + [psi_e x]) C_b_e, psi_e = R3(-theta) psi_i. The tile must
 * hold the total gravitation gradient.
 * With bias states the gyro bias is also in the measurement: the [w x]^2
 * removal used the task's corrected rate, w + db_w, so the measured gradient
 * carries sum_i db_w,i S_i (S_i below; the window's mean of S_i in the epoch's
 * body axes), and R carries no rate-bias share.
 * Epoch average (average_steps = n > 1): the valid samples of the last n steps
 * before the epoch are rotated to ECEF with the task's attitude of their step
 * (C_b_e Gamma_b C_e_b: the field does not turn with the body there), averaged,
 * and rotated back with the epoch's attitude. Since C_b_e,est = (I - [psi x])
 * C_b_e,true at every step of the window, the average is modelled as above
 * with the field replaced by its mean along the window's track (two-point
 * Gauss-Legendre: the map at the mean position +- the positions' standard
 * deviation along the track) and dr by the window's mean error dr - tau dv
 * (tau: epoch time minus the mean sample time).
 * R (full 6 x 6): sigma_meas^2 / n on the diagonal components and
 * (offdiag_ratio sigma_meas)^2 / n on the off-diagonal ones (sigma_meas is
 * one sample's noise of a diagonal component; six differenced accelerometers
 * give offdiag_ratio = 1/sqrt(2): an off-diagonal component averages four
 * readings, a diagonal one differences two), + sigma_db^2 on each (the map's noise does not
 * average), + the gyro's share: the removal with the measured rate w adds
 * d[w x]^2 = sum_i dw_i S_i, S_i = e_i w^T + w e_i^T - 2 w_i I (Gao eqs. 28-29:
 * the rotation terms are quadratic in w), so white rate noise sigma_w per step
 * adds sigma_w^2 / n^2 sum_k sum_i s_ik s_ik^T and a rate bias sigma_b per axis
 * sigma_b^2 sum_i s_i s_i^T (s_i the window mean; a constant bias is treated as
 * white from epoch to epoch), in ECEF components rotated to the epoch's body
 * axes; the second-order mean E[[dw x]^2] = -2 sigma_w^2 I is taken out of the
 * measured diagonal. The gyro noise is also an angle random walk of
 * sigma_w^2 h^2 per step in Q (with q_att_rad_rts).
 *
 * Real-time schedule (one unit of work per navigation step, so no step does
 * more than one pass over the sigma points):
 *   propagate (every step) -> epoch: tile from the HAL, measurement and
 *   nominal captured, UKF predict to the epoch -> per pass: spread (sets the
 *   pass weight, NIS of the first pass) -> update -> ... -> finish: UKF
 *   predict from the epoch to the current step, correction handed to the
 *   task, mean reset to 0.
 * Progressive passes (max_passes > 1; not in Gao): the tensor measures tilt
 * to ~1e-6 rad through the ~4600 E normal field, so with a 0.5 deg initial
 * attitude the sigma points' prediction is far from linear (second-order
 * term ~2.6 E against 0.01 E noise) and a single update can throw the
 * heading off. Pass k uses R / w_k, sum w_k = 1 (one update for a linear
 * model), w_k the smallest R_kk / (predicted spread of component k) until
 * every spread is below R_kk; the mean stays in the UKF between passes, so
 * each pass is re-linearised about the new estimate.
 *
 * Working precision: double (the UKF core), positions handed to geo.h in
 * gg_real_t.
 */
#ifndef GGINS_AID_MMUKF_H
#define GGINS_AID_MMUKF_H

#include <stdint.h>

#include "ggins/aid_integ.h"
#include "ggins/gmap.h"
#include "ggins/hal.h"
#include "ggins/limits.h"
#include "ggins/real.h"
#include "ggins/status.h"
#include "ggins/ukf.h"

/** Error-state dimension with the gravitation error state (dead reckoning). */
#define GG_AID_MM_NX_DR 12
/** Error-state dimension in model mode. */
#define GG_AID_MM_NX_MODEL 9
/** Bias states (gyro and accelerometer, three each) added by cfg.bias_states. */
#define GG_AID_MM_NX_BIAS 6
#if (GG_AID_MM_NX_DR + GG_AID_MM_NX_BIAS) > GG_UKF_NX_MAX
#error "the map-aid error state does not fit the UKF core (GG_UKF_NX_MAX, limits.h)"
#endif

/** Aid health (gg_aid_mm_t.health, mapped onto GG_HEALTH_MM_* by the task). */
#define GG_AID_MM_H_NO_MAP 0x01u    /**< no tile of the map storage covers the position at its height */
#define GG_AID_MM_H_GATED 0x02u     /**< the epoch's innovation failed the NIS gate */
#define GG_AID_MM_H_FAIL 0x04u      /**< the UKF rejected an operation (not PD, sigma point off the tile) */
#define GG_AID_MM_H_BAD_MEAS 0x08u  /**< epoch postponed: the gradient was rebuilt, coasting or bridged */
#define GG_AID_MM_H_SUSPECT 0x10u   /**< integrity monitor (aid_integ.h): SUSPECT, R de-weighted */
#define GG_AID_MM_H_ISOLATED 0x20u  /**< integrity monitor: ISOLATED, no correction fed */

/** Schedule phases. */
#define GG_AID_MM_PH_PROPAGATE 0
#define GG_AID_MM_PH_SPREAD 1
#define GG_AID_MM_PH_UPDATE 2
#define GG_AID_MM_PH_FINISH 3

typedef struct {
    int32_t enable;          /**< 1: aid on (the rest is validated only then) */
    int32_t update_steps;    /**< navigation steps between epochs, >= 2 max_passes + 2 */
    int32_t max_passes;      /**< progressive passes, 1..GG_MM_MAX_PASSES */
    double sigma_meas_s2;    /**< gradiometer noise of a diagonal component, s^-2 (> 0) */
    double sigma_db_s2;      /**< map (database) noise, s^-2 (>= 0) */
    double offdiag_ratio;    /**< off-diagonal noise / diagonal noise, (0, GG_LIM_MM_OFFDIAG_MAX]; 0 = 1 */
    double sig0_pos_m;       /**< initial one-sigma per axis: position, m (> 0) */
    double sig0_vel_mps;     /**< velocity, m/s (> 0) */
    double sig0_att_rad;     /**< attitude, rad (> 0) */
    double sig0_g_mps2;      /**< gravitation error (dead reckoning only), m/s^2 (> 0) */
    double q_vel_mps_rts;    /**< velocity random walk, m/s/sqrt(s) (>= 0) */
    double q_att_rad_rts;    /**< angle random walk, rad/sqrt(s) (>= 0) */
    double q_g_mps2_rts;     /**< gravitation-error random walk, m/s^2/sqrt(s) (>= 0) */
    double lambda;           /**< UT spread (>= 0; 0 = Gao) */
    double gate_nis;         /**< NIS gate, chi-square 6 dof (<= 0: none) */
    int32_t average_steps;   /**< navigation steps whose tensors are averaged into an epoch's
                                  measurement, 0..update_steps (0 or 1: the epoch's own sample) */
    double sigma_gyro_rps;   /**< gyro white noise of one navigation step's rate, rad/s (>= 0):
                                  its share of R (the [w x]^2 removal) and of Q (angle random walk) */
    double sigma_gyro_bias_rps; /**< gyro bias one-sigma per axis, rad/s (>= 0): its share of R
                                     (without bias states) */
    int32_t bias_states;        /**< 1: gyro and accelerometer bias states (the file comment), 0: none */
    double sig0_gyro_bias_rps;  /**< with bias states: initial one-sigma of the gyro bias, rad/s (> 0) */
    double sig0_acc_bias_mps2;  /**< and of the accelerometers' common bias, m/s^2 (> 0) */
    double q_gyro_bias_rps_rts; /**< gyro bias random walk, rad/s/sqrt(s) (>= 0) */
    double q_acc_bias_mps2_rts; /**< accelerometer bias random walk, m/s^2/sqrt(s) (>= 0) */
    gg_integ_config_t integ;    /**< integrity monitor on the epochs' NIS (aid_integ.h, 6 dof) */
    double sigma_baro_m;        /**< barometer white noise of one sample, m (>= 0): the vertical
                                     loop's share of Q (the file comment) */
} gg_aid_mm_config_t;

/** The task's INS solution and measurement at one navigation step. */
typedef struct {
    int32_t n_steps;          /**< navigation steps since the previous call (1.. bridge/coast) */
    double dt_s;              /**< one navigation step, s */
    double omega_ie;          /**< Earth rate in use, rad/s */
    gg_real_t sin_th;         /**< sin, cos of the Earth rotation angle theta at this step */
    gg_real_t cos_th;
    gg_real_t r_e[3];         /**< estimated position, ECEF, m */
    gg_real_t c_b_e[3][3];    /**< estimated attitude C_b_e */
    double c_b_i[3][3];       /**< estimated attitude C_b_i (bias states' dynamics) */
    double gamma_i[3][3];     /**< measured gradient, ECI axes, s^-2 (error dynamics) */
    double f_i[3];            /**< specific force, ECI axes, m/s^2 */
    double z_b[6];            /**< measured gradient, body axes: xx, yy, zz, xy, xz, yz, s^-2 */
    double w_b[3];            /**< body rate the [w x]^2 removal used, rad/s (0: no removal) */
    int32_t w_gyro;           /**< 1: w_b is the gyro reading (strapdown), 0: no gyro in z_b */
    int32_t z_valid;          /**< 1: z_b from this frame's own readings (not rebuilt, bridged, coasting) */
    double loop_k[3];         /**< the vertical loop's gains applied at this step (vchan.h k_applied:
                                   dh = k0 e, dv = k1 e, a_c += k2 e; all 0: no correction) */
    double loop_u_i[3];       /**< the up direction, ECI, the loop corrected along (unit) */
} gg_aid_ins_t;

/** A correction to the task's state (x = true - estimate, ECI, at this step). */
typedef struct {
    int32_t valid;            /**< 1: apply it */
    double dr_i[3];
    double dv_i[3];
    double psi_i[3];
    double dg_i[3];           /**< 0 in model mode */
    double db_w[3];           /**< gyro bias, body axes, rad/s (0 without bias states) */
    double db_f[3];           /**< accelerometer bias, body axes, m/s^2 (0 without bias states) */
} gg_aid_corr_t;

typedef struct {
    gg_aid_mm_config_t cfg;
    int32_t nx;                                   /**< 12 (dead reckoning) or 9 (model), + 6 with bias states */
    int32_t nb;                                   /**< index of the first bias state (= 12 or 9; nx without them) */
    gg_ukf_t ukf;                                 /**< error state and covariance */
    double phi[GG_UKF_NX_MAX][GG_UKF_NX_MAX];     /**< transition accumulated since the last predict */
    double q[GG_UKF_NX_MAX][GG_UKF_NX_MAX];       /**< process noise accumulated since then */
    /* the epoch (measurement and the nominal it is predicted about) */
    const gg_gmap_t *tile;                        /**< tile from the map storage, valid for the epoch */
    double ep_r_e[3];                             /**< nominal position, ECEF, m */
    double ep_c_b_e[3][3];                        /**< nominal attitude */
    double ep_sin_th;                             /**< Earth rotation angle of the epoch */
    double ep_cos_th;
    double ep_z[6];
    double rk[6];                                 /**< diagonal of R of a single sample */
    double w_pass;                                /**< weight of the pass in progress */
    double remaining;                             /**< measurement weight not yet used */
    int32_t pass;
    int32_t phase;                                /**< GG_AID_MM_PH_* */
    int32_t steps_since_epoch;
    int32_t accepted_any;
    uint32_t health;                              /**< GG_AID_MM_H_* of this step */
    uint32_t n_epochs;                            /**< epochs started */
    uint32_t n_updates;                           /**< epochs with an accepted update */
    uint32_t n_rejected;                          /**< epochs gated or failed */
    uint32_t n_no_map;                            /**< epochs without a tile covering the position at its height */
    double last_nis;                              /**< NIS of the last epoch (single update with R) */
    int32_t initialized;
    /* the epoch's averaging window (sums over its valid steps, ECEF axes) */
    int32_t av_n;                                 /**< steps summed */
    double av_g_e[3][3];                          /**< sum of C_b_e Gamma_b C_e_b, s^-2 */
    double av_r0[3];                              /**< first estimated position of the window, m */
    double av_dr[3];                              /**< sum of the positions minus av_r0, m */
    double av_rl[3];                              /**< last position of the window minus av_r0, m */
    double ep_dq[3];                              /**< epoch: half the spread of the two map nodes, ECEF, m */
    double av_ksum;                               /**< sum of the samples' steps since the last epoch */
    double ep_tau_s;                              /**< epoch time minus the window's mean sample time, s */
    double av_s[3][6];                            /**< sum of the rotated rate sensitivities s_i */
    double av_ss[6][6];                           /**< sum of s_i s_i^T over i and the steps */
    double ep_r[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX];    /**< R of the epoch (full, s^-4) */
    double ep_sb[3][6];                           /**< epoch: window mean of S_i, epoch's body axes (bias states) */
    double last_innov[6];                         /**< innovation of the last epoch (first pass), s^-2 */
    int32_t last_n_avg;                           /**< steps averaged into the last epoch */
    gg_integ_t integ;                             /**< integrity monitor (aid_integ.h) */
    uint32_t n_isolated;                          /**< epochs tested but not fed (ISOLATED) */
} gg_aid_mm_t;

/* gg_aid_mm_t has no gg_real_t member, on purpose: on x86-64 that would make
 * it 16-byte aligned, and GCC 12.2 at -O3 then miscomputes the misalignment
 * of its member arrays in outer-loop vectorization (a member at 8 mod 16 is
 * loaded with an aligned SSE instruction: SIGSEGV; standalone reproduction in
 * tests/unit/gcc12_outer_vect_align.c). With 8-byte alignment the compiler
 * cannot assume more than each member's own. aid_mmukf.c asserts it. */

/** Validate cfg and start the filter (mean 0, P0 = diag of the sig0_*).
 *  gravity_state = 1 with gravity dead reckoning, 0 in model mode. cfg->enable
 *  = 0 leaves the aid off (GG_OK, initialized = 0). GG_ERR_CONFIG on a bad
 *  value. */
gg_status_t gg_aid_mm_init(gg_aid_mm_t *a, const gg_aid_mm_config_t *cfg, int32_t gravity_state);

/** At the task's first step: with gravity dead reckoning, G(0) is the
 *  gravitation at the true start point (a surveyed value), so a start
 *  position error dr makes the gravitation error at the estimated point
 *  dg = -Gamma dr: P0 gets that correlation (P_gr = -Gamma P_rr,
 *  P_gg = Gamma P_rr Gamma^T + sig0_g^2 I). Model mode: nothing to do. */
gg_status_t gg_aid_mm_start(gg_aid_mm_t *a, const double gamma_i[3][3]);

/** One navigation step of the aid: propagate the covariance by ins->n_steps
 *  steps, then do the schedule's next unit of work (see the file comment).
 *  map may be NULL (no map storage: epochs are flagged NO_MAP). *corr is
 *  filled (valid = 1) at the end of an epoch; the task must apply it (the mean
 *  is reset to 0 here). a->health holds this step's GG_AID_MM_H_* bits.
 *  GG_ERR_NONFINITE / GG_ERR_RANGE on a bad INS input (aid state untouched). */
gg_status_t gg_aid_mm_step(gg_aid_mm_t *a, const gg_aid_ins_t *ins, const gg_hal_map_t *map,
                           gg_aid_corr_t *corr);

/** Predicted body-axes gradient (xx, yy, zz, xy, xz, yz) of the error state x
 *  about the nominal (r_e, C_b_e, theta): the measurement model. */
gg_status_t gg_aid_mm_predict(const gg_gmap_t *tile, const gg_real_t r_e[3],
                              gg_real_t c_b_e[3][3], gg_real_t sin_th, gg_real_t cos_th,
                              const double *x, double z[6]);

#endif /* GGINS_AID_MMUKF_H */
