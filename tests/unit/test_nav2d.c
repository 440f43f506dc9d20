/* Navigation task: the whole 2-D loop fed frames built from the analytic
 * flight and the exact point-mass field at each accelerometer, compared with
 * the truth; frame validation; the HAL cycle through a mock HAL. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/nav2d.h"

#include <complex.h>

static const t_flight_t kFlight = {300.0L, 0.0L, 0.0L};
#define DT_US 10000

static void make_config(gg_nav2d_config_t *cfg)
{
    long double r[3], v[3], a[3], g[3];
    memset(cfg, 0, sizeof *cfg);
    t_flight(&kFlight, 0.0L, r, v, a);
    t_point_mass_g(r, g);
    cfg->geometry.a_m = 0.5L;
    cfg->geometry.b_m = 0.5L;
    cfg->dt_us = DT_US;
    cfg->dt_tol_us = 100;
    for (int j = 0; j < 3; ++j) {
        cfg->r0[j] = r[j];
        cfg->v0[j] = v[j];
        cfg->g0[j] = g[j];
    }
    cfg->f_max = 100.0;
    cfg->asym_max = 1e-9;
    cfg->gravdr_trapezoid_only = 0;
}

static void make_frame(int64_t k, gg_frame_t *fr)
{
    t_make_frame(&kFlight, k, DT_US, 1000000, NULL, 0, fr);
}

/* Perfect sensors, 1 h at 100 Hz: the in-process equivalent of the
 * welker-perfect host-in-the-loop run. */
static void test_perfect_flight_1h(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    const int64_t n = 360000;
    for (int64_t k = 0; k <= n; ++k) {
        make_frame(k, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        assert_int_equal(out.health, 0);
    }
    long double r[3], v[3], a[3], g[3];
    t_flight(&kFlight, 3600.0L, r, v, a);
    t_point_mass_g(r, g);
    long double rn[3], vn[3], gn[3];
    for (int j = 0; j < 3; ++j) {
        rn[j] = out.r_i[j];
        vn[j] = out.v_i[j];
        gn[j] = out.g_i[j];
    }
    const long double er = norm3l(rn, r), ev = norm3l(vn, v), eg = norm3l(gn, g);
    printf("perfect 1 h, 100 Hz: |dr| = %.3Lg m, |dv| = %.3Lg m/s, |dG| = %.3Lg m/s^2\n", er, ev,
           eg);
    assert_int_equal(out.seq, n);
    assert_true(er < 1e-4L);
    assert_true(eg < 5e-11L);
}

static void test_config_rejected(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    make_config(&cfg);
    cfg.geometry.a_m = 0.0L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_CONFIG);
    make_config(&cfg);
    cfg.geometry.b_m = 0.0L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_CONFIG);
    make_config(&cfg);
    cfg.dt_us = 0;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_CONFIG);
    make_config(&cfg);
    cfg.g0[2] = NAN;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_CONFIG);
    make_config(&cfg);
    cfg.f_max = 0.0;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_CONFIG);
    /* a failed init leaves the task refusing frames */
    gg_frame_t fr;
    gg_nav_output_t out;
    make_frame(0, &fr);
    assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_ERR_NOT_INIT);
    assert_true((out.health & GG_HEALTH_NOT_INIT) != 0U);
    assert_int_equal(gg_nav2d_init(NULL, &cfg), GG_ERR_NULL);
}

/* Run 10 good steps, then offer a bad frame: it must be rejected with the
 * right status and health bit, the state must not change, and the next good
 * frames must continue exactly as if the bad one had been lost on the way
 * (against a task that never saw frame 10: bridged over, bit for bit). */
static void check_rejected(void (*spoil)(gg_frame_t *), gg_status_t want_status,
                           uint32_t want_bit)
{
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav, ref;
    gg_frame_t fr;
    gg_nav_output_t out, out_ref;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    assert_int_equal(gg_nav2d_init(&ref, &cfg), GG_OK);
    for (int64_t k = 0; k < 10; ++k) {
        make_frame(k, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        assert_int_equal(gg_nav2d_step(&ref, &fr, NULL, &out_ref), GG_OK);
    }
    make_frame(10, &fr);
    spoil(&fr);
    assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), want_status);
    assert_true((out.health & want_bit) != 0U);
    assert_true((out.health & GG_HEALTH_FRAME_REJECTED) != 0U);
    for (int j = 0; j < 3; ++j) {
        assert_true(GG_ISFINITE(out.r_i[j]) && GG_ISFINITE(out.v_i[j]) && GG_ISFINITE(out.g_i[j]));
        assert_true(out.r_i[j] == out_ref.r_i[j] && out.g_i[j] == out_ref.g_i[j]);
    }
    for (int64_t k = 11; k < 20; ++k) {
        make_frame(k, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        assert_int_equal(gg_nav2d_step(&ref, &fr, NULL, &out_ref), GG_OK);
        assert_memory_equal(out.r_i, out_ref.r_i, sizeof out.r_i);
        assert_memory_equal(out.v_i, out_ref.v_i, sizeof out.v_i);
        assert_memory_equal(out.g_i, out_ref.g_i, sizeof out.g_i);
    }
}

