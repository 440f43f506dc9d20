/**
 * @file nav3d.h
 * @brief Navigation task of the 3-D gravity-gradiometer INS: six tri-axis
 *        accelerometers, a rotating WGS-84 Earth, a space-stabilized or a
 *        strapdown platform (Welker, Pachter & Huffman section III,
 *        Fig. 1; Gao et al. section 3, eqs. 15-30).
 *
 * Frames (docs/design.md suffixes):
 *  - _e  ECEF, WGS-84: z to the north pole, x to the Greenwich meridian.
 *  - _i  ECI: coincides with _e at the first accepted frame (t = 0). The
 *        Earth turns about z at omega_ie: r_i = R3(theta) r_e, theta = omega_ie t,
 *        R3(theta) = [[c, -s, 0], [s, c, 0], [0, 0, 1]].
 *  - _n  local level, north-east-down at the current position.
 *  - _b  body / platform: x forward, y right, z down; accelerometer layout of
 *        diff3d.h (sensor 0 at (+a,0,0), 1 (0,+b,0), 2 (0,0,+c), 3 (-a,0,0),
 *        4 (0,-b,0), 5 (0,0,-c)); readings f = a - G in body axes.
 * Quaternions are scalar first, q = (w, x, y, z); q_b_e rotates body vectors
 * into ECEF (v_e = q_b_e (x) v_b (x) q_b_e*), i.e. C_b_e.
 *
 * Mechanization (why these frames). In an inertial frame
 * r''_i = f_i + G_i is free of Coriolis and centrifugal terms, so the third-
 * order fixed-step integrator of mech.h is used as it is. The gravitation,
 * however, is dead-reckoned in ECEF, where the field is static and
 * dG_e = Gamma_e dr_e holds exactly (in ECI the field at a fixed point turns
 * with the Earth: dG_i/dt = Gamma_i v_i + omega x G_i - Gamma_i (omega x r_i)):
 *   dr_e = R3(-theta_{k+1}) dr_i + [R3(-theta_{k+1}) - R3(-theta_k)] r_i(k)
 * (the rotation increment from sin/cos half-angle identities, no
 * cancellation), Gamma_e = C_b_e Gamma_b C_e_b, G_e by gravdr.h, then
 * G_i = R3(theta) G_e feeds the velocity half-step.
 *
 * Attitude. Stabilized platform: C_b_i constant (= C_b_e at t = 0); the
 * gyros are not used (omega_b taken as 0). Strapdown: q_b_i integrated from
 * the gyro rate samples (rad/s, at each frame time) by the classical
 * fourth-order Runge-Kutta method on q' = 1/2 q (x) (0, w), with w at the
 * mid-step interpolated through the samples k-2, k-1, k, k+1 (cubic). On
 * the first two steps, before four samples exist, the mid-step rate is the
 * cubic Hermite interpolant through w_k, w_{k+1} and the angular
 * accelerations the differencing measures at both ends (the antisymmetric
 * part, below): w(h/2) = (w_k + w_{k+1})/2 + h/8 (wd_k - wd_{k+1}), error
 * h^4 w''''/384. (A linear start left h^3 w''/12 in the attitude for good:
 * 8e-9 rad on a tumbling body, 2.5e-5 E in Gamma_e.) A quadratic left
 * 1.7e-8 rad after 1 h of a 0.2 rad/s spin with 0.05 rad/s precession (its
 * error h^3 w'''/16 in the rate is systematic); the cubic's is h^4 w''''/26.
 * Integrating the quaternion ODE with a fourth-order method
 * captures the non-commutativity (coning) terms that a single rotation
 * vector sum Delta-theta misses: the classical coning correction
 * 1/12 (w_k x w_{k+1}) h^2 is the leading term of the same series.
 * q is renormalised each step.
 * Rotating-body differencing (diff3d.h, Gao eqs. 24-27): Gamma_b = [w x]^2 -
 * (M + M^T)/2 with the gyro rate; the antisymmetric part measures the angular
 * acceleration omega_dot_b, published, and compared with the gyro-derived one
 * (parity, see below).
 *
 * Gravity: gradiometer mode (dead reckoning from the known G(0)) or model
 * mode (zonal WGS-84 normal field of gmodel.h evaluated at r_e).
 *
 * Vertical channel: optional barometric loop (vchan.h) on the geodetic
 * height, corrections along the ellipsoid normal u (the up unit vector):
 * position dh u, velocity dv u, G_e by Gamma_e dr_e, and the loop's integral
 * state a_c subtracted from the up specific force. (u is orthogonal to
 * omega x r, so u . v_i is the Earth-relative vertical speed.)
 *
 * Parity (health, GG_HEALTH_GAMMA_ASYM when above asym_max): stabilized
 * platform - the antisymmetric part of M (3 residuals, should be 0) and
 * trace(Gamma_b); strapdown - omega_dot_b minus the gyro-derived angular
 * acceleration (11 w_{k+1} - 18 w_k + 9 w_{k-1} - 2 w_{k-2}) / (6h)
 * (third-order backward difference: its own error is h^3/4 w'''', 2.5e-8
 * rad/s^2 on a body spinning at 1 rad/s with 0.3 rad/s precession at
 * 100 Hz, where the second-order difference's h^2/3 w''' is 1e-5; its
 * gyro-noise gain is sqrt(530)/6 = 3.84/h per unit rate noise, 1.1e-3
 * rad/s^2 for 2.9e-6 rad/s per sample at 100 Hz - asym_max must be above
 * both: a 3-D scenario derives it from the sensors' noise, the baselines and
 * the step, host_tools/lib/truth3d scenario3d.hpp; 0 on the first three
 * steps, before three earlier gyro samples exist) and trace(Gamma_b).
 *
 * Validation: a reading NaN/Inf, out of range or flagged bad is flagged and
 * rebuilt from the opposite pairs (fdi3d.h: one per pair and axis, GG_HEALTH_ACC_REBUILT,
 * acc_rebuilt); more readings lost, or a fault no single reading explains,
 * degrade the frame instead of rejecting it (fdi3d.h: GG_HEALTH_ACC_DEGRADED;
 * GG_HEALTH_GRAD_COAST for a gradient entry held on its last value - in
 * gravity-model mode taken from the onboard model -, GG_HEALTH_FORCE_COAST
 * for an axis' centre force held); a frame with fewer than 6 accelerometers,
 * bad readings before the first frame was used, or (strapdown) a gyro
 * sample NaN/Inf, above GG_LIM_W_MAX_RPS or flagged bad, is rejected and
 * flagged; its readings never reach the state. Seq/utime rules, bridging of up to GG_NAV3D_MAX_BRIDGE lost
 * frames (the bridged steps interpolate f_b, Gamma_b and w), re-synchronisation
 * and coasting through longer outages (f_b, Gamma_b and w held) as in nav2d.h
 * and navtask.h.
 *
 * Position output: ECEF and geodetic latitude, longitude, height on WGS-84
 * (geo.h: the constants, Bowring's iteration).
 *
 * Aiding: the gradient-map UKF (aid_mmukf.h, cfg.aid_mm) runs after each
 * step that advanced the state, on the task's own solution and measured
 * gradient, with tiles from the HAL's map storage (hal.h), and corrects the
 * state in closed loop at the end of each epoch (docs/nav3d.md). The
 * cold-atom particle filter (aid_pf.h, cfg.aid_pf) takes the frame's shot
 * with the task's solution, scores it against the storage's Gamma_zz tiles
 * and feeds its horizontal position correction back after each shot.
 *
 * Source files: nav3d.c (configuration, frame validation and sequencing,
 * bridging, the step), nav3d_att.c (strapdown attitude), nav3d_out.c
 * (output), nav3d_aid.c (the aiding sources), nav3d_pf.c (the cold-atom aid's hand-over); the algebra in quat.h, the
 * geodesy in geo.h.
 */
