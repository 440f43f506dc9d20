/* Frame-stream following and outage planning (navtask.h), against the rules
 * worked out by hand: which frames are trusted, at which step index, when
 * the stream re-synchronises and how far the task clock runs on; and what a
 * frame does to a lagging state (coast, bridge, use); and when the
 * frozen-reading monitor calls a reading stuck. */
#include "test_common.h"
#include "ggins/navtask.h"

#define DT 10000

static gg_frame_t frame(int64_t seq, int64_t utime)
{
    gg_frame_t f;
    memset(&f, 0, sizeof f);
    f.seq = seq;
    f.utime = utime;
    return f;
}

/* offer frame (seq, utime); return its step (-1 untrusted), health in *h */
static int64_t offer(gg_task_seq_t *s, int64_t seq, int64_t utime, uint32_t *h)
{
    gg_frame_t f = frame(seq, utime);
    int64_t step = -2;
    *h = gg_task_seq_update(s, &f, &step);
    return step;
}

static void start(gg_task_seq_t *s, int64_t tol, int64_t n)
{
    uint32_t h;
    assert_int_equal(gg_task_seq_init(s, DT, tol), GG_OK);
    for (int64_t k = 0; k < n; ++k) {
        assert_int_equal(offer(s, 100 + k, 5000000 + k * DT, &h), k);
        assert_int_equal(h, 0);
    }
}

static void test_init(void **state)
{
    (void)state;
    gg_task_seq_t s;
    assert_int_equal(gg_task_seq_init(NULL, DT, 0), GG_ERR_NULL);
    assert_int_equal(gg_task_seq_init(&s, 0, 0), GG_ERR_CONFIG);
    assert_int_equal(gg_task_seq_init(&s, DT, DT), GG_ERR_CONFIG);
    assert_int_equal(gg_task_seq_init(&s, DT, -1), GG_ERR_CONFIG);
    assert_int_equal(gg_task_seq_init(&s, DT, 0), GG_OK);
    /* 600 s at 100 Hz */
    assert_int_equal(s.max_outage_steps, 60000);
}

/* consistent frames, lost frames, repeats, a lone glitch */
static void test_stream(void **state)
{
    (void)state;
    gg_task_seq_t s;
    uint32_t h;
    start(&s, 0, 10); /* seq 100..109 = steps 0..9 */
    /* three lost: seq 113 at step 13 */
    assert_int_equal(offer(&s, 113, 5000000 + 13 * DT, &h), 13);
    assert_int_equal(h, GG_HEALTH_SEQ_GAP);
    /* a repeat and a backward seq are not trusted and change nothing */
    assert_int_equal(offer(&s, 113, 5000000 + 13 * DT, &h), -1);
    assert_int_equal(h, GG_HEALTH_SEQ_REPEAT);
    assert_int_equal(offer(&s, 50, 5000000 + 14 * DT, &h), -1);
    assert_int_equal(h, GG_HEALTH_SEQ_REPEAT);
    /* a lone time glitch (1 us off, tolerance 0) is rejected, the next frame
     * is the stream's next after one lost */
    assert_int_equal(offer(&s, 114, 5000000 + 14 * DT + 1, &h), -1);
    assert_int_equal(h, GG_HEALTH_TIME_JUMP);
    assert_int_equal(offer(&s, 115, 5000000 + 15 * DT, &h), 15);
    assert_int_equal(h, GG_HEALTH_SEQ_GAP);
    assert_int_equal(s.resyncs, 0U);
    /* out of range: never trusted */
    assert_int_equal(offer(&s, 116, -1, &h), -1);
    assert_int_equal(h, GG_HEALTH_TIME_JUMP);
    assert_int_equal(offer(&s, INT64_MAX, 5000000 + 16 * DT, &h), -1);
    assert_int_equal(h, GG_HEALTH_TIME_JUMP);
    /* a long but consistent gap (10 min less a step) is trusted */
    assert_int_equal(offer(&s, 115 + 60000, 5000000 + (15 + 60000) * DT, &h), 15 + 60000);
    /* one longer is not */
    assert_int_equal(offer(&s, 115 + 60000 + 60002, 5000000 + (15 + 60000 + 60002) * DT, &h), -1);
    assert_int_equal(h, GG_HEALTH_SEQ_GAP | GG_HEALTH_TIME_JUMP);
}