static void spoil_nan(gg_frame_t *f) { f->f[2][2] = NAN; }
static void spoil_inf(gg_frame_t *f) { f->f[0][0] = -INFINITY; }
static void spoil_range(gg_frame_t *f) { f->f[1][0] = 1e3; }
static void spoil_sensor(gg_frame_t *f) { f->acc_status[3] = GG_SENSOR_BAD; }
static void spoil_count(gg_frame_t *f) { f->n_acc = 3; }
static void spoil_hilo(gg_frame_t *f) { f->f_lo[1][2] = 1e-3; } /* a residual can never be that large */
static void spoil_gap(gg_frame_t *f) { f->seq += 1; }
static void spoil_repeat(gg_frame_t *f) { f->seq -= 1; }
static void spoil_time(gg_frame_t *f) { f->utime += 5000; }
static void spoil_time_back(gg_frame_t *f) { f->utime -= 20000; }


/* Fuzzing findings (docs/robustness.md): time stamps / seq at the ends of
 * int64 must not overflow the step checks; absurd-but-finite configurations
 * are refused. */
static void spoil_utime_min(gg_frame_t *f) { f->utime = INT64_MIN; }
static void spoil_seq_max(gg_frame_t *f) { f->seq = INT64_MAX; }
static void spoil_utime_max(gg_frame_t *f) { f->utime = INT64_MAX; }

static void test_extreme_time_and_config(void **state)
{
    (void)state;
    check_rejected(spoil_utime_min, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
    check_rejected(spoil_seq_max, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
    check_rejected(spoil_utime_max, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
    /* a first frame at INT64_MIN is refused too (it used to be accepted and
     * the next difference overflowed) */
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    make_frame(0, &fr);
    fr.utime = INT64_MIN;
    assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_ERR_SEQUENCE);
    assert_int_equal(nav.started, 0);
    /* absurd but finite configurations */
    make_config(&cfg);
    cfg.v0[2] = 1.9e289L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_RANGE);
    make_config(&cfg);
    cfg.g0[0] = 6e144L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_RANGE);
    make_config(&cfg);
    cfg.geometry.a_m = 3e-5L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_RANGE);
    make_config(&cfg);
    cfg.r_ref_m = 1.96e308L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_RANGE);
    make_config(&cfg);
    cfg.r0[0] = 10.0L;
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_ERR_RANGE);
}

