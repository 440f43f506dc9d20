/* Helpers shared by the navigation tasks (nav2d.h, nav3d.h): frame
 * sequencing, reading plausibility and the per-step cycle accounting.
 * No state of their own; each returns health bits (frame.h, GG_HEALTH_*)
 * for the caller to OR into its output.
 *
 * Sequencing rules (docs/robustness.md): a frame with seq or utime outside
 * [0, GG_TIME_MAX] is a time jump (differences could overflow); after the
 * stream's first frame, seq <= last_seq is a repeat; a frame n + 1 steps on
 * in both seq and utime (within dt_tol_us), n lost frames, is the stream's
 * next; anything else is a gap/time jump. The stream moves on with every
 * consistent frame, usable or not, so that a run of rejected readings never
 * leaves the task behind it; GG_TASK_RESYNC_FRAMES consistent frames that
 * disagree with it re-synchronise it (GG_HEALTH_RESYNC).
 * Recovery: while the navigation state lags the stream by more than the
 * bridge (a long outage), each frame coasts it on the last usable inputs
 * (GG_TASK_CATCHUP_STEPS at most), so the task always navigates.
 */
#ifndef GGINS_NAVTASK_H
#define GGINS_NAVTASK_H

#include "ggins/frame.h"
#include "ggins/hal.h"
#include "ggins/limits.h"
#include "ggins/real.h"
#include "ggins/status.h"

#include <stddef.h>
#include <stdint.h>

/** A reading's low part (f_lo, m/s^2) above this is malformed: a residual
 *  below double resolution cannot exceed ulp(f_max)/2, far below 1e-9. */
#define GG_TASK_F_LO_MAX 1e-9

/** Frames in a row, each one step after the previous in seq and time, that
 *  re-synchronise the task to a stream it lost (a clock step, a restarted
 *  counter, a run of frames too long to bridge). A lone glitch never does. */
#define GG_TASK_RESYNC_FRAMES 3

/** Steps coasted per frame on held inputs while the navigation state lags the
 *  stream by more than the bridge: a long outage is caught up at this rate
 *  (each coast step costs one navigation step of cycles). */
#define GG_TASK_CATCHUP_STEPS 10

/** Longest outage carried through by propagation, s. A re-synchronisation
 *  across a longer break (or across a clock that went backwards with a
 *  restarted counter) propagates one step and flags GG_HEALTH_TIME_JUMP. */
#define GG_TASK_MAX_OUTAGE_S 600

/** Latest start of the task clock, us. The task clock starts on the frame
 *  clock of the first frame, or at this value if that frame is later: half
 *  of GG_TIME_MAX leaves ~73 000 years of steps before the clock could leave
 *  the accepted range, whatever time stamp the stream starts with. */
#define GG_TASK_CLOCK_START_MAX (GG_TIME_MAX / 2)

/** The frame stream as the task has followed it. Every frame whose
 *  sequencing is consistent (seq on by n + 1 and utime by (n + 1) dt within
 *  dt_tol, n lost frames) moves it on, whether or not its readings are
 *  usable; a frame that is not starts or extends a run of candidates, and
 *  GG_TASK_RESYNC_FRAMES consistent candidates re-synchronise the stream.
 *  Steps are counted on the task's own clock (step index, and utime mapped
 *  by clock_offset_us), which stays continuous and monotonic whatever the
 *  frames' clock does. */
typedef struct {
    int64_t dt_us;             /**< fixed step, us (> 0) */
    int64_t dt_tol_us;         /**< tolerated |utime step - dt_us|, us */
    int64_t max_outage_steps;  /**< GG_TASK_MAX_OUTAGE_S in steps */
    int started;               /**< a frame has been taken as the stream's start */
    int64_t last_seq;          /**< seq of the stream's last frame */
    int64_t last_utime;        /**< its time stamp (frame clock), us */
    int64_t last_step;         /**< its step index (task clock) */
    int64_t clock_offset_us;   /**< task clock = frame clock + offset, us */
    int32_t n_cand;            /**< candidate frames in the current run */
    int64_t cand_seq;          /**< last candidate's seq */
    int64_t cand_utime;        /**< last candidate's utime, us */
    int64_t cand_first_seq;    /**< first candidate's seq */
    int64_t cand_first_utime;  /**< first candidate's utime, us */
    uint32_t resyncs;          /**< re-synchronisations so far */
} gg_task_seq_t;

/** What a frame does to the navigation state, from the stream position of
 *  the frame and of the state (gg_task_plan). */
typedef struct {
    int64_t coast;   /**< steps to coast on the held inputs first */
    int64_t bridge;  /**< lost steps to bridge by interpolation up to this frame */
    int use;         /**< 1: the frame's readings advance the state to its step */
} gg_task_plan_t;

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