/* A lasting clock step of 1 us (tolerance 0): the first two frames after it
 * are candidates, the third re-synchronises at the counter's step; the task
 * clock runs on continuously (offset -1 us). */
static void test_clock_step(void **state)
{
    (void)state;
    gg_task_seq_t s;
    uint32_t h;
    start(&s, 0, 10);
    assert_int_equal(offer(&s, 110, 5000000 + 10 * DT + 1, &h), -1);
    assert_int_equal(h, GG_HEALTH_TIME_JUMP);
    assert_int_equal(offer(&s, 111, 5000000 + 11 * DT + 1, &h), -1);
    assert_int_equal(offer(&s, 112, 5000000 + 12 * DT + 1, &h), 12);
    assert_int_equal(h, GG_HEALTH_RESYNC);
    assert_int_equal(s.resyncs, 1U);
    assert_int_equal(gg_task_seq_clock(&s, 5000000 + 12 * DT + 1), 5000000 + 12 * DT);
    assert_int_equal(offer(&s, 113, 5000000 + 13 * DT + 1, &h), 13);
    assert_int_equal(h, 0);
    /* a time jump that lasts (+5 ms, then back): two re-synchronisations, the
     * counter keeps the step count exact */
    for (int64_t k = 14; k < 134; ++k) {
        const int64_t st = offer(&s, 100 + k, 5000000 + k * DT + 1 + 5000, &h);
        assert_int_equal(st, (k < 16) ? -1 : k);
    }
    assert_int_equal(s.resyncs, 2U);
    for (int64_t k = 134; k < 140; ++k) {
        const int64_t st = offer(&s, 100 + k, 5000000 + k * DT + 1, &h);
        assert_int_equal(st, (k < 136) ? -1 : k);
    }
    assert_int_equal(s.resyncs, 3U);
    assert_int_equal(gg_task_seq_clock(&s, 5000000 + 139 * DT + 1), 5000000 + 139 * DT);
}

/* A stream whose first time stamp is 65 489 us short of the end of the
 * accepted range (a fuzz finding): the task clock starts at half the range,
 * so that it stays inside it while the frame clock leaves it. Frames beyond
 * the range are refused; the stream re-synchronises on the frames after a
 * restart of both counter and clock, and the task clock is still inside the
 * range, on by the steps. A stream starting low keeps the frame clock. */
static void test_clock_near_range_end(void **state)
{
    (void)state;
    gg_task_seq_t s;
    uint32_t h;
    const int64_t t0 = GG_TIME_MAX - 65489;
    assert_int_equal(gg_task_seq_init(&s, DT, 0), GG_OK);
    for (int64_t k = 0; k < 7; ++k) {
        assert_int_equal(offer(&s, k, t0 + k * DT, &h), k);
        assert_int_equal(h, 0);
        assert_int_equal(gg_task_seq_clock(&s, t0 + k * DT), GG_TIME_MAX / 2 + k * DT);
    }
    /* the frame clock leaves the range: refused */
    assert_int_equal(offer(&s, 7, t0 + 7 * DT, &h), -1);
    assert_int_equal(h, GG_HEALTH_TIME_JUMP);
    /* both restart; three frames re-synchronise (counter back, clock back:
     * one step of outage, flagged) */
    assert_int_equal(offer(&s, 0, 1000, &h), -1);
    assert_int_equal(offer(&s, 1, 1000 + DT, &h), -1);
    assert_int_equal(offer(&s, 2, 1000 + 2 * DT, &h), 9);
    assert_int_equal(h, GG_HEALTH_RESYNC | GG_HEALTH_TIME_JUMP);
    assert_int_equal(gg_task_seq_clock(&s, 1000 + 2 * DT), GG_TIME_MAX / 2 + 9 * DT);
    for (int64_t k = 3; k < 100; ++k) {
        assert_int_equal(offer(&s, k, 1000 + k * DT, &h), k + 7);
        assert_int_equal(h, 0);
    }
    /* the latest start kept as it is */
    assert_int_equal(gg_task_seq_init(&s, DT, 0), GG_OK);
    assert_int_equal(offer(&s, 0, GG_TIME_MAX / 2, &h), 0);
    assert_int_equal(gg_task_seq_clock(&s, GG_TIME_MAX / 2), GG_TIME_MAX / 2);
    assert_int_equal(gg_task_seq_init(&s, DT, 0), GG_OK);
    assert_int_equal(offer(&s, 0, GG_TIME_MAX / 2 + 1, &h), 0);
    assert_int_equal(gg_task_seq_clock(&s, GG_TIME_MAX / 2 + 1), GG_TIME_MAX / 2);
}