static void test_bad_frames_rejected_state_untouched(void **state)
{
    (void)state;
    /* (two unusable readings in one axis group degrade the group instead:
     * test_group_degraded) */
    check_rejected(spoil_count, GG_ERR_SENSOR, GG_HEALTH_FRAME_REJECTED);
    /* seq one ahead but the time stamp one step on: inconsistent, rejected */
    check_rejected(spoil_gap, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
    check_rejected(spoil_repeat, GG_ERR_SEQUENCE, GG_HEALTH_SEQ_REPEAT);
    check_rejected(spoil_time, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
    check_rejected(spoil_time_back, GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP);
}

/* One unusable reading (NaN/Inf, out of range, malformed residual, or a
 * sensor flagged bad - both its axes) is flagged, rebuilt from the parity
 * relation of its axis group, and the navigation carries on. The rebuilt
 * value is right to the change of the group's curvature term since its last
 * healthy value (~1.4e-17 m/s^2 per second on this flight: 6000 steps ->
 * ~1e-15 m/s^2 in one reading -> ~3e-11 m/s^2 of G through 300 m/s); bound
 * 1e-10 m/s^2 in G and 1e-6 m in position after one minute. */
static void check_rebuilt(void (*spoil)(gg_frame_t *), uint32_t want_bit)
{
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav, ref;
    gg_frame_t fr;
    gg_nav_output_t out, out_ref;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    assert_int_equal(gg_nav2d_init(&ref, &cfg), GG_OK);
    for (int64_t k = 0; k < 6000; ++k) {
        make_frame(k, &fr);
        assert_int_equal(gg_nav2d_step(&ref, &fr, NULL, &out_ref), GG_OK);
        if (k >= 10) spoil(&fr); /* from step 10 on, for a minute */
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        if (k >= 10) {
            assert_true((out.health & want_bit) != 0U);
            assert_true((out.health & GG_HEALTH_ACC_REBUILT) != 0U);
            assert_true((out.health & GG_HEALTH_FRAME_REJECTED) == 0U);
        }
    }
    long double dr = 0, dg = 0;
    for (int j = 0; j < 3; ++j) {
        dr += (out.r_i[j] - out_ref.r_i[j]) * (long double)(out.r_i[j] - out_ref.r_i[j]);
        dg += (out.g_i[j] - out_ref.g_i[j]) * (long double)(out.g_i[j] - out_ref.g_i[j]);
    }
    printf("rebuilt reading for a minute: |dr| = %.3Lg m, |dG| = %.3Lg m/s^2 vs clean run\n",
           sqrtl(dr), sqrtl(dg));
    assert_true(sqrtl(dr) < 1e-6L);
    assert_true(sqrtl(dg) < 1e-10L);
}

static void spoil_sensor3(gg_frame_t *f) { f->acc_status[2] = GG_SENSOR_BAD; f->f[2][0] = 1e300; }

static void test_single_bad_reading_rebuilt(void **state)
{
    (void)state;
    check_rebuilt(spoil_nan, GG_HEALTH_ACC_NONFINITE);
    check_rebuilt(spoil_inf, GG_HEALTH_ACC_NONFINITE);
    check_rebuilt(spoil_range, GG_HEALTH_ACC_RANGE);
    check_rebuilt(spoil_hilo, GG_HEALTH_ACC_RANGE);
    check_rebuilt(spoil_sensor, GG_HEALTH_ACC_SENSOR);
    check_rebuilt(spoil_sensor3, GG_HEALTH_ACC_SENSOR);
}

/* Lost frames (a seq gap with a consistent time stamp) are bridged: the
 * missing steps are flown with gradient and specific force interpolated
 * between the frames on either side. Against a run that saw every frame:
 * dropping 1, then 5, then 50 frames costs < 1e-6 m and < 1e-12 m/s^2 after
 * a minute; a frame with a bad time stamp is rejected and the next one
 * bridges over it (navigation does not stop). Longer outages:
 * test_recovery.c. */
static void test_lost_frames_bridged(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav, ref;
    gg_frame_t fr;
    gg_nav_output_t out, out_ref;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    assert_int_equal(gg_nav2d_init(&ref, &cfg), GG_OK);
    int bridged = 0;
    for (int64_t k = 0; k < 6000; ++k) {
        make_frame(k, &fr);
        assert_int_equal(gg_nav2d_step(&ref, &fr, NULL, &out_ref), GG_OK);
        const int lost = (k == 1000) || (k >= 2000 && k < 2005) || (k >= 3000 && k < 3050);
        if (lost) continue;
        if (k == 4000) {
            /* a time stamp 5 ms off: rejected, then bridged over */
            fr.utime += 5000;
            assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_ERR_SEQUENCE);
            assert_true((out.health & GG_HEALTH_TIME_JUMP) != 0U);
            continue;
        }
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        if (out.health & GG_HEALTH_SEQ_GAP) bridged++;
    }
    assert_int_equal(bridged, 4);
    long double dr = 0, dg = 0;
    for (int j = 0; j < 3; ++j) {
        dr += (out.r_i[j] - out_ref.r_i[j]) * (long double)(out.r_i[j] - out_ref.r_i[j]);
        dg += (out.g_i[j] - out_ref.g_i[j]) * (long double)(out.g_i[j] - out_ref.g_i[j]);
    }
    printf("lost 1 + 5 + 50 frames and one bad time stamp, bridged: after a minute |dr| = %.3Lg m, "
           "|dG| = %.3Lg m/s^2 vs the run that saw every frame\n", sqrtl(dr), sqrtl(dg));
    assert_true(sqrtl(dr) < 1e-6L);
    assert_true(sqrtl(dg) < 1e-12L);
}

/* ---- recovery: no input leaves the task unable to navigate (navtask.h) ---- */

/* |r_nav - r_true| of an output at step k of the flight */
static long double pos_err(const gg_nav_output_t *o, int64_t k)
{
    long double r[3], v[3], a[3], rn[3];
    t_flight(&kFlight, (long double)k * (long double)DT_US * 1e-6L, r, v, a);
    for (int j = 0; j < 3; ++j) rn[j] = o->r_i[j];
    return norm3l(rn, r);
}

/* Error that holding the inputs costs: the specific force of this flight,
 * (g - V^2/R) along up, turns at V/R, so |df/dt| = (g - V^2/R) V/R. Held for
 * T_c s (coast) and then ramped back over T_b s (bridge), the velocity error
 * is about |df/dt| (T_c^2/2 + T_c T_b/2), flown on for t s. */
static long double held_input_bound(long double t_c, long double t_b, long double t)
{
    long double r[3], v[3], a[3], g[3];
    t_flight(&kFlight, 0.0L, r, v, a);
    t_point_mass_g(r, g);
    const long double rn = sqrtl(r[0] * r[0] + r[2] * r[2]);
    const long double gn = sqrtl(g[0] * g[0] + g[2] * g[2]);
    const long double fdot = (gn - kFlight.v * kFlight.v / rn) * kFlight.v / rn;
    return fdot * (0.5L * t_c * t_c + 0.5L * t_c * t_b) * t;
}

/* Fly steps 0..n-1 with frames changed by fault(k, frame) (return 0 to drop
 * the frame); check that every frame from k_ok on is used, and return the
 * position error at the end, the health bits seen and the last output. */
typedef int (*fault_fn)(int64_t k, gg_frame_t *fr);
static long double fly_fault(gg_nav2d_config_t *cfg, int64_t n, fault_fn fault, int64_t k_ok,
                             uint32_t *seen, gg_nav_output_t *last, double *max_outage)
{
    static gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    assert_int_equal(gg_nav2d_init(&nav, cfg), GG_OK);
    *seen = 0U;
    *max_outage = 0.0;
    for (int64_t k = 0; k < n; ++k) {
        make_frame(k, &fr);
        if (fault(k, &fr) == 0) continue;
        const gg_status_t st = gg_nav2d_step(&nav, &fr, NULL, &out);
        *seen |= out.health;
        if (out.outage_s > *max_outage) *max_outage = out.outage_s;
        for (int j = 0; j < 3; ++j) assert_true(GG_ISFINITE(out.r_i[j]));
        if (k >= k_ok && st != GG_OK)
            fail_msg("step %lld after the fault: status %d health 0x%x", (long long)k, st,
                     out.health);
    }
    *last = out;
    return pos_err(&out, n - 1);
}

/* 1.5 s of malformed frames (three accelerometers: nothing to rebuild or
 * degrade from): the stream is followed, 0.5 s is coasted on the held inputs,
 * 1 s bridged, and every frame after is used. Before, the 101st rejected
 * frame froze the task for good: every later frame a "gap", 17 km of error
 * after a minute. */
static int f_malformed(int64_t k, gg_frame_t *fr)
{
    if (k >= 1000 && k < 1150) fr->n_acc = 3;
    return 1;
}

/* A clock step of 1 us that lasts, with no tolerance (the scenarios'
 * default): re-synchronised after three frames, two steps bridged. */
static int f_clock_step(int64_t k, gg_frame_t *fr)
{
    if (k >= 1000) fr->utime += 1;
    return 1;
}

/* A time stamp 5 ms off for 1.2 s, then right again. */
static int f_time_jump_lasting(int64_t k, gg_frame_t *fr)
{
    if (k >= 1000 && k < 1120) fr->utime += 5000;
    return 1;
}

/* The counter restarts from 0 at step 2000 (a sensor reboot), 0.3 s lost. */
static int f_counter_restart(int64_t k, gg_frame_t *fr)
{
    if (k >= 2000 && k < 2030) return 0;
    if (k >= 2030) fr->seq = k - 2030;
    return 1;
}

/* 150 forged frames replace the genuine ones: far-ahead seq at plausible
 * times carrying the readings of step 1000 (stale), then the genuine stream
 * resumes. */
static int f_forged_burst(int64_t k, gg_frame_t *fr)
{
    if (k > 1000 && k <= 1150) {
        make_frame(1000, fr);
        fr->seq = 1000000 + k;
        fr->utime = 1000000 + k * DT_US;
    }
    return 1;
}

static void test_recovery(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav_output_t out;
    uint32_t seen;
    double max_outage;
    const int64_t n = 6000; /* a minute */
    long double e, bound;

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_malformed, 1150, &seen, &out, &max_outage);
    bound = held_input_bound(0.5L, 1.0L, 58.5L);
    printf("recovery: malformed frames 1.5 s: |dr| %.3Lg m after 60 s (held-input estimate %.3Lg m), "
           "outage %.2f s, %u steps coasted\n", e, bound, max_outage, out.coast_steps);
    assert_true((seen & GG_HEALTH_COAST) != 0U);
    assert_int_equal(out.coast_steps, 50);
    assert_near(max_outage, 1.5, 1e-9);
    assert_true(out.outage_s == 0.0 && out.state_lag_s == 0.0);
    assert_true(e < 2.0L * bound);

    make_config(&cfg);
    cfg.dt_tol_us = 0;
    e = fly_fault(&cfg, n, f_clock_step, 1002, &seen, &out, &max_outage);
    printf("recovery: 1 us clock step: |dr| %.3Lg m after 60 s, %u resync\n", e, out.resync_count);
    assert_true((seen & GG_HEALTH_RESYNC) != 0U);
    assert_int_equal(out.resync_count, 1);
    assert_true(e < 1e-6L); /* two steps bridged by interpolation */

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_time_jump_lasting, 1122, &seen, &out, &max_outage);
    printf("recovery: time stamps 5 ms off for 1.2 s: |dr| %.3Lg m after 60 s, %u resyncs\n", e,
           out.resync_count);
    assert_int_equal(out.resync_count, 2);
    assert_true(e < 1e-6L);

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_counter_restart, 2032, &seen, &out, &max_outage);
    printf("recovery: counter restart after 0.3 s lost: |dr| %.3Lg m after 60 s\n", e);
    assert_int_equal(out.resync_count, 1);
    assert_true(e < 1e-6L);

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_forged_burst, 1153, &seen, &out, &max_outage);
    bound = held_input_bound(1.5L, 0.0L, 58.5L);
    printf("recovery: 150 forged frames: |dr| %.3Lg m after 60 s (held-input estimate %.3Lg m), "
           "%u resyncs\n", e, bound, out.resync_count);
    assert_int_equal(out.resync_count, 2);
    assert_true(e < 2.0L * bound);
}

