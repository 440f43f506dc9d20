/**
 * @file frame.h
 * @brief Sensor frame (HAL input) and navigation output (HAL output).
 *
 * Conventions (docs/design.md): SI units; the accelerometers read
 * specific force f = a - G in platform axes; on the space-stabilized
 * platform of Welker, Pachter & Huffman the platform axes are the inertial
 * axes (_i). Axis index 0 = x, 1 = y, 2 = z. In the 2-D case (vertical plane
 * x, z) axis 1 is unused and published as zero.
 * Time stamps are int64 microseconds (utime), seq is the step index.
 */
#ifndef GGINS_FRAME_H
#define GGINS_FRAME_H

#include <stdint.h>

/** Largest number of distributed tri-axis accelerometers (3-D: six). */
#define GG_MAX_ACC 6

/** Time stamps and step indices are accepted in [0, GG_TIME_MAX]: ~146 000
 *  years of microseconds, and small enough that no difference of two of them
 *  can overflow int64 (a frame outside the range is rejected, GG_HEALTH_TIME_JUMP). */
#define GG_TIME_MAX 0x3FFFFFFFFFFFFFFFLL

/** Per-sensor status codes carried in frames (0 = good sample). */
#define GG_SENSOR_OK 0
#define GG_SENSOR_BAD 1
#define GG_SENSOR_ABSENT 2

/** One fixed-step sample of every sensor, as the HAL delivers it. */
typedef struct {
    int64_t utime;                  /**< sample time, microseconds */
    int64_t seq;                    /**< step index, +1 per step */
    int32_t n_acc;                  /**< accelerometers present (4 in 2-D, 6 in 3-D) */
    double f[GG_MAX_ACC][3];        /**< specific force per accelerometer, platform axes, m/s^2 */
    double f_lo[GG_MAX_ACC][3];     /**< residual of f below double resolution, m/s^2 (reading =
                                         f + f_lo; 0 when the sensor resolves less). A double at
                                         9.8 m/s^2 resolves only 1.8e-15 m/s^2: that rounding,
                                         differenced over 1 m, is 7e-16 s^-2 of white gradient
                                         noise, enough to push a perfect-sensor 1 h flight's
                                         gravity error to ~1e-10 m/s^2 through the vertical mode */
    int32_t acc_status[GG_MAX_ACC]; /**< GG_SENSOR_* per accelerometer */
    double omega_b[3];              /**< gyro angular rate, body axes, rad/s (3-D strapdown) */
    int32_t gyro_status;            /**< GG_SENSOR_* */
    double baro_alt_m;              /**< barometric (pressure) altitude, m */
    int64_t baro_utime;             /**< time of the barometer sample, microseconds */
    int32_t baro_status;            /**< GG_SENSOR_*; ABSENT when no new sample this step */
    /* cold-atom vertical gradiometer (aid_pf.h; Phillips et al.): one shot a period */
    double ca_s[2];                 /**< fringe pair of the shot: upper (s_0) and lower (s_1)
                                         interferometer, populations normalised by the atom number */
    int64_t ca_utime;               /**< time of the shot, microseconds */
    int32_t ca_status;              /**< GG_SENSOR_OK: a new shot; GG_SENSOR_BAD: a failed shot (no
                                         pair); GG_SENSOR_ABSENT: no new shot this step */
} gg_frame_t;

/** Health bits of the navigation output (a bit set = condition present this step). */
#define GG_HEALTH_NOT_INIT        0x00000001u  /**< no valid navigation state yet */
#define GG_HEALTH_ACC_NONFINITE   0x00000002u  /**< an accelerometer reading was NaN/Inf */
#define GG_HEALTH_ACC_RANGE       0x00000004u  /**< an accelerometer reading was out of range */
#define GG_HEALTH_ACC_SENSOR      0x00000008u  /**< an accelerometer flagged its sample bad/absent */
#define GG_HEALTH_SEQ_GAP         0x00000010u  /**< seq skipped forward */
#define GG_HEALTH_SEQ_REPEAT      0x00000020u  /**< seq repeated or went backwards */
#define GG_HEALTH_TIME_JUMP       0x00000040u  /**< utime step differs from the configured step */
#define GG_HEALTH_GAMMA_ASYM      0x00000080u  /**< gradient symmetry residual above threshold */
#define GG_HEALTH_FRAME_REJECTED  0x00000100u  /**< frame not used; state propagated no further */
#define GG_HEALTH_DEADLINE        0x00000200u  /**< step took longer than the step period */
#define GG_HEALTH_BARO_INVALID    0x00000400u /**< barometer sample NaN/Inf, out of range or bad */
#define GG_HEALTH_BARO_STALE      0x00000800u /**< barometer sample too old */
#define GG_HEALTH_BARO_OUTLIER    0x00001000u /**< barometer sample rejected by the innovation gate */
#define GG_HEALTH_BARO_RECAPTURE  0x00002000u /**< gate overridden after repeated rejections */
#define GG_HEALTH_BARO_COAST      0x00004000u /**< vertical channel coasting: no barometer accepted lately */
#define GG_HEALTH_ACC_FAULT       0x00008000u /**< accelerometer parity check failed this step */
#define GG_HEALTH_ACC_REBUILT     0x00010000u /**< degraded: readings rebuilt from parity (see acc_excluded) */
#define GG_HEALTH_GRAD_COAST      0x00020000u /**< degraded: a gradient component coasts on its last good value */
#define GG_HEALTH_MODEL_OUTSIDE   0x00040000u /**< gravity-model mode: outside the programmed anomaly grid */
#define GG_HEALTH_GYRO_INVALID    0x00080000u /**< 3-D strapdown: gyro sample NaN/Inf, out of range or flagged bad */
#define GG_HEALTH_RESYNC          0x00100000u /**< the task re-synchronised to the frame stream (seq/clock) at this frame */
#define GG_HEALTH_COAST           0x00200000u /**< degraded: steps propagated on the last usable inputs (outage) */
#define GG_HEALTH_PF_SHOT_INVALID 0x00400000u /**< cold-atom aid: shot NaN/Inf or out of range (used as a failed shot)
                                                   or dropped (filter busy, frame not used) */