/* The counter restarts (seq back to 0) while the clock runs on: the clock
 * gives the outage (5 steps). The clock goes back while the counter runs on:
 * the counter gives it. Both jump: one step, flagged. */
static void test_restart(void **state)
{
    (void)state;
    gg_task_seq_t s;
    uint32_t h;
    start(&s, 0, 10); /* last: seq 109, step 9, utime 5000000 + 9 DT */
    assert_int_equal(offer(&s, 0, 5000000 + 14 * DT, &h), -1);
    assert_int_equal(offer(&s, 1, 5000000 + 15 * DT, &h), -1);
    assert_int_equal(offer(&s, 2, 5000000 + 16 * DT, &h), 16);
    assert_int_equal(h, GG_HEALTH_RESYNC);
    /* the clock steps back 1 s, the counter on by 3 */
    assert_int_equal(offer(&s, 5, 4000000, &h), -1);
    assert_int_equal(offer(&s, 6, 4000000 + DT, &h), -1);
    assert_int_equal(offer(&s, 7, 4000000 + 2 * DT, &h), 16 + 3 + 2);
    assert_int_equal(h, GG_HEALTH_RESYNC);
    assert_int_equal(gg_task_seq_clock(&s, 4000000 + 2 * DT), 5000000 + 21 * DT);
    /* both back: one step, and the outage is unknown */
    assert_int_equal(offer(&s, 1, 1000, &h), -1);
    assert_int_equal(offer(&s, 2, 1000 + DT, &h), -1);
    assert_int_equal(offer(&s, 3, 1000 + 2 * DT, &h), 21 + 1 + 2);
    assert_int_equal(h, GG_HEALTH_RESYNC | GG_HEALTH_TIME_JUMP);
    assert_int_equal(s.resyncs, 3U);
    /* candidates must be consecutive: alternating junk never re-synchronises */
    for (int k = 0; k < 50; ++k) {
        assert_int_equal(offer(&s, 1000000 + 7 * k, 90000000 + 3 * k, &h), -1);
    }
    assert_int_equal(s.resyncs, 3U);
    /* an out-of-range frame breaks a candidate run */
    assert_int_equal(offer(&s, 500, 7000000, &h), -1);
    assert_int_equal(offer(&s, 501, 7000000 + DT, &h), -1);
    assert_int_equal(offer(&s, 502, -5, &h), -1);
    assert_int_equal(offer(&s, 503, 7000000 + 3 * DT, &h), -1);
    assert_int_equal(s.resyncs, 3U);
}

static void test_plan(void **state)
{
    (void)state;
    gg_task_plan_t p;
    /* the next frame */
    gg_task_plan(11, 10, 1, 100, &p);
    assert_true(p.coast == 0 && p.bridge == 0 && p.use == 1);
    /* 100 lost: bridged */
    gg_task_plan(111, 10, 1, 100, &p);
    assert_true(p.coast == 0 && p.bridge == 100 && p.use == 1);
    /* 101 lost: one step coasted, then 100 bridged */
    gg_task_plan(112, 10, 1, 100, &p);
    assert_true(p.coast == 1 && p.bridge == 100 && p.use == 1);
    /* unusable readings with 101 lost: one step coasted, frame not used */
    gg_task_plan(112, 10, 0, 100, &p);
    assert_true(p.coast == 1 && p.bridge == 0 && p.use == 0);
    /* unusable, within the bridge: nothing */
    gg_task_plan(50, 10, 0, 100, &p);
    assert_true(p.coast == 0 && p.bridge == 0 && p.use == 0);
    /* far behind: catch up GG_TASK_CATCHUP_STEPS, not usable yet */
    gg_task_plan(10000, 10, 1, 100, &p);
    assert_true(p.coast == GG_TASK_CATCHUP_STEPS && p.bridge == 0 && p.use == 0);
    /* last catch-up frame */
    gg_task_plan(10 + 101 + GG_TASK_CATCHUP_STEPS, 10, 1, 100, &p);
    assert_true(p.coast == GG_TASK_CATCHUP_STEPS && p.bridge == 100 && p.use == 1);
    /* a frame not ahead of the state does nothing */
    gg_task_plan(10, 10, 1, 100, &p);
    assert_true(p.coast == 0 && p.bridge == 0 && p.use == 0);
}