/* ---- a sensor group that loses more readings than parity rebuilds degrades ---- */

/* Error that holding gradient component Gamma_jk costs (fdi2d.h): held from
 * t0 for T s, it is off by |dGamma_jk/dt| tau after tau s, taken here from the
 * independent point-mass truth along the flight (central difference, the
 * largest over the hold); G then errs by <= gd V tau^2 / 2 and the position,
 * flown on to t_end, by gd V (T^4/24 + T^3/6 dt + T^2/4 dt^2), dt = t_end - t0 - T
 * (the vertical mode's growth over a minute, cosh(sqrt(2g/R) 60 s) - 1 = 0.5 %,
 * is inside the factor 2 the tests allow). */
static long double held_grad_bound(int j, int kk, long double t0, long double T, long double t_end)
{
    long double gd = 0.0L;
    for (int i = 0; i <= 10; ++i) {
        long double t = t0 + T * (long double)i / 10.0L, r1[3], r2[3], v[3], a[3], g1[3][3], g2[3][3];
        t_flight(&kFlight, t - 0.5L, r1, v, a);
        t_flight(&kFlight, t + 0.5L, r2, v, a);
        t_point_mass_gamma(r1, g1);
        t_point_mass_gamma(r2, g2);
        const long double d = fabsl(g2[j][kk] - g1[j][kk]);
        if (d > gd) gd = d;
    }
    const long double dt = t_end - t0 - T, V = kFlight.v;
    return gd * V * (powl(T, 4) / 24.0L + powl(T, 3) / 6.0L * dt + T * T / 4.0L * dt * dt);
}