/** Frozen-reading monitor. A noisy accelerometer never repeats its reading
 *  (hi and lo parts) bit for bit over many frames: white noise of sigma
 *  over a double's resolution eps repeats with probability below eps/sigma
 *  a frame. A reading that does, over `frames` used frames in a row, is
 *  taken as stuck (GG_HEALTH_ACC_FROZEN) and set aside as a known-bad
 *  reading, to be rebuilt or held like a NaN one, for as long as it keeps
 *  that value. This is the one check that sees an equal stuck fault on every
 *  reading of an axis, which moves no parity relation (fdi2d.h, fdi3d.h).
 *  Off (frames = 0) for noise-free sensors: an exact reading of a constant
 *  field is constant. The readings compared are those of the frames whose
 *  readings entered the state (gg_task_frozen_commit), so a rejected frame
 *  leaves the monitor as it was. */
typedef struct {
    int32_t frames;                /**< used frames in a row with one value that make a reading
                                        frozen (2..GG_LIM_FROZEN_FRAMES_MAX; 0: off) */
    double last[GG_MAX_ACC][3];    /**< the readings of the last used frame, m/s^2 (hi parts) */
    double last_lo[GG_MAX_ACC][3]; /**< and their lo parts, m/s^2 */
    int32_t run[GG_MAX_ACC][3];    /**< used frames in a row, up to the last, in which the
                                        reading had its value (1..frames; 0: no frame yet) */
} gg_task_frozen_t;

/** The monitor's bit of reading (sensor, axis): 3 * sensor + axis (as GG_FDI3D_BIT). */
#define GG_TASK_READING_BIT(sensor, axis) (1u << ((3u * (uint32_t)(sensor)) + (uint32_t)(axis)))

/** Set up the monitor: frames = 0 (off) or 2..GG_LIM_FROZEN_FRAMES_MAX;
 *  GG_ERR_CONFIG otherwise. */
gg_status_t gg_task_frozen_init(gg_task_frozen_t *m, int32_t frames);

/** The readings of fr's accelerometers 0..n_acc-1 (n_acc <= GG_MAX_ACC)
 *  that are frozen if fr is used: bit 3 * sensor + axis set when the reading
 *  equals the last used frame's and so completes a run of `frames` used frames
 *  with one value. Reads the monitor only; 0 when it is off. */
uint32_t gg_task_frozen_check(const gg_task_frozen_t *m, const gg_frame_t *fr, int32_t n_acc);

/** Take the readings of a used frame fr into the monitor (the raw readings,
 *  before any rebuilding). */
void gg_task_frozen_commit(gg_task_frozen_t *m, const gg_frame_t *fr, int32_t n_acc);

/** Start following a stream of fixed step dt_us (> 0), tolerance dt_tol_us
 *  (0 <= tol < dt). GG_ERR_CONFIG otherwise. */
gg_status_t gg_task_seq_init(gg_task_seq_t *seq, int64_t dt_us, int64_t dt_tol_us);

/** Follow one frame. Returns its sequencing health bits (GG_HEALTH_TIME_JUMP,
 *  GG_HEALTH_SEQ_REPEAT, GG_HEALTH_SEQ_GAP, GG_HEALTH_RESYNC); *step = the
 *  frame's step index on the task clock when its sequencing is trusted, -1
 *  when it is not (the frame must not advance the state). The first frame
 *  ever is step 0. */
uint32_t gg_task_seq_update(gg_task_seq_t *seq, const gg_frame_t *fr, int64_t *step);

/** The frame's time stamp on the task clock, us (only for a trusted frame). */
int64_t gg_task_seq_clock(const gg_task_seq_t *seq, int64_t utime);

/** *ft = *fr with its time stamps (frame and barometer sample) on the task
 *  clock, so that they run on continuously through a re-synchronisation. */
void gg_task_seq_map_frame(const gg_task_seq_t *seq, const gg_frame_t *fr, gg_frame_t *ft);

/** How long the readings have been out of the state and how far the state
 *  lags the stream, s, for a task whose state (started != 0) is at
 *  state_step and last used a frame at input_step; 0 before it started. */
void gg_task_outage(const gg_task_seq_t *seq, int started, int64_t state_step, int64_t input_step,
                    int64_t dt_us, double *outage_s, double *lag_s);

/** Plan a trusted frame at frame_step against a started state at state_step
 *  (< frame_step): coast up to GG_TASK_CATCHUP_STEPS steps while the lag
 *  exceeds max_bridge + 1, then, when the readings are usable (usable != 0)
 *  and what is left fits the bridge, bridge and use the frame. */
void gg_task_plan(int64_t frame_step, int64_t state_step, int usable, int64_t max_bridge,
                  gg_task_plan_t *plan);

/** Close a step's cycle accounting: cyc[GG_MOD_TOTAL] = now - t_start,
 *  copies cyc into out_cycles; returns GG_HEALTH_DEADLINE when the total
 *  exceeds the step budget dt_us at the HAL's clock, else 0. */
uint32_t gg_task_close_cycles(const gg_hal_t *hal, int64_t dt_us, uint32_t t_start,
                              uint32_t cyc[GG_MOD_COUNT], uint32_t out_cycles[GG_MOD_COUNT]);

#endif /* GGINS_NAVTASK_H */
