/* Helpers shared by the navigation tasks (nav2d.h, nav3d.h): frame
 * sequencing, reading plausibility and the per-step cycle accounting.
 * No state of their own; each returns health bits (frame.h, GG_HEALTH_*)
 * for the caller to OR into its output.
 *
 * Sequencing rules (docs/robustness.md): a frame with seq or utime outside
 * [0, GG_TIME_MAX] is a time jump (differences could overflow); after the
 * first accepted frame, seq <= last_seq is a repeat; n = seq - last_seq - 1
 * lost frames are bridged when n <= max_bridge and utime has moved on by
 * (n + 1) dt_us within dt_tol_us, otherwise it is a gap/time jump.
 */
#ifndef GGINS_NAVTASK_H
#define GGINS_NAVTASK_H

#include "ggins/frame.h"
#include "ggins/hal.h"
#include "ggins/real.h"

#include <stddef.h>
#include <stdint.h>

/** A reading's low part (f_lo, m/s^2) above this is malformed: a residual
 *  below double resolution cannot exceed ulp(f_max)/2, far below 1e-9. */
#define GG_TASK_F_LO_MAX 1e-9

/** The last accepted frame and the step rules, as the sequence check needs them. */
typedef struct {
    int started;         /**< a frame has been accepted */
    int64_t last_seq;    /**< its sequence number */
    int64_t last_utime;  /**< its time stamp, us */
    int64_t dt_us;       /**< fixed step, us (> 0) */
    int64_t dt_tol_us;   /**< tolerated |utime step - dt_us|, us */
    int64_t max_bridge;  /**< most lost frames bridged */
} gg_task_seq_t;

/** Cycle counter of the HAL now; 0 without a HAL or counter. (Inline, as
 *  the next one: called several times per step, a call each cost the 2-D
 *  step 4 % more instructions on the Cortex-M7.) */
static inline uint32_t gg_task_cycles(const gg_hal_t *hal)
{
    uint32_t c = 0U;
    if ((hal != NULL) && (hal->cycle_count != NULL)) {
        c = hal->cycle_count(hal->ctx);
    }
    return c;
}

/** Health bits of one accelerometer reading (hi + lo parts): 0 if usable,
 *  GG_HEALTH_ACC_NONFINITE for NaN/Inf, GG_HEALTH_ACC_RANGE for |f| > f_max
 *  or |lo| > GG_TASK_F_LO_MAX. */
static inline uint32_t gg_task_check_reading(double f, double lo, double f_max)
{
    uint32_t h = 0U;
    if (!GG_ISFINITE(f) || !GG_ISFINITE(lo)) {
        h = GG_HEALTH_ACC_NONFINITE;
    } else if ((f > f_max) || (f < -f_max) || (lo > GG_TASK_F_LO_MAX) ||
               (lo < -GG_TASK_F_LO_MAX)) {
        h = GG_HEALTH_ACC_RANGE;
    } else {
        /* usable */
    }
    return h;
}

/** Health bits of a frame's sequencing against seq (GG_HEALTH_TIME_JUMP,
 *  GG_HEALTH_SEQ_REPEAT, GG_HEALTH_SEQ_GAP); *missing = lost frames to bridge
 *  (left unchanged unless there are some). */
uint32_t gg_task_check_sequence(const gg_task_seq_t *seq, const gg_frame_t *fr, int64_t *missing);

/** Close a step's cycle accounting: cyc[GG_MOD_TOTAL] = now - t_start,
 *  copies cyc into out_cycles; returns GG_HEALTH_DEADLINE when the total
 *  exceeds the step budget dt_us at the HAL's clock, else 0. */
uint32_t gg_task_close_cycles(const gg_hal_t *hal, int64_t dt_us, uint32_t t_start,
                              uint32_t cyc[GG_MOD_COUNT], uint32_t out_cycles[GG_MOD_COUNT]);

#endif /* GGINS_NAVTASK_H */