static int f_x_pair_a_nan(int64_t k, gg_frame_t *fr) /* 1x and 3x NaN for 10 s */
{
    if (k >= 1000 && k < 2000) { fr->f[0][0] = NAN; fr->f[2][0] = NAN; }
    return 1;
}
static int f_sensor2_bad_4z_inf(int64_t k, gg_frame_t *fr) /* sensor 2 bad, 4z Inf, 10 s */
{
    if (k >= 1000 && k < 2000) { fr->acc_status[1] = GG_SENSOR_BAD; fr->f[3][2] = INFINITY; }
    return 1;
}
static int f_stuck2x_nan4x(int64_t k, gg_frame_t *fr) /* 2x stuck from 10 s, 4x NaN 20-30 s */
{
    static double stuck;
    if (k == 1000) stuck = fr->f[1][0];
    if (k >= 1000) { fr->f[1][0] = stuck; fr->f_lo[1][0] = 0.0; }
    if (k >= 2000 && k < 3000) fr->f[3][0] = NAN;
    return 1;
}
static int f_bad3_step2x(int64_t k, gg_frame_t *fr) /* sensor 3 bad and 2x +1e-9 step, 10 s */
{
    if (k >= 1000 && k < 2000) { fr->acc_status[2] = GG_SENSOR_BAD; fr->f_lo[1][0] += 1e-9; }
    return 1;
}
static int f_all_z_nan(int64_t k, gg_frame_t *fr) /* all four z NaN for 1.5 s */
{
    if (k >= 1000 && k < 1150)
        for (int i = 0; i < 4; ++i) fr->f[i][2] = NAN;
    return 1;
}

/* Every frame is used (none rejected) through the fault, flagged
 * ACC_DEGRADED, and the error after a minute stays inside twice the
 * held-input bound of the components that had to be held (1e-6 m where
 * everything came from readings or symmetry). */
static void test_group_degraded(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav_output_t out;
    uint32_t seen;
    double max_outage;
    const int64_t n = 6000;
    long double e, bound;

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_x_pair_a_nan, 0, &seen, &out, &max_outage);
    bound = held_grad_bound(0, 0, 10.0L, 10.0L, 60.0L);
    printf("degraded: 1x+3x NaN 10 s (Gxx held): |dr| %.3Lg m after 60 s (bound %.3Lg m)\n", e, bound);
    assert_true((seen & GG_HEALTH_ACC_DEGRADED) && (seen & GG_HEALTH_GRAD_COAST));
    assert_true(!(seen & (GG_HEALTH_FRAME_REJECTED | GG_HEALTH_COAST | GG_HEALTH_FORCE_COAST)));
    assert_true(e < 2.0L * bound + 1e-6L);

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_sensor2_bad_4z_inf, 0, &seen, &out, &max_outage);
    bound = held_grad_bound(2, 2, 10.0L, 10.0L, 60.0L);
    printf("degraded: sensor 2 bad + 4z Inf 10 s (Gzz held): |dr| %.3Lg m after 60 s (bound %.3Lg m)\n", e, bound);
    assert_true((seen & GG_HEALTH_ACC_DEGRADED) && (seen & GG_HEALTH_GRAD_COAST));
    assert_true(!(seen & (GG_HEALTH_FRAME_REJECTED | GG_HEALTH_COAST | GG_HEALTH_FORCE_COAST)));
    assert_true(e < 2.0L * bound + 1e-6L);

    make_config(&cfg);
    cfg.fdi_parity_f_max = 1e-11;
    cfg.fdi_asym_max = 1e-11;
    e = fly_fault(&cfg, n, f_stuck2x_nan4x, 0, &seen, &out, &max_outage);
    printf("degraded: 2x stuck + 4x NaN 10 s (Gxz from symmetry): |dr| %.3Lg m after 60 s\n", e);
    assert_true((seen & GG_HEALTH_ACC_DEGRADED) && (seen & GG_HEALTH_ACC_FAULT));
    assert_true(!(seen & (GG_HEALTH_FRAME_REJECTED | GG_HEALTH_COAST | GG_HEALTH_FORCE_COAST |
                          GG_HEALTH_GRAD_COAST)));
    assert_int_equal(out.acc_excluded, GG_FDI_BIT(1, 0));
    assert_true(e < 1e-6L);

    make_config(&cfg);
    cfg.fdi_parity_f_max = 1e-11;
    cfg.fdi_asym_max = 1e-11;
    e = fly_fault(&cfg, n, f_bad3_step2x, 0, &seen, &out, &max_outage);
    /* the residual fits no single reading: the x group (3x rebuilt, so every
     * x reading is suspect) and the off-diagonal readings are set aside: the
     * x force, Gxx, Gxz and Gzx held */
    bound = held_input_bound(10.0L, 0.0L, 50.0L) + held_grad_bound(0, 0, 10.0L, 10.0L, 60.0L) +
            held_grad_bound(0, 2, 10.0L, 10.0L, 60.0L) + held_grad_bound(2, 0, 10.0L, 10.0L, 60.0L);
    printf("degraded: sensor 3 bad + 2x step 10 s (x force, Gxx, Gxz, Gzx held): |dr| %.3Lg m after 60 s "
           "(bound %.3Lg m)\n", e, bound);
    assert_true((seen & GG_HEALTH_ACC_DEGRADED) && (seen & GG_HEALTH_ACC_FAULT) &&
                (seen & GG_HEALTH_GRAD_COAST));
    assert_true(!(seen & (GG_HEALTH_FRAME_REJECTED | GG_HEALTH_COAST)));
    assert_true(e < 2.0L * bound + 1e-6L);

    make_config(&cfg);
    e = fly_fault(&cfg, n, f_all_z_nan, 0, &seen, &out, &max_outage);
    bound = held_input_bound(1.5L, 0.0L, 58.5L) + held_grad_bound(2, 2, 10.0L, 1.5L, 60.0L);
    printf("degraded: all z NaN 1.5 s (z force and Gzz held): |dr| %.3Lg m after 60 s "
           "(bound %.3Lg m)\n", e, bound);
    assert_true((seen & GG_HEALTH_ACC_DEGRADED) && (seen & GG_HEALTH_FORCE_COAST));
    assert_true(!(seen & (GG_HEALTH_FRAME_REJECTED | GG_HEALTH_COAST)));
    assert_true(e < 2.0L * bound);
}