#ifndef GGINS_NAV3D_H
#define GGINS_NAV3D_H

#include <stdint.h>
#include "ggins/aid_mmukf.h"
#include "ggins/aid_pf.h"
#include "ggins/diff3d.h"
#include "ggins/fdi3d.h"
#include "ggins/frame.h"
#include "ggins/geo.h"
#include "ggins/gmodel.h"
#include "ggins/gravdr.h"
#include "ggins/hal.h"
#include "ggins/limits.h"
#include "ggins/mech.h"
#include "ggins/nav2d.h"
#include "ggins/navtask.h"
#include "ggins/real.h"
#include "ggins/status.h"
#include "ggins/vchan.h"

/** Platform kinds (gg_nav3d_config_t.platform). */
#define GG_PLATFORM_STABILIZED 0 /**< space-stabilized: perfect inertial attitude reference */
#define GG_PLATFORM_STRAPDOWN 1  /**< body-fixed sensors, attitude from the gyros */

/** Lost frames a step may bridge (see nav2d.h). */
#define GG_NAV3D_MAX_BRIDGE 100


typedef struct {
    gg_diff3d_config_t geometry; /**< half-baselines a, b, c, m */
    int platform;                /**< GG_PLATFORM_STABILIZED or GG_PLATFORM_STRAPDOWN */
    int64_t dt_us;               /**< fixed step, microseconds (> 0) */
    int64_t dt_tol_us;           /**< tolerated |utime step - dt_us|, microseconds (>= 0, < dt_us) */
    gg_real_t r0_e[3];           /**< initial position, ECEF, m */
    gg_real_t v0_e[3];           /**< initial Earth-relative velocity, ECEF axes, m/s */
    gg_real_t g0_e[3];           /**< initial gravitation G(0), ECEF axes, m/s^2 */
    gg_real_t q0_b_e[4];         /**< initial attitude C_b_e as a unit quaternion (w, x, y, z) */
    gg_real_t omega_ie;          /**< Earth rate, rad/s (0 selects GG_WGS84_OMEGA_IE; use a
                                      negative value for a non-rotating Earth: it is taken as 0) */
    double f_max;                /**< accelerometer range, m/s^2 (> 0) */
    double asym_max;             /**< parity residual flag threshold, s^-2 (> 0) */
    double fdi_parity_f_max;     /**< pair-mean fault detection threshold, m/s^2 (fdi3d.h; 0: off,
                                      else >= GG_FDI3D_FLOOR_MPS2) */
    int gravity_mode;            /**< GG_GRAVITY_GRADIOMETER or GG_GRAVITY_MODEL (nav2d.h) */
    gg_gmodel_config_t model;    /**< onboard gravity model (model mode only; zonal part used) */
    int baro_enable;             /**< 1: barometric vertical channel on */
    gg_vchan_config_t baro;      /**< vertical loop (baro_enable only) */
    gg_aid_mm_config_t aid_mm;   /**< gradient-map UKF aid (aid_mmukf.h; aid_mm.enable = 1: on; the
                                      tiles come from the HAL's map storage, hal.h) */
    gg_aid_pf_config_t aid_pf;   /**< cold-atom particle-filter aid (aid_pf.h; aid_pf.enable = 1: on; the
                                      fringe pairs from the frame's ca_* fields, the Gamma_zz tiles from
                                      the HAL's map storage) */
    int32_t acc_frozen_frames;   /**< used frames in a row with one value that make a reading
                                      stuck (navtask.h; 0: off, else 2..GG_LIM_FROZEN_FRAMES_MAX) */
} gg_nav3d_config_t;