/* The frozen-reading monitor, frame by frame by hand: with a window of 4,
 * a reading is stuck at the 4th used frame of one value, stays stuck while it
 * keeps it, and is usable at once when it changes; a lo part that changes is
 * a change; a check alone (a frame not used) moves nothing; off (0) flags
 * nothing; readings beyond n_acc are not looked at. */
static void test_frozen(void **state)
{
    gg_task_frozen_t m;
    gg_frame_t f = frame(0, 0);
    (void)state;
    assert_int_equal(gg_task_frozen_init(&m, 1), GG_ERR_CONFIG);
    assert_int_equal(gg_task_frozen_init(&m, -1), GG_ERR_CONFIG);
    assert_int_equal(gg_task_frozen_init(&m, GG_LIM_FROZEN_FRAMES_MAX + 1), GG_ERR_CONFIG);
    assert_int_equal(gg_task_frozen_init(NULL, 4), GG_ERR_NULL);
    assert_int_equal(gg_task_frozen_init(&m, 4), GG_OK);
    /* sensor 1 axis 2 (bit 5) stuck at 9.8; sensor 0 axis 0 (bit 0) changes every frame;
       every other reading is 0 and stays 0: stuck too */
    const uint32_t all = (1U << 12) - 1U; /* 4 sensors x 3 axes */
    for (int k = 0; k < 6; ++k) {
        f.f[1][2] = 9.8;
        f.f[0][0] = 1.0 + 0.001 * k;
        const uint32_t bits = gg_task_frozen_check(&m, &f, 4);
        if (k < 3) {
            assert_int_equal(bits, 0U); /* 1..3 frames of one value */
        } else {
            assert_int_equal(bits, all & ~1U); /* the 4th frame on: every constant reading */
        }
        /* checking again without committing gives the same answer */
        assert_int_equal(gg_task_frozen_check(&m, &f, 4), bits);
        gg_task_frozen_commit(&m, &f, 4);
    }
    /* a change of the lo part alone: usable again, and one value for 4 frames from here */
    f.f_lo[1][2] = 1e-16;
    assert_int_equal(gg_task_frozen_check(&m, &f, 4) & (1U << 5), 0U);
    gg_task_frozen_commit(&m, &f, 4);
    assert_int_equal(gg_task_frozen_check(&m, &f, 4) & (1U << 5), 0U); /* 2nd */
    gg_task_frozen_commit(&m, &f, 4);
    assert_int_equal(gg_task_frozen_check(&m, &f, 4) & (1U << 5), 0U); /* 3rd */
    gg_task_frozen_commit(&m, &f, 4);
    assert_int_not_equal(gg_task_frozen_check(&m, &f, 4) & (1U << 5), 0U); /* 4th */
    /* NaN never repeats (it is a known-bad reading anyway) */
    f.f[1][2] = NAN;
    gg_task_frozen_commit(&m, &f, 4);
    assert_int_equal(gg_task_frozen_check(&m, &f, 4) & (1U << 5), 0U);
    /* only sensors below n_acc; n_acc out of range is clamped */
    assert_int_equal(gg_task_frozen_check(&m, &f, 1) & ~7U, 0U);
    assert_int_equal(gg_task_frozen_check(&m, &f, -3), 0U);
    (void)gg_task_frozen_check(&m, &f, 99);
    /* off: nothing, however long a value is kept */
    assert_int_equal(gg_task_frozen_init(&m, 0), GG_OK);
    for (int k = 0; k < 10; ++k) {
        assert_int_equal(gg_task_frozen_check(&m, &f, 6), 0U);
        gg_task_frozen_commit(&m, &f, 6);
    }
    assert_int_equal(gg_task_frozen_check(NULL, &f, 6), 0U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_stream),
        cmocka_unit_test(test_clock_step),
        cmocka_unit_test(test_restart),
        cmocka_unit_test(test_clock_near_range_end),
        cmocka_unit_test(test_plan),
        cmocka_unit_test(test_frozen),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