/* An asymmetric gradient (a faulty accelerometer) is flagged. */
static void test_asymmetry_flagged(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    make_frame(0, &fr);
    assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
    assert_int_equal(out.health & GG_HEALTH_GAMMA_ASYM, 0);
    make_frame(1, &fr);
    fr.f[1][0] += 1e-8; /* sensor 2 x steps by 1e-8 m/s^2: Gxz off by 1e-8 s^-2 */
    assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
    assert_true((out.health & GG_HEALTH_GAMMA_ASYM) != 0U);
    assert_near(out.gamma_asym, -1e-8L, 1e-12L); /* Gxz = (f4x - f2x)/2b falls */
}

/* ---- mock HAL ---- */
typedef struct {
    int64_t next_k;
    int64_t n_frames;
    gg_nav_output_t last;
    int writes;
    uint32_t clock;
    uint32_t tick;
} mock_t;

static gg_status_t mock_read(void *ctx, gg_frame_t *frame)
{
    mock_t *m = ctx;
    if (m->next_k >= m->n_frames) return GG_ERR_NO_DATA;
    make_frame(m->next_k++, frame);
    return GG_OK;
}
static gg_status_t mock_write(void *ctx, const gg_nav_output_t *out)
{
    mock_t *m = ctx;
    m->last = *out;
    m->writes++;
    return (gg_status_t)mock();
}
static uint32_t mock_cycles(void *ctx)
{
    mock_t *m = ctx;
    m->clock += m->tick; /* every read of the counter advances it */
    return m->clock;
}

static void test_task_cycle_through_hal(void **state)
{
    (void)state;
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    make_config(&cfg);
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    mock_t m = {0};
    m.n_frames = 3;
    m.clock = 0xFFFFFF00u; /* wraps during the run: differences must survive it */
    m.tick = 100;
    const gg_hal_t hal = {&m, mock_read, mock_write, mock_cycles, 1000000000u, NULL, NULL};
    will_return_count(mock_write, GG_OK, 3);
    for (int i = 0; i < 3; ++i) assert_int_equal(gg_nav2d_task_cycle(&nav, &hal), GG_OK);
    assert_int_equal(gg_nav2d_task_cycle(&nav, &hal), GG_ERR_NO_DATA);
    assert_int_equal(m.writes, 3);
    assert_int_equal(m.last.seq, 2);
    assert_true(m.last.cycles[GG_MOD_TOTAL] > 0U && m.last.cycles[GG_MOD_TOTAL] < 10000U);
    assert_true(m.last.cycles[GG_MOD_DIFF] == 100U);
    assert_int_equal(m.last.health & GG_HEALTH_DEADLINE, 0);

    /* a slow step (counter runs 5e6 ticks per read at 1 GHz: > 10 ms a step) */
    m.n_frames = 4;
    m.tick = 5000000;
    will_return(mock_write, GG_OK);
    assert_int_equal(gg_nav2d_task_cycle(&nav, &hal), GG_OK);
    assert_true((m.last.health & GG_HEALTH_DEADLINE) != 0U);

    /* an output that cannot be written is reported */
    m.n_frames = 5;
    m.tick = 1;
    will_return(mock_write, GG_ERR_IO);
    assert_int_equal(gg_nav2d_task_cycle(&nav, &hal), GG_ERR_IO);
}

/* ---- barometric vertical channel through the whole navigation step ---- */

#define BARO_EVERY 100 /* 1 Hz barometer at 100 Hz steps */
static const long double kPoles[3] = {0.005L, 0.01L, 0.015L};

static void baro_config(gg_nav2d_config_t *cfg, int model_mode)
{
    make_config(cfg);
    cfg->baro_enable = 1;
    for (int i = 0; i < 3; ++i) cfg->baro.poles[i] = kPoles[i];
    cfg->baro.omega_s2 = T_GM / (T_RE * T_RE * T_RE);
    cfg->baro.period_us = BARO_EVERY * DT_US;
    cfg->baro.max_age_us = 500000;
    cfg->baro.coast_us = 10000000;
    cfg->baro.alt_min_m = -1000.0;
    cfg->baro.alt_max_m = 30000.0;
    cfg->baro.gate_m = 100.0;
    cfg->baro.max_rejects = 5;
    cfg->r_ref_m = T_RE;
    if (model_mode) {
        cfg->gravity_mode = GG_GRAVITY_MODEL;
        cfg->model.gm = T_GM;
        cfg->model.a_m = T_RE;
    }
}

/* Frame k of flight fl with perfect sensors plus an accelerometer bias (all
 * four sensors, both axes), and a perfect barometer every BARO_EVERY steps. */
static void make_frame_fl(const t_flight_t *fl, int64_t k, const long double bias[3],
                          gg_frame_t *fr)
{
    t_make_frame(fl, k, DT_US, 1000000, bias, BARO_EVERY, fr);
}

