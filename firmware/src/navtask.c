/* Helpers shared by the navigation tasks (navtask.h). */
#include "ggins/navtask.h"

#include <stddef.h>

uint32_t gg_task_check_sequence(const gg_task_seq_t *seq, const gg_frame_t *fr, int64_t *missing)
{
    uint32_t h = 0U;
    if ((fr->utime < 0) || (fr->utime > GG_TIME_MAX) || (fr->seq < 0) || (fr->seq > GG_TIME_MAX)) {
        h |= GG_HEALTH_TIME_JUMP; /* outside the accepted range: differences could overflow */
    } else if (seq->started != 0) {
        if (fr->seq <= seq->last_seq) {
            h |= GG_HEALTH_SEQ_REPEAT;
        } else {
            /* n frames missing: bridged if n <= max_bridge and the time stamp
             * is (n + 1) steps on */
            const int64_t n = (fr->seq - seq->last_seq) - 1;
            if (n > seq->max_bridge) {
                h |= GG_HEALTH_SEQ_GAP | GG_HEALTH_TIME_JUMP;
            } else {
                const int64_t dt = fr->utime - seq->last_utime;
                const int64_t err = dt - ((n + 1) * seq->dt_us);
                if ((err > seq->dt_tol_us) || (err < -seq->dt_tol_us)) {
                    h |= GG_HEALTH_TIME_JUMP;
                } else if (n > 0) {
                    h |= GG_HEALTH_SEQ_GAP;
                    *missing = n;
                } else {
                    /* the next step */
                }
            }
        }
    } else {
        /* first frame: nothing to compare with */
    }
    return h;
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
