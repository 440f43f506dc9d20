/* Helpers shared by the navigation tasks (navtask.h). */
#include "ggins/navtask.h"

#include <stddef.h>

static int64_t abs64(int64_t x)
{
    return (x < 0) ? -x : x;
}

gg_status_t gg_task_seq_init(gg_task_seq_t *seq, int64_t dt_us, int64_t dt_tol_us)
{
    const gg_task_seq_t empty = {0};
    if (seq == NULL) {
        return GG_ERR_NULL;
    }
    if ((dt_us <= 0) || (dt_us > GG_TIME_MAX) || (dt_tol_us < 0) || (dt_tol_us >= dt_us)) {
        return GG_ERR_CONFIG;
    }
    *seq = empty;
    seq->dt_us = dt_us;
    seq->dt_tol_us = dt_tol_us;
    seq->max_outage_steps = ((int64_t)GG_TASK_MAX_OUTAGE_S * 1000000) / dt_us;
    if (seq->max_outage_steps < 1) {
        seq->max_outage_steps = 1;
    }
    return GG_OK;
}

/* The stream moves on to frame fr at step index step. */
static void adopt(gg_task_seq_t *seq, const gg_frame_t *fr, int64_t step)
{
    seq->last_seq = fr->seq;
    seq->last_utime = fr->utime;
    seq->last_step = step;
    seq->n_cand = 0;
}

/* Steps from the stream's last frame to the first frame of the candidate run:
 * the counter's advance when it is plausible (the clock stepped), else the
 * clock's (the counter restarted), else one step (*unknown = 1). */
static int64_t outage_steps(const gg_task_seq_t *seq, int *unknown)
{
    const int64_t dseq = seq->cand_first_seq - seq->last_seq;
    const int64_t dtime = seq->cand_first_utime - seq->last_utime;
    int64_t n = 1;
    *unknown = 0;
    if ((dseq >= 1) && (dseq <= seq->max_outage_steps)) {
        n = dseq;
    } else if ((dtime > 0) && (dtime <= (seq->max_outage_steps * seq->dt_us))) {
        n = (dtime + (seq->dt_us / 2)) / seq->dt_us;
        if (n < 1) {
            n = 1;
        }
    } else {
        *unknown = 1;
    }
    return n;
}

uint32_t gg_task_seq_update(gg_task_seq_t *seq, const gg_frame_t *fr, int64_t *step)
{
    uint32_t h = 0U;
    *step = -1;
    if ((fr->utime < 0) || (fr->utime > GG_TIME_MAX) || (fr->seq < 0) || (fr->seq > GG_TIME_MAX)) {
        seq->n_cand = 0;
        return GG_HEALTH_TIME_JUMP; /* outside the accepted range: differences could overflow */
    }
    if (seq->started == 0) {
        seq->started = 1;
        /* the task clock starts on the frame clock, or lower down where the
         * first frame leaves too little of the range for the flight */
        seq->clock_offset_us =
            (fr->utime > GG_TASK_CLOCK_START_MAX) ? (GG_TASK_CLOCK_START_MAX - fr->utime) : 0;
        adopt(seq, fr, 0);
        *step = 0;
        return 0U;
    }
    if (fr->seq <= seq->last_seq) {
        h |= GG_HEALTH_SEQ_REPEAT;
    } else {
        /* n frames lost in between: the frame must be n + 1 steps on in time too */
        const int64_t n = (fr->seq - seq->last_seq) - 1;
        if (n > seq->max_outage_steps) {
            h |= GG_HEALTH_SEQ_GAP | GG_HEALTH_TIME_JUMP;
        } else {
            const int64_t err = (fr->utime - seq->last_utime) - ((n + 1) * seq->dt_us);
            if (abs64(err) > seq->dt_tol_us) {
                h |= GG_HEALTH_TIME_JUMP;
            } else {
                if (n > 0) {
                    h |= GG_HEALTH_SEQ_GAP;
                }
                *step = seq->last_step + n + 1;
                adopt(seq, fr, *step);
                return h;
            }
        }
    }
    /* inconsistent with the stream: a candidate for a new one */
    if ((seq->n_cand > 0) && (fr->seq > seq->cand_seq) && ((fr->seq - seq->cand_seq) == 1) &&
        (abs64((fr->utime - seq->cand_utime) - seq->dt_us) <= seq->dt_tol_us)) {
        seq->n_cand += 1;
    } else {
        seq->n_cand = 1;
        seq->cand_first_seq = fr->seq;
        seq->cand_first_utime = fr->utime;
    }
    seq->cand_seq = fr->seq;
    seq->cand_utime = fr->utime;
    if (seq->n_cand >= GG_TASK_RESYNC_FRAMES) {
        int unknown = 0;
        const int64_t n1 = outage_steps(seq, &unknown);
        const int64_t s_new = seq->last_step + n1 + (int64_t)(seq->n_cand - 1);
        /* the task clock runs on by the steps, whatever the frames' clock did */
        const int64_t t_task = (seq->last_utime + seq->clock_offset_us) +
                               ((s_new - seq->last_step) * seq->dt_us);
        seq->clock_offset_us = t_task - fr->utime;
        seq->resyncs += 1U;
        adopt(seq, fr, s_new);
        *step = s_new;
        h = GG_HEALTH_RESYNC | ((unknown != 0) ? GG_HEALTH_TIME_JUMP : 0U);
    }
    return h;
}