/* Vertical error state of a navigation state: h, v_up, a_c, G_up. */
static void vstate(const gg_nav2d_t *nav, const long double u[3], long double x[4])
{
    gg_real_t r[3], v[3], g[3];
    assert_int_equal(gg_mech_get(&nav->mech, r, v), GG_OK);
    x[0] = sqrtl(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    x[1] = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
    x[2] = nav->a_c;
    if (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER) {
        assert_int_equal(gg_gravdr_get(&nav->gravdr, g), GG_OK);
        x[3] = g[0] * u[0] + g[1] * u[1] + g[2] * u[2];
    } else {
        x[3] = 0.0L;
    }
}

/* Roots of the monic polynomial z^n + c[n-1] z^(n-1) + ... + c[0] (Durand-Kerner). */
static void poly_roots(int n, const long double c[], long double complex z[])
{
    for (int i = 0; i < n; ++i) z[i] = cpowl(0.4L + 0.9L * I, i);
    for (int it = 0; it < 2000; ++it) {
        for (int i = 0; i < n; ++i) {
            long double complex p = 1.0L, d = 1.0L;
            for (int k = n - 1; k >= 0; --k) p = p * z[i] + c[k];
            for (int j = 0; j < n; ++j)
                if (j != i) d *= (z[i] - z[j]);
            z[i] -= p / d;
        }
    }
}

/* Characteristic polynomial of an n x n matrix (Faddeev-LeVerrier). */
static void char_poly(int n, long double A[4][4], long double c[4])
{
    long double M[4][4] = {{0}}, AM[4][4];
    long double ck = 1.0L;
    for (int k = 1; k <= n; ++k) {
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) M[i][j] += (i == j) ? ck : 0.0L;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
                AM[i][j] = 0;
                for (int l = 0; l < n; ++l) AM[i][j] += A[i][l] * M[l][j];
            }
        long double tr = 0;
        for (int i = 0; i < n; ++i) tr += AM[i][i];
        ck = -tr / k;
        c[n - k] = ck;
        memcpy(M, AM, sizeof M);
    }
}

/* The implemented discrete loop's poles: linearise the whole navigation step
 * by finite differences over one barometer period (perturb h, v_up, a_c and,
 * in gradiometer mode, G_up), take the eigenvalues z of the transition
 * matrix and s = ln(z)/T. They must match the configured poles within 1 %. In
 * gradiometer mode the fourth eigenvalue is 1 (G_up - Gamma_uu h is carried
 * unchanged: the corrections keep G consistent with the position). */
