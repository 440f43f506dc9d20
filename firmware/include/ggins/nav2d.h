/**
 * @file nav2d.h
 * @brief Navigation task of the 2-D gravity-gradiometer INS (Welker,
 *        Pachter & Huffman): wires differencing, gravity dead reckoning and
 *        the space-stabilized mechanization together, one fixed step per
 *        sensor frame.
 *
 * The first accepted frame (time t0) initialises the state at the configured
 * r0, v0 and G0 (the paper assumes G(0) known) and the measured Gamma(t0),
 * f(t0); every later frame advances the state by exactly one step.
 * Frames are validated before any module runs. A reading that is NaN/Inf,
 * out of range or from a sensor flagged bad is flagged and rebuilt from the
 * redundancy of the others (fdi2d.h: one per axis group; a group that loses
 * more degrades - its components from its remaining pairs, the symmetry of
 * the gradient or held on their last good values, GG_HEALTH_ACC_DEGRADED,
 * GRAD_COAST, FORCE_COAST - instead of rejecting the frame); parity
 * checks (when configured) detect and isolate faults the sensors do not
 * report themselves (stuck, stepped, drifting axes) and accommodate them.
 * A malformed frame (too few accelerometers), a first frame that would need
 * held values, or one whose seq/utime is inconsistent
 * (repeated or backward seq, a time stamp not one step - or, after lost
 * frames, n + 1 steps - on), is rejected and flagged in the health word; its
 * readings never reach the navigation state. Up to GG_NAV2D_MAX_BRIDGE lost
 * or rejected frames are bridged (see below). Recovery (navtask.h): the
 * stream is followed through rejected frames, re-synchronised after a clock
 * step or a restarted counter (GG_HEALTH_RESYNC, resync_count), and during
 * an outage longer than the bridge the state is coasted on the last usable
 * gradient and specific force (GG_HEALTH_COAST), so no input, however long or
 * bad, leaves the task unable to navigate; outage_s and state_lag_s say how
 * long and how far behind.
 * Gravity comes from the dead reckoning (gradiometer mode) or from the
 * onboard model (model mode); optionally a barometric vertical channel
 * (vchan.h) damps the vertical mode: the up acceleration is reduced by its
 * integral state, and each accepted barometer sample corrects position and
 * velocity along the local up u = r/|r| (and G by Gamma dr, so that G stays
 * consistent with the corrected position).
 * Accelerometer mapping: frame.f[i][0] (x) and frame.f[i][2] (z) of
 * accelerometers i = 0..3 are the paper's sensors 1..4.
 */
#ifndef GGINS_NAV2D_H
#define GGINS_NAV2D_H

#include <stdint.h>
#include "ggins/diff2d.h"
#include "ggins/fdi2d.h"
#include "ggins/geo.h"
#include "ggins/frame.h"
#include "ggins/gmodel.h"
#include "ggins/gravdr.h"
#include "ggins/hal.h"
#include "ggins/mech.h"
#include "ggins/navtask.h"
#include "ggins/real.h"
#include "ggins/status.h"
#include "ggins/vchan.h"

/** Where the navigation takes G from. */
#define GG_GRAVITY_GRADIOMETER 0 /**< dead-reckoned from the differenced accelerometers */
#define GG_GRAVITY_MODEL 1       /**< onboard model (conventional INS) */

/** Lost frames a step may bridge (a seq gap of n <= this, with a time stamp
 *  n + 1 steps on): the missing steps are flown with the gradient and specific
 *  force interpolated between the frames on either side, flagged
 *  GG_HEALTH_SEQ_GAP. A longer gap is rejected. 100 = 1 s at 100 Hz. */
#define GG_NAV2D_MAX_BRIDGE 100

/** Default altitude reference radius: WGS-84 semi-major axis, m. */
#define GG_R_REF_DEFAULT_M GG_WGS84_A_M