int64_t gg_task_seq_clock(const gg_task_seq_t *seq, int64_t utime)
{
    return utime + seq->clock_offset_us;
}

void gg_task_seq_map_frame(const gg_task_seq_t *seq, const gg_frame_t *fr, gg_frame_t *ft)
{
    *ft = *fr;
    ft->utime = gg_task_seq_clock(seq, fr->utime);
    if ((fr->baro_utime >= 0) && (fr->baro_utime <= GG_TIME_MAX)) {
        ft->baro_utime = gg_task_seq_clock(seq, fr->baro_utime);
    }
}

void gg_task_outage(const gg_task_seq_t *seq, int started, int64_t state_step, int64_t input_step,
                    int64_t dt_us, double *outage_s, double *lag_s)
{
    *outage_s = 0.0;
    *lag_s = 0.0;
    if (started != 0) {
        const int64_t d_in = seq->last_step - input_step;
        const int64_t d_state = seq->last_step - state_step;
        const gg_real_t dt_s = (gg_real_t)dt_us * 1.0e-6L;
        *outage_s = (double)((gg_real_t)d_in * dt_s);
        *lag_s = (double)((gg_real_t)d_state * dt_s);
    }
}

void gg_task_plan(int64_t frame_step, int64_t state_step, int usable, int64_t max_bridge,
                  gg_task_plan_t *plan)
{
    const int64_t lag = frame_step - state_step;
    int64_t coast = lag - 1 - max_bridge;
    plan->coast = 0;
    plan->bridge = 0;
    plan->use = 0;
    if (lag >= 1) {
        if (coast < 0) {
            coast = 0;
        }
        if (coast > GG_TASK_CATCHUP_STEPS) {
            coast = GG_TASK_CATCHUP_STEPS;
        }
        plan->coast = coast;
        if ((usable != 0) && ((lag - coast - 1) <= max_bridge)) {
            plan->use = 1;
            plan->bridge = lag - coast - 1;
        }
    }
}

uint32_t gg_task_close_cycles(const gg_hal_t *hal, int64_t dt_us, uint32_t t_start,
                              uint32_t cyc[GG_MOD_COUNT], uint32_t out_cycles[GG_MOD_COUNT])
{
    uint32_t h = 0U;
    size_t m;
    cyc[GG_MOD_TOTAL] = gg_task_cycles(hal) - t_start;
    if ((hal != NULL) && (hal->cycle_count != NULL) && (hal->cycles_per_second > 0U)) {
        const uint64_t budget = ((uint64_t)dt_us * (uint64_t)hal->cycles_per_second) / 1000000U;
        if ((uint64_t)cyc[GG_MOD_TOTAL] > budget) {
            h = GG_HEALTH_DEADLINE;
        }
    }
    for (m = 0U; m < (size_t)GG_MOD_COUNT; ++m) {
        out_cycles[m] = cyc[m];
    }
    return h;
}

gg_status_t gg_task_frozen_init(gg_task_frozen_t *m, int32_t frames)
{
    const gg_task_frozen_t empty = {0};
    if (m == NULL) {
        return GG_ERR_NULL;
    }
    if ((frames != 0) && ((frames < 2) || (frames > GG_LIM_FROZEN_FRAMES_MAX))) {
        return GG_ERR_CONFIG;
    }
    *m = empty;
    m->frames = frames;
    return GG_OK;
}

/* The run of one value the reading (s, j) would have if fr were used: one
 * more than the last used frame's run when it repeats that frame's reading
 * (hi and lo parts; a run of 0 means no frame yet), else 1; at most frames. */
static int32_t frozen_run_after(const gg_task_frozen_t *m, const gg_frame_t *fr, int32_t s, int32_t j)
{
    int32_t run = 1;
    if ((m->run[s][j] > 0) && (fr->f[s][j] == m->last[s][j]) &&
        (fr->f_lo[s][j] == m->last_lo[s][j])) {
        run = (m->run[s][j] < m->frames) ? (m->run[s][j] + 1) : m->frames;
    }
    return run;
}

static int32_t frozen_count(int32_t n_acc)
{
    int32_t n = n_acc;
    if (n < 0) {
        n = 0;
    } else if (n > GG_MAX_ACC) {
        n = GG_MAX_ACC;
    } else {
        /* in range */
    }
    return n;
}

uint32_t gg_task_frozen_check(const gg_task_frozen_t *m, const gg_frame_t *fr, int32_t n_acc)
{
    uint32_t bits = 0U;
    if ((m != NULL) && (fr != NULL) && (m->frames > 0)) {
        const int32_t n = frozen_count(n_acc);
        int32_t s;
        int32_t j;
        for (s = 0; s < n; ++s) {
            for (j = 0; j < 3; ++j) {
                if (frozen_run_after(m, fr, s, j) >= m->frames) {
                    bits |= GG_TASK_READING_BIT(s, j);
                }
            }
        }
    }
    return bits;
}

void gg_task_frozen_commit(gg_task_frozen_t *m, const gg_frame_t *fr, int32_t n_acc)
{
    if ((m != NULL) && (fr != NULL) && (m->frames > 0)) {
        const int32_t n = frozen_count(n_acc);
        int32_t s;
        int32_t j;
        for (s = 0; s < n; ++s) {
            for (j = 0; j < 3; ++j) {
                m->run[s][j] = frozen_run_after(m, fr, s, j);
                m->last[s][j] = fr->f[s][j];
                m->last_lo[s][j] = fr->f_lo[s][j];
            }
        }
    }
}