static void check_loop_poles(int model_mode)
{
    const t_flight_t still = {0.0L, 0.0L, 0.3L};
    const long double zero[3] = {0, 0, 0};
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    baro_config(&cfg, model_mode);
    long double r0[3], v0[3], a0[3], g0[3];
    t_flight(&still, 0.0L, r0, v0, a0);
    t_point_mass_g(r0, g0);
    for (int j = 0; j < 3; ++j) {
        cfg.r0[j] = r0[j];
        cfg.v0[j] = v0[j];
        cfg.g0[j] = g0[j];
    }
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    int64_t k = 0;
    for (; k <= 10 * BARO_EVERY; ++k) {
        make_frame_fl(&still, k, zero, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
    }
    const int n = model_mode ? 3 : 4;
    const long double u[3] = {r0[0] / sqrtl(r0[0] * r0[0] + r0[2] * r0[2]), 0,
                              r0[2] / sqrtl(r0[0] * r0[0] + r0[2] * r0[2])};
    const long double eps[4] = {1.0L, 1e-2L, 1e-6L, 1e-6L};
    gg_nav2d_t runs[5];
    for (int p = 0; p <= n; ++p) runs[p] = nav;
    for (int p = 1; p <= n; ++p) {
        gg_real_t dr[3] = {0, 0, 0}, dv[3] = {0, 0, 0}, da[3] = {0, 0, 0};
        const long double e = eps[p - 1];
        for (int j = 0; j < 3; ++j) {
            if (p == 1) dr[j] = e * u[j];
            if (p == 2) dv[j] = e * u[j];
            if (p == 3) da[j] = -e * u[j];
            if (p == 4) da[j] = e * u[j];
        }
        if (p == 3) {
            runs[p].a_c += e;
            runs[p].vchan.a_c += e;
        }
        if (p == 4) {
            const gg_real_t dg[3] = {e * u[0], e * u[1], e * u[2]};
            assert_int_equal(gg_gravdr_correct(&runs[p].gravdr, dg), GG_OK);
        }
        assert_int_equal(gg_mech_correct(&runs[p].mech, dr, dv, da), GG_OK);
    }
    for (int64_t kk = k; kk < k + BARO_EVERY; ++kk) {
        make_frame_fl(&still, kk, zero, &fr);
        for (int p = 0; p <= n; ++p)
            assert_int_equal(gg_nav2d_step(&runs[p], &fr, NULL, &out), GG_OK);
    }
    long double x0[4], xp[4], A[4][4];
    vstate(&runs[0], u, x0);
    for (int p = 1; p <= n; ++p) {
        vstate(&runs[p], u, xp);
        for (int i = 0; i < n; ++i) A[i][p - 1] = (xp[i] - x0[i]) / eps[p - 1];
    }
    long double c[4];
    long double complex z[4];
    char_poly(n, A, c);
    poly_roots(n, c, z);
    const long double T = BARO_EVERY * DT_US * 1e-6L;
    int matched[3] = {0, 0, 0}, unit = 0;
    for (int i = 0; i < n; ++i) {
        const long double complex s = clogl(z[i]) / T;
        printf("%s mode: z = %.9Lf%+.2Le i  ->  s = %.6Le%+.2Le i\n",
               model_mode ? "model" : "gradiometer", creall(z[i]), cimagl(z[i]), creall(s),
               cimagl(s));
        if (cabsl(z[i] - 1.0L) < 1e-9L) {
            unit++;
            continue;
        }
        for (int q = 0; q < 3; ++q)
            if (!matched[q] && cabsl(s + kPoles[q]) < 0.01L * kPoles[q]) {
                matched[q] = 1;
                break;
            }
    }
    assert_true(matched[0] && matched[1] && matched[2]);
    assert_int_equal(unit, model_mode ? 0 : 1);
}

static void test_baro_loop_poles_model_mode(void **state)
{
    (void)state;
    check_loop_poles(1);
}

static void test_baro_loop_poles_gradiometer_mode(void **state)
{
    (void)state;
    check_loop_poles(0);
}

/* A constant accelerometer bias along up leaves no steady-state altitude
 * error: the loop's integral state takes it up. Stationary platform, so the
 * bias stays along up. A second-order loop would keep b/(k2 - 2 w^2) = 36 mm;
 * the free channel would be ~1e3 m off after 3 h. */
static void test_bias_no_steady_state_altitude_error(void **state)
{
    (void)state;
    const t_flight_t still = {0.0L, 0.0L, 0.0L}; /* at the equator: up = +x */
    gg_nav2d_config_t cfg;
    gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    baro_config(&cfg, 0);
    long double r0[3], v0[3], a0[3], g0[3];
    t_flight(&still, 0.0L, r0, v0, a0);
    t_point_mass_g(r0, g0);
    for (int j = 0; j < 3; ++j) {
        cfg.r0[j] = r0[j];
        cfg.v0[j] = v0[j];
        cfg.g0[j] = g0[j];
    }
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    const long double b = 1e-5L;
    const long double bias[3] = {b, 0.0L, 0.0L};
    const int64_t n = 3 * 3600 * 100;
    for (int64_t k = 0; k <= n; ++k) {
        make_frame_fl(&still, k, bias, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
    }
    const long double dh = out.h_ins_m - 0.0L;
    printf("bias %.1Le m/s^2 up, 3 h: altitude error %.3Le m, a_c = %.6Le m/s^2\n", b, dh,
           (long double)out.g_up_corr);
    assert_true(fabsl(dh) < 1e-6L);
    assert_near(out.g_up_corr, b, 1e-3L * b);
    assert_int_equal(out.health, 0);
}

/* Rubenstein & Winter eq. 2: in the conventional (gravity-model) mode a
 * step deflection of the vertical delta, not in the onboard model, gives the
 * Schuler response |dx| = R delta (1 - cos w_s t), w_s^2 = g/R. Platform at
 * rest at the equator (up = x), true field = point mass + a uniform
 * horizontal (north, z) gravitation g delta; onboard model = the point mass.
 * Checked over two Schuler periods at 100 Hz, within 1 % of the peak. */
static void test_schuler_step_deflection(void **state)
{
    (void)state;
    const t_flight_t still = {0.0L, 0.0L, 0.0L};
    gg_nav2d_config_t cfg;
    static gg_nav2d_t nav;
    gg_frame_t fr;
    gg_nav_output_t out;
    baro_config(&cfg, 1);
    long double r0[3], v0[3], a0[3], g0[3];
    t_flight(&still, 0.0L, r0, v0, a0);
    t_point_mass_g(r0, g0);
    for (int j = 0; j < 3; ++j) {
        cfg.r0[j] = r0[j];
        cfg.v0[j] = v0[j];
        cfg.g0[j] = g0[j];
    }
    assert_int_equal(gg_nav2d_init(&nav, &cfg), GG_OK);
    const long double g = T_GM / (T_RE * T_RE), ws = sqrtl(g / T_RE);
    const long double delta = 10.0L / 206264.806L; /* 10 arcsec */
    const long double dg = g * delta;              /* horizontal gravitation the model lacks */
    /* readings: f_i = a - G(r_i) - dg z^ (a = 0 at rest), barometer perfect */
    const long double bias[3] = {0.0L, 0.0L, -dg};
    const long double period = 2.0L * 3.14159265358979323846L / ws;
    const int64_t n = (int64_t)(2.0L * period * 100.0L);
    long double worst = 0.0L;
    for (int64_t k = 0; k <= n; ++k) {
        make_frame_fl(&still, k, bias, &fr);
        assert_int_equal(gg_nav2d_step(&nav, &fr, NULL, &out), GG_OK);
        if (k % 6000 == 0) {
            const long double t = (long double)k * 0.01L;
            /* the navigation's acceleration error is G_model - G_true = -dg z^, so
             * dz'' = -dg - w_s^2 dz: dz = -R delta (1 - cos w_s t) */
            const long double want = -T_RE * delta * (1.0L - cosl(ws * t));
            const long double got = out.r_i[2]; /* north error (truth z = 0) */
            worst = fmaxl(worst, fabsl(got - want));
        }
    }
    printf("step deflection 10\": peak 2 R delta = %.2Lf m; worst |dx - R delta (1 - cos w_s t)| "
           "= %.3Le m over 2 Schuler periods (%.2Lf min each)\n",
           2.0L * T_RE * delta, worst, period / 60.0L);
    assert_true(worst < 0.01L * 2.0L * T_RE * delta);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_perfect_flight_1h),
        cmocka_unit_test(test_config_rejected),
        cmocka_unit_test(test_bad_frames_rejected_state_untouched),
        cmocka_unit_test(test_single_bad_reading_rebuilt),
        cmocka_unit_test(test_extreme_time_and_config),
        cmocka_unit_test(test_lost_frames_bridged),
        cmocka_unit_test(test_recovery),
        cmocka_unit_test(test_group_degraded),
        cmocka_unit_test(test_asymmetry_flagged),
        cmocka_unit_test(test_task_cycle_through_hal),
        cmocka_unit_test(test_baro_loop_poles_model_mode),
        cmocka_unit_test(test_baro_loop_poles_gradiometer_mode),
        cmocka_unit_test(test_bias_no_steady_state_altitude_error),
        cmocka_unit_test(test_schuler_step_deflection),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