typedef struct {
    gg_nav3d_config_t cfg;
    gg_diff3d_t diff;
    gg_fdi3d_t fdi;              /**< rebuilds unusable readings from the opposite pairs */
    gg_gravdr_t gravdr;          /**< G_e, Gamma_e (ECEF) */
    gg_mech_t mech;              /**< r_i, v_i (ECI) */
    gg_gmodel_t gmodel;
    gg_vchan_t vchan;
    gg_real_t omega_ie;          /**< Earth rate in use, rad/s */
    gg_real_t dt_s;
    gg_real_t q_b_i[4];          /**< attitude, body to ECI */
    gg_real_t w_k[3];            /**< gyro rate at the last accepted step, rad/s */
    gg_real_t w_km1[3];          /**< gyro rate one step earlier, rad/s */
    gg_real_t w_km2[3];          /**< two steps earlier, rad/s */
    int n_w;                     /**< gyro samples held (1..3) */
    int64_t n_steps;             /**< steps flown since t = 0 (theta = omega_ie n dt) */
    gg_real_t sin_th;            /**< sin / cos of theta at the current step */
    gg_real_t cos_th;
    gg_real_t sin_hstep;         /**< sin / cos of omega_ie dt / 2 */
    gg_real_t cos_hstep;
    gg_real_t gamma_b[3][3];     /**< last accepted gradient, body axes, s^-2 */
    gg_real_t gamma_e[3][3];     /**< same in ECEF, s^-2 */
    gg_real_t f_b[3];            /**< last accepted centre specific force, body, m/s^2 */
    double bias_w[3];            /**< gyro bias estimate subtracted from every rate, body, rad/s
                                      (learnt by the map aid's bias states; 0 otherwise) */
    double bias_f[3];            /**< accelerometer bias estimate common to the six, subtracted from
                                      every reading, body, m/s^2 (likewise) */
    gg_real_t omega_dot_b[3];    /**< angular acceleration from differencing at the last step, rad/s^2
                                      (also the Hermite start-up's end slope) */
    gg_real_t parity[4];         /**< 3 antisymmetric residuals (rad/s^2) + trace (s^-2) */
    gg_real_t a_c;               /**< vertical loop's integral state in use, m/s^2 */
    double loop_k[3];            /**< the vertical loop's gains applied since the map aid last
                                      stepped (vchan.h k_applied; all 0: none), for its error model */
    double loop_u_i[3];          /**< the up direction, ECI, they were applied along */
    gg_real_t h_ins;             /**< geodetic height, m */
    gg_real_t baro_innov;
    gg_task_seq_t seq;           /**< the frame stream as followed (navtask.h) */
    gg_task_frozen_t frozen;     /**< frozen-reading monitor (navtask.h) */
    int64_t state_step;          /**< step index of the navigation state (task clock) */
    int64_t state_clock_us;      /**< task-clock time of that step, us */
    int64_t input_step;          /**< step of the last frame whose readings were used */
    uint32_t coast_steps;        /**< steps coasted on held inputs so far */
    gg_aid_mm_t aid_mm;          /**< gradient-map aid (cfg.aid_mm.enable) */
    int64_t aid_step;            /**< state_step the aid has propagated to (-1: not yet) */
    double aid_corr_m[3];        /**< position correction of the aid's last epoch, ECI, m */
    gg_aid_pf_t aid_pf;          /**< cold-atom particle-filter aid (cfg.aid_pf.enable) */
    int64_t pf_last_utime;       /**< ca_utime of the last shot taken */
    int32_t pf_have_shot;        /**< a shot was taken (pf_last_utime valid) */
    int configured;
    int started;
} gg_nav3d_t;