typedef struct {
    gg_diff2d_config_t geometry; /**< half-baselines a (x) and b (z), m */
    int64_t dt_us;               /**< fixed step, microseconds (> 0) */
    int64_t dt_tol_us;           /**< tolerated |utime step - dt_us|, microseconds (>= 0) */
    gg_real_t r0[3];             /**< initial position, inertial, m (y ignored) */
    gg_real_t v0[3];             /**< initial velocity, inertial, m/s (y ignored) */
    gg_real_t g0[3];             /**< initial gravitation G(0), inertial, m/s^2 (y ignored) */
    double f_max;                /**< accelerometer range: |f| above it is out of range, m/s^2 (> 0) */
    double asym_max;             /**< symmetry residual flag threshold, s^-2 (> 0) */
    int gravdr_trapezoid_only;   /**< 0 (default): corrected gravity DR; 1: plain trapezoid */
    int gravity_mode;            /**< GG_GRAVITY_GRADIOMETER or GG_GRAVITY_MODEL */
    gg_gmodel_config_t model;    /**< onboard gravity model (model mode only) */
    int baro_enable;             /**< 1: barometric vertical channel on */
    gg_vchan_config_t baro;      /**< vertical loop (baro_enable only) */
    gg_real_t r_ref_m;           /**< altitude reference: h = |r| - r_ref_m, m (>= 0; 0 selects
                                      GG_R_REF_DEFAULT_M) */
    double fdi_parity_f_max;     /**< accelerometer parity detection threshold, m/s^2 (0: off) */
    double fdi_asym_max;         /**< gradient-symmetry detection threshold, s^-2 (0: off) */
    int32_t acc_frozen_frames;   /**< used frames in a row with one value that make a reading
                                      stuck (navtask.h; 0: off, else 2..GG_LIM_FROZEN_FRAMES_MAX) */
} gg_nav2d_config_t;

typedef struct {
    gg_nav2d_config_t cfg;
    gg_diff2d_t diff;
    gg_fdi2d_t fdi;
    gg_gravdr_t gravdr;
    gg_mech_t mech;
    gg_gmodel_t gmodel;
    gg_vchan_t vchan;
    gg_real_t a_c;               /**< vertical loop's integral state in use, m/s^2 */
    gg_real_t h_ins;
    gg_real_t baro_innov;
    gg_real_t gamma[3][3];       /**< last accepted gradient */
    gg_real_t f_c[3];            /**< last accepted centre specific force */
    gg_real_t asym;
    gg_task_seq_t seq;           /**< the frame stream as followed (navtask.h) */
    gg_task_frozen_t frozen;     /**< frozen-reading monitor (navtask.h) */
    int64_t state_step;          /**< step index of the navigation state (task clock) */
    int64_t state_clock_us;      /**< task-clock time of that step, us */
    int64_t input_step;          /**< step of the last frame whose readings were used */
    uint32_t coast_steps;        /**< steps coasted on held inputs so far */
    int configured;              /**< init succeeded */
    int started;                 /**< first frame accepted */
} gg_nav2d_t;

/** Validate and store the configuration. GG_ERR_CONFIG on zero baseline,
 *  zero/negative step, non-finite initial state or thresholds. */
gg_status_t gg_nav2d_init(gg_nav2d_t *nav, const gg_nav2d_config_t *cfg);

/** Process one frame. Fills *out (state, health) whenever nav, frame and out
 *  are non-NULL; returns GG_OK when the frame was used, an error code when it
 *  was rejected (state untouched).
 *  hal may be NULL; when given, its cycle counter times each module. */
gg_status_t gg_nav2d_step(gg_nav2d_t *nav, const gg_frame_t *frame,
                          const gg_hal_t *hal, gg_nav_output_t *out);

/** One cycle of the navigation task: read a frame through the HAL, step,
 *  publish the output. GG_ERR_NO_DATA when the HAL had no frame. Sets
 *  GG_HEALTH_DEADLINE when the step took longer than dt. */
gg_status_t gg_nav2d_task_cycle(gg_nav2d_t *nav, const gg_hal_t *hal);

#endif /* GGINS_NAV2D_H */