#define GG_HEALTH_PF_FAIL         0x00800000u /**< cold-atom aid: no map tile at the position, every candidate
                                                   off the map (weights reset) or an operation rejected */
#define GG_HEALTH_ACC_DEGRADED    0x01000000u /**< degraded: an accelerometer axis group lost more readings
                                                   than parity rebuilds; its gradient components from
                                                   symmetry or held (GRAD_COAST), see fdi2d.h */
#define GG_HEALTH_FORCE_COAST     0x02000000u /**< degraded: no reading of an axis usable, its centre
                                                   specific force held on the last good value */
#define GG_HEALTH_ACC_FROZEN      0x04000000u /**< an accelerometer reading kept one value over the configured
                                                   frames (stuck): set aside as known bad (navtask.h) */
/* 3-D gradient-map aid (aid_mmukf.h), the top bits */
#define GG_HEALTH_MM_BAD_MEAS     0x08000000u /**< map aid: epoch postponed, the gradient was rebuilt, bridged or coasting */
#define GG_HEALTH_MM_NO_MAP       0x10000000u /**< map aid: no tile of the map storage covers the position (epoch skipped) */
#define GG_HEALTH_MM_GATED        0x20000000u /**< map aid: the epoch's innovation failed the NIS gate (no correction) */
#define GG_HEALTH_MM_FAIL         0x40000000u /**< map aid: UKF operation rejected (not PD, sigma point off the tile) or correction not applied */
#define GG_HEALTH_AID_INTEGRITY   0x80000000u  /**< an aid's integrity monitor (aid_integ.h) is SUSPECT (de-weighted) or ISOLATED
                                                     (no correction fed): which, in the output's mm_integ / pf_integ */

/** Timed firmware modules (index into gg_nav_output_t.cycles). */
enum {
    GG_MOD_DIFF = 0,    /**< accelerometer differencing */
    GG_MOD_GRAVDR = 1,  /**< gravity dead reckoning */
    GG_MOD_MECH = 2,    /**< mechanization (and the onboard gravity model in model mode) */
    GG_MOD_VCHAN = 3,   /**< barometric vertical channel */
    GG_MOD_TOTAL = 4,   /**< whole navigation step */
    GG_MOD_AID_MM = 5,  /**< gradient-map UKF aid of the 3-D task (aid_mmukf.h); 0 in 2-D */
    GG_MOD_AID_PF = 6,  /**< cold-atom particle-filter aid of the 3-D task (aid_pf.h); 0 in 2-D */
    GG_MOD_COUNT = 7
};

/** Navigation output of one step. */
typedef struct {
    int64_t utime;              /**< time of the frame this output answers, microseconds */
    int64_t seq;                /**< seq of that frame */
    int32_t status;             /**< gg_status_t of the step */
    uint32_t health;            /**< GG_HEALTH_* bits */
    double r_i[3];              /**< position of the platform centre, inertial, m */
    double v_i[3];              /**< velocity, inertial, m/s */
    double g_i[3];              /**< gravitation G at the estimated position, inertial, m/s^2 */
    double gamma_i[3][3];       /**< gradient Gamma[j][k] = dG_j/dx_k, s^-2 */
    double f_i[3];              /**< specific force at the platform centre, m/s^2 */
    double gamma_asym;          /**< symmetry residual Gamma_xz - Gamma_zx, s^-2 */
    double h_ins_m;             /**< inertial altitude |r| - R_ref, m */
    double baro_innov_m;        /**< last barometer innovation h_ins - h_baro, m (0 if none) */
    double parity_f[2];         /**< accelerometer parity residuals p_x, p_z, m/s^2 (fdi2d.h) */
    uint32_t acc_excluded;      /**< readings excluded for good, bit 2*sensor+axis (fdi2d.h) */
    uint32_t acc_rebuilt;       /**< readings rebuilt this step (known bad or excluded) */
    double g_up_corr;           /**< vertical loop's integral state a_c, m/s^2: the up
                                     acceleration the loop removes. In gravity-model mode
                                     -a_c estimates the vertical gravity disturbance
                                     (true minus model, along up; airborne gravimeter) */
    uint32_t cycles[GG_MOD_COUNT]; /**< HAL cycle-counter ticks per module this step */
    uint32_t resync_count;      /**< re-synchronisations to the frame stream so far (navtask.h) */
    uint32_t coast_steps;       /**< steps propagated on held inputs so far (outages) */
    double outage_s;            /**< time since the readings of a frame last entered the state, s
                                     (0 when this frame's did) */
    double state_lag_s;         /**< how far the state's time is behind this frame's, s (0 when
                                     the frame was used; up to the bridge during an outage) */
} gg_nav_output_t;

#endif /* GGINS_FRAME_H */