/** Navigation output of one 3-D step. */
typedef struct gg_nav3d_output_s {
    int64_t utime;               /**< time of the frame this output answers, microseconds */
    int64_t seq;
    int32_t status;              /**< gg_status_t of the step */
    uint32_t health;             /**< GG_HEALTH_* bits */
    double r_e[3];               /**< position, ECEF, m */
    double r_e_lo[3];            /**< residual below double resolution, m (r = r_e + r_e_lo) */
    double v_e[3];               /**< Earth-relative velocity, ECEF axes, m/s */
    double lat_rad;              /**< geodetic latitude, WGS-84, rad */
    double lon_rad;              /**< longitude, rad, (-pi, pi] */
    double h_m;                  /**< height above the ellipsoid, m */
    double v_n[3];               /**< Earth-relative velocity, NED, m/s */
    double g_e[3];               /**< gravitation at the estimated position, ECEF, m/s^2 */
    double g_e_lo[3];
    double gamma_e[3][3];        /**< gradient dG_j/dx_k, ECEF axes, s^-2 */
    double gamma_b[3][3];        /**< gradient, body axes, s^-2 */
    double f_b[3];               /**< centre specific force, body axes, m/s^2 */
    double q_b_e[4];             /**< attitude C_b_e (w, x, y, z) */
    double rpy_rad[3];           /**< roll, pitch, yaw of the body w.r.t. NED, rad */
    double omega_b[3];           /**< gyro rate used, body axes, rad/s */
    double omega_dot_b[3];       /**< angular acceleration from the antisymmetric part, rad/s^2 */
    double parity[4];            /**< antisymmetric residuals (3, rad/s^2) and trace Gamma_b (s^-2) */
    double h_ins_m;              /**< inertial (geodetic) height used by the loop, m */
    double baro_innov_m;         /**< last barometer innovation h_ins - h_baro, m */
    double g_up_corr;            /**< vertical loop's integral state a_c, m/s^2 */
    double t_s;                  /**< time since t = 0, s */
    uint32_t cycles[GG_MOD_COUNT]; /**< cycle-counter ticks per module (GG_MOD_*) */
    uint32_t resync_count;       /**< re-synchronisations to the frame stream so far (navtask.h) */
    uint32_t coast_steps;        /**< steps propagated on held inputs so far (outages) */
    uint32_t acc_rebuilt;        /**< readings rebuilt this step, bit 3*sensor+axis (fdi3d.h) */
    uint32_t acc_excluded;       /**< readings excluded for good (isolated faults), same bits */
    double outage_s;             /**< time since the readings of a frame last entered the state, s */
    double state_lag_s;          /**< how far the state's time is behind this frame's, s */
    /* gradient-map aid (aid_mmukf.h); all 0 when it is off */
    int32_t mm_phase;            /**< schedule phase after this step (GG_AID_MM_PH_*) */
    int32_t mm_corrected;        /**< 1: this step applied the aid's correction to the state */
    uint32_t mm_epochs;          /**< measurement epochs started so far */
    uint32_t mm_updates;         /**< epochs with an accepted update so far */
    uint32_t mm_rejected;        /**< epochs gated or failed so far */
    uint32_t mm_no_map;          /**< epochs without a covering map tile so far */
    double mm_nis;               /**< NIS of the last epoch (single update with R, 6 dof) */
    double mm_sigma[18];         /**< one-sigma of the error state (aid_mmukf.h order: dr_i m,
                                      dv_i m/s, psi_i rad, dg_i m/s^2 (dead reckoning), then the
                                      bias states db_w rad/s, db_f m/s^2; 0 beyond its size) */
    double mm_bias[6];           /**< the task's bias estimates subtracted from the readings: gyro,
                                      body axes, rad/s; accelerometers' common bias, body, m/s^2 */
    double mm_corr_m[3];         /**< position correction of the last epoch, ECI axes, m */
    double mm_innov[6];          /**< innovation of the last epoch (xx yy zz xy xz yz, body axes), s^-2 */
    double mm_pcov[18];          /**< covariance after this step, upper triangles (xx yy zz xy xz yz)
                                      of the dr_i (m^2), dv_i ((m/s)^2), psi_i (rad^2) blocks */
    int32_t mm_n_avg;            /**< samples averaged into the last epoch's measurement */
    int32_t mm_integ;            /**< integrity monitor (aid_integ.h): GG_INTEG_OK / SUSPECT / ISOLATED */
    double mm_integ_ratio;       /**< its test ratio after the last epoch (window sum / chi-square band; > 1 outside) */
    uint32_t mm_isolated;        /**< epochs tested but not fed (ISOLATED) so far */
    /* cold-atom particle-filter aid (aid_pf.h); all 0 when it is off */
    int32_t pf_phase;            /**< schedule phase after this step (GG_AID_PF_PH_*) */
    int32_t pf_corrected;        /**< 1: this step fed the filter's correction back into the state */
    uint32_t pf_shots;           /**< shots taken so far */
    uint32_t pf_updates;         /**< shots weighed (a pair on the map) so far */
    uint32_t pf_failed;          /**< shots predicted only (failed, invalid or without a tile) so far */
    uint32_t pf_invalid;         /**< shots with a NaN/Inf or out-of-range pair so far */
    uint32_t pf_dropped;         /**< shots dropped (filter busy, or the frame's state not current) so far */
    uint32_t pf_no_map;          /**< shots without a covering map tile so far */
    uint32_t pf_map_miss;        /**< shots with candidates off the tile so far */
    uint32_t pf_degenerate;      /**< shots whose weights were reset so far */
    uint32_t pf_resampled;       /**< resamplings so far */
    double pf_ess;               /**< effective sample size of the last shot */
    double pf_spread_m[2];       /**< the cloud's spread (weighted sd of dN, dE) after the last shot, m */
    double pf_corr_m[2];         /**< last correction fed back, north, east, m */
    double pf_mean_m[2];         /**< the particles' mean after the last shot relative to the corrected
                                      state, north, east, m (the filter's estimate: state + pf_mean_m) */
    double pf_gzz_s2;            /**< weighted Gamma_zz of the last shot's candidates, s^-2 (0: not weighed) */
    double pf_nis;               /**< the last weighed shot's statistic (pf.h nis, 1 dof; -1: not weighed) */
    int32_t pf_integ;            /**< integrity monitor (aid_integ.h): GG_INTEG_OK / SUSPECT / ISOLATED */
    double pf_integ_ratio;       /**< its test ratio after the last weighed shot (> 1 outside the band) */
    uint32_t pf_isolated;        /**< weighed shots whose correction was not fed (ISOLATED) so far */
    uint32_t pf_uninformative;   /**< weighed shots whose correction was withheld (information gate, aid_pf.h) so far */
    double pf_info;              /**< the last shot's share of the free-inertial position variance removed
                                      (pf.h info; -1: not modelled) */
    double pf_spread_fi_m[2];    /**< the free-inertial sd of dN, dE after the last shot, m (pf.h spread_fi) */
} gg_nav3d_output_t;

/** Validate and store the configuration. GG_ERR_CONFIG on a non-finite or
 *  inconsistent value, GG_ERR_RANGE beyond the GG_LIM_* limits of nav2d.h. */
gg_status_t gg_nav3d_init(gg_nav3d_t *nav, const gg_nav3d_config_t *cfg);

/** Process one frame. Fills *out whenever nav, frame and out are non-NULL;
 *  GG_OK when the frame was used, an error code when it was rejected (state
 *  untouched). hal may be NULL; when given, its cycle counter times the modules. */
gg_status_t gg_nav3d_step(gg_nav3d_t *nav, const gg_frame_t *frame, const gg_hal_t *hal,
                          gg_nav3d_output_t *out);

/** One cycle of the 3-D task: read a frame through the HAL, step, publish
 *  through hal->write_output3d. GG_ERR_NO_DATA when the HAL had no frame. */
gg_status_t gg_nav3d_task_cycle(gg_nav3d_t *nav, const gg_hal_t *hal);

#endif /* GGINS_NAV3D_H */
