/* 3-D navigation task (nav3d) against closed-form truth on a rotating Earth:
 * a platform moving along a circle of latitude at constant height (uniform
 * circular motion in the inertial frame), in the field of a central point
 * mass plus buried anomaly masses fixed to the Earth (so the field turns
 * with the Earth), with a body that precesses and spins (closed-form
 * attitude, rates and angular accelerations). Every accelerometer reading is
 * built from rigid-body kinematics at the sensor's own position in long
 * double; nothing is integrated numerically on the truth side. */
#include "test_common.h"
#include "truth2d.h"
#include "ggins/nav3d.h"

#include <float.h>

#include "truth3.h"

typedef struct {
    long double pos_err, vel_err, g_err, att_err, gam_err, h_err;
} run_result_t;

/* fly n steps, return the errors at the end (and the worst Gamma_b error) */
static run_result_t fly(const truth3_t *T, int platform, int baro, int64_t dt_us, long long n)
{
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    run_result_t res = {0};
    make_config(T, platform, baro, dt_us, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    for (long long k = 0; k <= n; ++k) {
        make_frame(T, k, dt_us, &fr);
        const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
        if (st != GG_OK) fail_msg("step %lld: status %d health 0x%x", k, st, out.health);
    }
    const long double t = (long double)n * (long double)dt_us * 1e-6L;
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], g[3], th[3][3], cbe[3][3];
    truth_pose(T, t, r_e, v_e, r_i, a_i, cbi, w, wd);
    field_e(T, r_e, g);
    long double re_hat[3], ve_hat[3], ge_hat[3];
    for (int j = 0; j < 3; ++j) {
        re_hat[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
        ve_hat[j] = out.v_e[j];
        ge_hat[j] = (long double)out.g_e[j] + (long double)out.g_e_lo[j];
    }
    res.pos_err = norm3l(re_hat, r_e);
    res.vel_err = norm3l(ve_hat, v_e);
    res.g_err = norm3l(ge_hat, g);
    res.h_err = fabsl((long double)out.h_m - T->h0);
    /* attitude: C_b_e = R3(-theta) C_b_i; compare with the output quaternion */
    rz(-W_IE * t, th);
    matmul(th, cbi, cbe);
    long double q[4];
    dcm_to_quat(cbe, q);
    /* rotation angle of q_true^* (x) q_hat: 2 |vector part| (acos of the dot
     * product would lose everything below 1e-9 rad) */
    {
        const long double a0 = q[0], a1 = -q[1], a2 = -q[2], a3 = -q[3];
        const long double b0 = out.q_b_e[0], b1 = out.q_b_e[1], b2 = out.q_b_e[2], b3 = out.q_b_e[3];
        const long double x = a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2;
        const long double y = a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1;
        const long double z = a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0;
        res.att_err = 2.0L * sqrtl(x * x + y * y + z * z);
    }
    return res;
}

/* Space-stabilized platform parked on the rotating Earth, 1 h at 100 Hz,
 * with Earth-fixed anomalies: the field turns with the Earth under the
 * inertial platform, which the ECEF gravity dead reckoning must follow. */
static void test_stabilized_parked_1h(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    const run_result_t r = fly(&T, GG_PLATFORM_STABILIZED, 0, 10000, 360000);
    print_message("stabilized parked 1 h: |dr| %.3Lg m, |dv| %.3Lg m/s, |dG| %.3Lg m/s^2, att %.3Lg rad\n",
                  r.pos_err, r.vel_err, r.g_err, r.att_err);
    assert_true(r.pos_err < 0.01L); /* better than 1 cm */
    assert_true(r.g_err < 1e-11L);
    assert_true(r.att_err < 1e-15L);
}

/* Strapdown body flying east at ~200 m/s along a circle of latitude, spinning
 * at 0.2 rad/s about x while precessing at 0.05 rad/s, with the barometer
 * loop, 1 h at 100 Hz. */
static void test_strapdown_tumbling_flight_1h(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.lon_rate = 200.0L / (6.4e6L * cosl(T.lat0));
    T.p = 0.05L;
    T.s = 0.2L;
    rx(0.3L, T.c0);
    const run_result_t r = fly(&T, GG_PLATFORM_STRAPDOWN, 1, 10000, 360000);
    print_message("strapdown tumbling 200 m/s 1 h (baro): |dr| %.3Lg m, |dv| %.3Lg m/s, |dG| %.3Lg m/s^2, "
                  "att %.3Lg rad, |dh| %.3Lg m\n",
                  r.pos_err, r.vel_err, r.g_err, r.att_err, r.h_err);
    assert_true(r.pos_err < 0.01L);
    assert_true(r.att_err < 1e-9L);
}

/* Strapdown start-up on a fast-turning body (spin 1 rad/s about x,
 * precession 0.3 rad/s: |w''| = s^2 p = 0.3 rad/s^3). Before four gyro samples
 * exist the mid-step rate comes from the cubic Hermite interpolant with the
 * measured angular accelerations; a linear start would leave h^3 |w''|/12 =
 * 2.5e-8 rad in the attitude for good, the quadratic second step h^4 |w'''|/16.
 * Truth: the closed-form attitude after 20 steps. Also the strapdown parity
 * there: the gyro-derived angular acceleration by the third-order backward
 * difference differs from the exact measured one by h^3/4 |w''''| = 7.5e-8
 * rad/s^2 (s^3 p = 0.3 rad/s^5), where a second-order difference is off by
 * h^2/3 |w'''| = 1e-5: asym_max 1e-6 must stay quiet. */
static void test_strapdown_startup_fast_body(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.p = 0.3L;
    T.s = 1.0L;
    rx(0.3L, T.c0);
    const long double lin = 1e-6L * 0.3L / 12.0L;
    const run_result_t r = fly(&T, GG_PLATFORM_STRAPDOWN, 0, 10000, 20);
    print_message("strapdown start-up, 1 rad/s spin, 20 steps: att %.3Lg rad (linear start %.3Lg)\n",
                  r.att_err, lin);
    assert_true(r.att_err < lin / 100.0L);

    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 0, 10000, &cfg);
    cfg.asym_max = 1e-6;
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    double worst = 0.0;
    for (long long k = 0; k <= 500; ++k) {
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
        for (int j = 0; j < 3; ++j) {
            if (fabs(out.parity[j]) > worst) worst = fabs(out.parity[j]);
        }
        if ((out.health & GG_HEALTH_GAMMA_ASYM) != 0U)
            fail_msg("step %lld: parity %g %g %g", k, out.parity[0], out.parity[1], out.parity[2]);
    }
    print_message("strapdown parity on the fast body, steps 0..500: worst %.3g rad/s^2 "
                  "(h^3/4 |w''''| = 7.5e-8)\n", worst);
    assert_true(worst < 1.5e-7);
    assert_true(worst > 1e-9); /* the difference's own error is there: the residual is live */
}

/* The same flight with the rotation terms of the Earth switched off in the
 * firmware (omega_ie < 0) must fail badly: proves the test sees the Earth rate. */
static void test_earth_rate_matters(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STABILIZED, 0, 10000, &cfg);
    cfg.omega_ie = -1.0L;
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    for (long long k = 0; k <= 6000; ++k) {
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    }
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3];
    truth_pose(&T, 60.0L, r_e, v_e, r_i, a_i, cbi, w, wd);
    long double re_hat[3] = {out.r_e[0], out.r_e[1], out.r_e[2]};
    print_message("non-rotating firmware on a rotating Earth, 60 s: |dr| %.3Lg m\n", norm3l(re_hat, r_e));
    assert_true(norm3l(re_hat, r_e) > 10.0L);
}

/* Geodetic conversion: Bowring's iteration against the closed-form forward map. */
static void test_geodetic(void **state)
{
    (void)state;
    long double worst_ang = 0, worst_h = 0;
    for (int i = -90; i <= 90; i += 5) {
        for (int hh = 0; hh < 4; ++hh) {
            const long double hs[] = {-4000.0L, 0.0L, 12000.0L, 90000.0L};
            const long double lat = (long double)i * 3.14159265358979323846L / 180.0L;
            const long double lon = -3.0L + 0.13L * (long double)(i + 90) / 5.0L;
            long double r[3], la, lo, h;
            geo2ecef(lat, lon, hs[hh], r);
            assert_int_equal(gg_geo_ecef_to_geodetic(r, &la, &lo, &h), GG_OK);
            worst_ang = fmaxl(worst_ang, fabsl(la - lat));
            if (i != 90 && i != -90) worst_ang = fmaxl(worst_ang, fabsl(remainderl(lo - lon, 2 * 3.14159265358979323846L)));
            worst_h = fmaxl(worst_h, fabsl(h - hs[hh]));
            long double r2[3];
            assert_int_equal(gg_geo_geodetic_to_ecef(lat, lon, hs[hh], r2), GG_OK);
            assert_true(norm3l(r, r2) < 1e-8L);
        }
    }
    print_message("geodetic: worst angle error %.3Lg rad, height %.3Lg m\n", worst_ang, worst_h);
    assert_true(worst_ang < 1e-17L);
    assert_true(worst_h < 1e-10L);
    long double la, lo, h;
    const long double centre[3] = {10.0L, 0.0L, 0.0L};
    assert_int_equal(gg_geo_ecef_to_geodetic(centre, &la, &lo, &h), GG_ERR_RANGE);
}

/* Bad input is rejected, flagged, and leaves the state untouched; readings
 * lost beyond one per pair-axis (a NaN pair, every pair of an axis touched,
 * two opposite sensors bad) are rebuilt by the degraded path instead. */
static void test_rejections(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.p = 0.05L;
    T.s = 0.2L;
    static gg_nav3d_t nav, before;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 1, 10000, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    for (long long k = 0; k < 50; ++k) {
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    }
    make_frame(&T, 50, 10000, &fr);
    struct {
        const char *what;
        gg_status_t want;
        uint32_t bit;
    } cases[] = {{"nan pair", GG_ERR_NONFINITE, GG_HEALTH_ACC_NONFINITE},
                 {"range on every pair of an axis", GG_ERR_RANGE, GG_HEALTH_ACC_RANGE},
                 {"bad opposite sensors", GG_ERR_SENSOR, GG_HEALTH_ACC_SENSOR},
                 {"nan gyro", GG_ERR_SENSOR, GG_HEALTH_GYRO_INVALID},
                 {"gyro range", GG_ERR_SENSOR, GG_HEALTH_GYRO_INVALID},
                 {"bad gyro", GG_ERR_SENSOR, GG_HEALTH_GYRO_INVALID},
                 {"five acc", GG_ERR_SENSOR, GG_HEALTH_ACC_SENSOR},
                 {"repeat", GG_ERR_SEQUENCE, GG_HEALTH_SEQ_REPEAT},
                 {"time jump", GG_ERR_SEQUENCE, GG_HEALTH_TIME_JUMP}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        gg_frame_t bad = fr;
        switch (c) {
        case 0: bad.f[2][1] = NAN; bad.f[5][1] = NAN; break;
        case 1: bad.f[0][0] = 1e5; bad.f[1][0] = 1e5; bad.f[5][0] = 1e5; break;
        case 2: bad.acc_status[3] = GG_SENSOR_BAD; bad.acc_status[0] = GG_SENSOR_BAD; break;
        case 3: bad.omega_b[1] = NAN; break;
        case 4: bad.omega_b[2] = 50.0; break;
        case 5: bad.gyro_status = GG_SENSOR_BAD; break;
        case 6: bad.n_acc = 5; break;
        case 7: bad.seq = 49; bad.utime = 490000; break;
        default: bad.utime += 5000; break;
        }
        before = nav;
        const gg_status_t st = gg_nav3d_step(&nav, &bad, NULL, &out);
        if (c < 3) {
            /* more readings lost than one per pair-axis: the degraded rebuild
             * (fdi3d.h) uses the frame, flagged */
            if (st != GG_OK || (out.health & cases[c].bit) == 0U ||
                (out.health & (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_ACC_REBUILT)) !=
                    (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_ACC_REBUILT) ||
                (out.health & GG_HEALTH_FRAME_REJECTED) != 0U)
                fail_msg("%s: status %d health 0x%x (want used, degraded)", cases[c].what, st, out.health);
            nav = before;
            continue;
        }
        if (st != cases[c].want || (out.health & cases[c].bit) == 0U ||
            (out.health & GG_HEALTH_FRAME_REJECTED) == 0U)
            fail_msg("%s: status %d health 0x%x", cases[c].what, st, out.health);
        /* the navigation state is untouched (the stream follower moves on
         * with a frame whose sequencing is consistent: compared apart) */
        nav.seq = before.seq;
        assert_memory_equal(&nav, &before, sizeof nav);
        nav = before; /* each case against the same state */
    }
    /* the good frame is then accepted */
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    assert_int_equal(out.health & GG_HEALTH_FRAME_REJECTED, 0);
}

/* Gravity-model mode: a frame whose lost pairs (sensors 0, 1, 3, 4) take
 * column entries from the onboard model (the prior handed to fdi3d for that
 * step) and which is then rejected (a gradient beyond GG_LIM_GAMMA_MAX_S2
 * from the one pair left, which no parity check can catch) leaves the whole
 * task state byte-identical, the fault isolation's model prior included. */
static void test_model_prior_rejected(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    static gg_nav3d_t nav, before;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 0, 10000, &cfg);
    cfg.gravity_mode = GG_GRAVITY_MODEL;
    cfg.model.gm = 3.986004418e14L;
    cfg.model.a_m = 6378137.0L;
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    for (long long k = 0; k < 50; ++k) {
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    }
    make_frame(&T, 50, 10000, &fr);
    /* the model's entries are used for a lost pair: the frame is accepted */
    {
        gg_frame_t lost = fr;
        for (int j = 0; j < 3; ++j)
            for (int i = 0; i < 6; ++i)
                if (i != 2 && i != 5) lost.f[i][j] = NAN;
        before = nav;
        assert_int_equal(gg_nav3d_step(&nav, &lost, NULL, &out), GG_OK);
        assert_true((out.health & GG_HEALTH_GRAD_COAST) != 0U);
        nav = before;
    }
    /* the same, with an out-of-range gradient on the x pair of sensors 2/3 */
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 6; ++i)
            if (i != 2 && i != 5) fr.f[i][j] = NAN;
    fr.f[2][0] += 0.01;
    fr.f[5][0] -= 0.01;
    before = nav;
    const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
    if (st == GG_OK || (out.health & GG_HEALTH_FRAME_REJECTED) == 0U)
        fail_msg("status %d health 0x%x (want rejected)", st, out.health);
    nav.seq = before.seq;
    assert_memory_equal(&nav, &before, sizeof nav);
}

/* A run of bad frames never leaves the fault isolation refusing every frame
 * after (found by fuzz_nav3d): a platform at rest in a point-mass field
 * (stabilized, non-rotating, pair-mean detection on); one frame with a
 * denormal reading 5x (isolated and excluded), then one with sensor 0 reading
 * zero on every axis, 1x at -1.3e62 m/s^2 (out of range), 2x zero and 2z a
 * little off: used, degraded, and it leaves pair means and column entries in
 * the isolation's latched state from which the good frames that follow
 * rebuild an absurd gradient. Before, each of them was refused (ACC_RANGE)
 * and the latched state restored with it: frozen for good. Now a refused
 * frame is tried once more from a fresh isolation: the first good frame is
 * used (ACC_FAULT), and the position stays where the platform is. */
static void at_rest_frame(int64_t k, gg_frame_t *f)
{
    static const double off[6][3] = {{0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5},
                                     {-0.5, 0, 0}, {0, -0.5, 0}, {0, 0, -0.5}};
    const long double gm = 3.986004418e14L, r0 = 6378137.0L;
    memset(f, 0, sizeof *f);
    f->utime = k * 10000;
    f->seq = k;
    f->n_acc = 6;
    for (int s = 0; s < 6; ++s) {
        const long double p[3] = {r0 + off[s][0], off[s][1], off[s][2]};
        const long double rr = sqrtl(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int j = 0; j < 3; ++j) {
            const long double fv = gm * p[j] / (rr * rr * rr); /* f = -G at rest */
            f->f[s][j] = (double)fv;
            f->f_lo[s][j] = (double)(fv - (long double)f->f[s][j]);
        }
    }
    f->baro_status = GG_SENSOR_ABSENT;
    f->ca_status = GG_SENSOR_ABSENT;
}

static void test_poisoned_isolation(void **state)
{
    (void)state;
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    const long double gm = 3.986004418e14L, r0 = 6378137.0L;
    memset(&cfg, 0, sizeof cfg);
    for (int j = 0; j < 3; ++j) cfg.geometry.half_base_m[j] = 0.5L;
    cfg.platform = GG_PLATFORM_STABILIZED;
    cfg.dt_us = 10000;
    cfg.dt_tol_us = 100;
    cfg.r0_e[0] = r0;
    cfg.g0_e[0] = -gm / (r0 * r0);
    cfg.q0_b_e[0] = 1.0L;
    cfg.omega_ie = -1.0L;
    cfg.f_max = 100.0;
    cfg.asym_max = 1e-6;
    cfg.fdi_parity_f_max = GG_FDI3D_FLOOR_MPS2;
    cfg.gravity_mode = GG_GRAVITY_GRADIOMETER;
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    at_rest_frame(0, &fr);
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    at_rest_frame(1, &fr);
    fr.f[5][0] = 7.2036766980789388e-307;
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    assert_int_equal(out.acc_excluded, 1u << 15); /* 5x isolated */
    at_rest_frame(2, &fr);
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
    at_rest_frame(3, &fr);
    fr.f[0][0] = fr.f[0][1] = fr.f[0][2] = 0.0;
    fr.f[1][0] = -1.2984059704111749e+62;
    fr.f[2][0] = 0.0;
    fr.f[2][2] = 7.5500700593254799e-07;
    (void)gg_nav3d_step(&nav, &fr, NULL, &out);
    for (int64_t k = 4; k < 12; ++k) {
        at_rest_frame(k, &fr);
        const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
        if (st != GG_OK)
            fail_msg("good frame %lld refused: status %d, health 0x%x", (long long)k, st, out.health);
        if (k == 4) assert_true((out.health & GG_HEALTH_ACC_FAULT) != 0U);
    }
    /* the degraded frame 3 entered the state: its cost is bounded, not zero */
    const double dr = sqrt((out.r_e[0] - (double)r0) * (out.r_e[0] - (double)r0) + out.r_e[1] * out.r_e[1] +
                           out.r_e[2] * out.r_e[2]);
    if (!(dr < 1.0)) fail_msg("position off the platform by %g m after 0.12 s", dr);
}

/* One unusable reading per pair and axis is rebuilt from its partner and the
 * other pairs (fdi3d.h), on the tumbling strapdown flight at 200 m/s: NaN on
 * sensor 2's y axis, sensor 4 flagged bad (all three axes) and an
 * out-of-range x reading of sensor 0, from 10 s to the end. The rebuilt
 * reading keeps the curvature difference of its last whole frame, so its
 * error is at most twice the curvature term, df <= 2 (h_max^2 / 2) |D|_max
 * with |D|_max ~ 9 GM / r^4 for the point mass (the anomalies add less);
 * that is a gradient error df / (2 h_min) and a centre force error df / 6,
 * which over t s at v give |dr| <~ (df / 2h_min) v t^3 / 6 + (df / 6) t^2 / 2
 * against the clean run. */
static void test_rebuilt3d(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.lon_rate = 200.0L / (6.4e6L * cosl(T.lat0));
    T.p = 0.05L;
    T.s = 0.2L;
    static gg_nav3d_t nav, ref;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out, out_ref;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 0, 10000, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    assert_int_equal(gg_nav3d_init(&ref, &cfg), GG_OK);
    for (long long k = 0; k < 6000; ++k) {
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&ref, &fr, NULL, &out_ref), GG_OK);
        if (k >= 1000) {
            fr.f[2][1] = NAN;
            fr.acc_status[4] = GG_SENSOR_BAD;
            fr.f[0][0] = 1e5;
        }
        const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
        if (st != GG_OK) fail_msg("step %lld: status %d health 0x%x", k, st, out.health);
        if (k >= 1000) {
            const uint32_t want = GG_FDI3D_BIT(2, 1) | GG_FDI3D_BIT(4, 0) | GG_FDI3D_BIT(4, 1) |
                                  GG_FDI3D_BIT(4, 2) | GG_FDI3D_BIT(0, 0);
            assert_int_equal(out.acc_rebuilt, want);
            assert_true((out.health & GG_HEALTH_ACC_REBUILT) != 0U);
            assert_true((out.health & GG_HEALTH_FRAME_REJECTED) == 0U);
        }
    }
    long double a[3], b[3];
    for (int j = 0; j < 3; ++j) {
        a[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
        b[j] = (long double)out_ref.r_e[j] + (long double)out_ref.r_e_lo[j];
    }
    const long double dr = norm3l(a, b);
    const long double r = 6.38e6L, gm = 3.986004418e14L, t = 50.0L, v = 200.0L;
    const long double df = 2.0L * (0.5L * 0.6L * 0.6L) * 9.0L * gm / (r * r * r * r);
    const long double bound = (df / (2.0L * 0.4L)) * v * t * t * t / 6.0L + (df / 6.0L) * t * t / 2.0L;
    print_message("3-D: 5 readings rebuilt for 50 s (tumbling, 200 m/s): |dr| %.3Lg m vs clean run "
                  "(curvature bound %.3Lg m)\n", dr, bound);
    assert_true(dr < bound);
}

/* Fault detection and isolation (fdi3d.h) at the derived default threshold
 * on perfect sensors (GG_FDI3D_FLOOR_MPS2): a 1e-8 m/s^2 step bias from 10 s
 * on one reading moves its pair mean by 5e-9 m/s^2, so it is flagged on its
 * first step, isolated by the trace (a reading along its own offset) or the
 * antisymmetric part (a cross-axis reading: zero on the stabilized platform,
 * the gyro-derived angular acceleration on the strapdown one), excluded and
 * rebuilt; the error against the clean run is then that of a rebuilt reading
 * (test_rebuilt3d's curvature bound). Without detection the same bias gives
 * centimetres in a minute. Two biased pairs on one axis are detected and
 * the axis degrades to its third pair. */
static void test_fdi3d_isolation(void **state)
{
    (void)state;
    static gg_nav3d_t nav, ref;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out, out_ref;
    gg_frame_t fr;
    struct {
        int platform, sensor, axis;
    } cases[] = {{GG_PLATFORM_STABILIZED, 1, 2}, {GG_PLATFORM_STABILIZED, 5, 2},
                 {GG_PLATFORM_STABILIZED, 3, 1}, {GG_PLATFORM_STRAPDOWN, 0, 0},
                 {GG_PLATFORM_STRAPDOWN, 4, 1},  {GG_PLATFORM_STRAPDOWN, 2, 0}};
    const long double r = 6.38e6L, gm = 3.986004418e14L, t = 50.0L, v = 200.0L;
    const long double df = 2.0L * (0.5L * 0.6L * 0.6L) * 9.0L * gm / (r * r * r * r);
    const long double bound = (df / (2.0L * 0.4L)) * v * t * t * t / 6.0L + (df / 6.0L) * t * t / 2.0L;
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; ++c) {
        truth3_t T;
        default_truth(&T);
        T.lon_rate = 200.0L / (6.4e6L * cosl(T.lat0));
        if (cases[c].platform == GG_PLATFORM_STRAPDOWN) {
            T.p = 0.05L;
            T.s = 0.2L;
        }
        make_config(&T, cases[c].platform, 0, 10000, &cfg);
        cfg.fdi_parity_f_max = GG_FDI3D_FLOOR_MPS2;
        assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
        assert_int_equal(gg_nav3d_init(&ref, &cfg), GG_OK);
        long long first = -1;
        for (long long k = 0; k < 6000; ++k) {
            make_frame(&T, k, 10000, &fr);
            assert_int_equal(gg_nav3d_step(&ref, &fr, NULL, &out_ref), GG_OK);
            assert_int_equal(out_ref.health & GG_HEALTH_ACC_FAULT, 0);
            if (k >= 1000) fr.f[cases[c].sensor][cases[c].axis] += 1e-8;
            const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
            if (st != GG_OK) fail_msg("case %zu step %lld: status %d health 0x%x", c, k, st, out.health);
            if (first < 0 && (out.health & GG_HEALTH_ACC_FAULT)) first = k;
        }
        long double a[3], b[3];
        for (int j = 0; j < 3; ++j) {
            a[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
            b[j] = (long double)out_ref.r_e[j] + (long double)out_ref.r_e_lo[j];
        }
        const long double dr = norm3l(a, b);
        print_message("3-D FDI: %s, 1e-8 m/s^2 on %d%c: detected after %lld steps, excluded 0x%05x, "
                      "|dr| %.3Lg m vs clean run after 50 s (bound %.3Lg m)\n",
                      cases[c].platform == GG_PLATFORM_STRAPDOWN ? "strapdown" : "stabilized",
                      cases[c].sensor, "xyz"[cases[c].axis], first - 1000, out.acc_excluded, dr, bound);
        assert_int_equal(first, 1000);
        assert_int_equal(out.acc_excluded, GG_FDI3D_BIT(cases[c].sensor, cases[c].axis));
        assert_true(dr < bound);
    }
    /* a double fault on one axis (0y and 2y biased): detected, not isolable
     * from the pair means; the y axis is set aside and its third pair (1y/4y)
     * given back, as its two readings agree with the column entry M[y][1] the
     * trace gives from pairs 0 on x and 2 on z; every frame used, nothing held. The
     * error against the truth after 3 s: that of the clean run's rebuild,
     * well inside the single-reading bound. */
    {
        truth3_t T;
        default_truth(&T);
        make_config(&T, GG_PLATFORM_STABILIZED, 0, 10000, &cfg);
        cfg.fdi_parity_f_max = GG_FDI3D_FLOOR_MPS2;
        assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
        uint32_t seen = 0U;
        for (long long k = 0; k < 1300; ++k) {
            make_frame(&T, k, 10000, &fr);
            if (k >= 1000) {
                fr.f[0][1] += 1e-8;
                fr.f[2][1] -= 3e-8;
            }
            const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
            seen |= out.health;
            assert_int_equal(st, GG_OK);
        }
        long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3], a[3];
        truth_pose(&T, 12.99L, r_e, v_e, r_i, a_i, cbi, w, wd);
        for (int j = 0; j < 3; ++j) a[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
        const long double e = norm3l(a, r_e);
        print_message("3-D FDI: double fault 0y +1e-8, 2y -3e-8: health seen 0x%08x, |dr| %.3Lg m "
                      "after 3 s (bound %.3Lg m)\n", seen, e, bound);
        assert_true((seen & (GG_HEALTH_ACC_FAULT | GG_HEALTH_ACC_DEGRADED)) ==
                    (GG_HEALTH_ACC_FAULT | GG_HEALTH_ACC_DEGRADED));
        assert_int_equal(seen & (GG_HEALTH_COAST | GG_HEALTH_FRAME_REJECTED | GG_HEALTH_GRAD_COAST |
                                 GG_HEALTH_FORCE_COAST), 0);
        assert_int_equal(out.coast_steps, 0U);
        assert_true(e < bound);
    }
}

/* On the stabilized platform the gyros are not used: a NaN gyro is ignored. */
static void test_stabilized_ignores_gyro(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STABILIZED, 0, 10000, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    make_frame(&T, 0, 10000, &fr);
    fr.omega_b[0] = NAN;
    fr.gyro_status = GG_SENSOR_BAD;
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
}

/* Lost frames are bridged (flagged) and the flight still closes. */
static void test_bridge(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.lon_rate = 200.0L / (6.4e6L * cosl(T.lat0));
    T.p = 0.05L;
    T.s = 0.2L;
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 0, 10000, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    for (long long k = 0; k <= 6000; ++k) {
        if (k >= 3000 && k < 3005) continue; /* five frames lost */
        make_frame(&T, k, 10000, &fr);
        assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
        if (k == 3005) assert_true((out.health & GG_HEALTH_SEQ_GAP) != 0U);
    }
    long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3];
    truth_pose(&T, 60.0L, r_e, v_e, r_i, a_i, cbi, w, wd);
    long double re_hat[3];
    for (int j = 0; j < 3; ++j) re_hat[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
    print_message("5 lost frames bridged, 60 s: |dr| %.3Lg m\n", norm3l(re_hat, r_e));
    assert_true(norm3l(re_hat, r_e) < 1e-3L);
}

/* Recovery (navtask.h): 1.5 s of malformed frames (five accelerometers:
 * every frame of it is rejected) is followed, 0.5 s coasted on the
 * held inputs and 1 s bridged; every frame after is used. The error this
 * costs: the centre specific force turns (Earth and transport rate) at
 * |df/dt|, taken from the truth by central differences, so the velocity
 * error is about |df/dt| (T_c^2/2 + T_c T_b/2) for T_c = 0.5 s held and
 * T_b = 1 s ramped, flown on for 58.5 s. Before, the 101st rejected frame
 * froze the task for good. A lasting 1 us clock step (no tolerance)
 * re-synchronises after three frames. NaN on both readings of one pair on
 * one axis for 1.5 s no longer rejects a frame (before, it did and the task
 * coasted, 1.58e-2 m): the degraded rebuild (fdi3d.h) takes the pair's mean
 * from the other pairs and its column entry from the symmetry of Gamma, so
 * the error stays that of a rebuilt reading (test_rebuilt3d's curvature
 * bound, 4.06e-6 m, which the test allows). */
static void test_recovery3d(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    T.lon_rate = 200.0L / (6.4e6L * cosl(T.lat0));
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t out;
    gg_frame_t fr, f0, f1;
    long double fdot = 0.0L;
    make_frame(&T, 999, 10000, &f0);
    make_frame(&T, 1001, 10000, &f1);
    for (int j = 0; j < 3; ++j) {
        long double m0 = 0.0L, m1 = 0.0L;
        for (int i = 0; i < 6; ++i) {
            m0 += ((long double)f0.f[i][j] + (long double)f0.f_lo[i][j]) / 6.0L;
            m1 += ((long double)f1.f[i][j] + (long double)f1.f_lo[i][j]) / 6.0L;
        }
        fdot += ((m1 - m0) / 0.02L) * ((m1 - m0) / 0.02L);
    }
    fdot = sqrtl(fdot);
    for (int c = 0; c < 3; ++c) {
        make_config(&T, GG_PLATFORM_STABILIZED, 0, 10000, &cfg);
        if (c == 1) cfg.dt_tol_us = 0;
        assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
        uint32_t seen = 0U;
        double max_outage = 0.0;
        for (long long k = 0; k < 6000; ++k) {
            make_frame(&T, k, 10000, &fr);
            if (c == 0 && k >= 1000 && k < 1150) fr.n_acc = 5;
            if (c == 1 && k >= 1000) fr.utime += 1;
            if (c == 2 && k >= 1000 && k < 1150) fr.f[2][1] = fr.f[5][1] = NAN;
            const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &out);
            seen |= out.health;
            if (out.outage_s > max_outage) max_outage = out.outage_s;
            if (k >= (c == 0 ? 1150 : c == 1 ? 1002 : 0) && st != GG_OK)
                fail_msg("case %d step %lld: status %d health 0x%x", c, k, st, out.health);
        }
        long double r_e[3], v_e[3], r_i[3], a_i[3], cbi[3][3], w[3], wd[3];
        truth_pose(&T, 59.99L, r_e, v_e, r_i, a_i, cbi, w, wd);
        long double re_hat[3];
        for (int j = 0; j < 3; ++j) re_hat[j] = (long double)out.r_e[j] + (long double)out.r_e_lo[j];
        const long double e = norm3l(re_hat, r_e);
        if (c == 0) {
            const long double bound = fdot * (0.5L * 0.25L + 0.5L * 0.5L * 1.0L) * 58.5L;
            print_message("3-D recovery: malformed frames 1.5 s: |dr| %.3Lg m after 60 s (held-input "
                          "estimate %.3Lg m, |df/dt| %.3Lg m/s^3), outage %.2f s, %u coasted\n",
                          e, bound, fdot, max_outage, out.coast_steps);
            assert_true((seen & GG_HEALTH_COAST) != 0U);
            assert_int_equal(out.coast_steps, 50);
            assert_near(max_outage, 1.5, 1e-9);
            assert_true(e < 2.0L * bound);
        } else if (c == 2) {
            print_message("3-D: NaN pair 2y/5y 1.5 s, degraded: |dr| %.3Lg m after 60 s, health seen "
                          "0x%08x, %u coasted\n", e, seen, out.coast_steps);
            assert_true((seen & (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_ACC_NONFINITE)) ==
                        (GG_HEALTH_ACC_DEGRADED | GG_HEALTH_ACC_NONFINITE));
            assert_int_equal(seen & (GG_HEALTH_COAST | GG_HEALTH_FRAME_REJECTED), 0);
            assert_true(e < 4.06e-6L);
        } else {
            print_message("3-D recovery: 1 us clock step: |dr| %.3Lg m after 60 s, %u resync\n", e,
                          out.resync_count);
            assert_int_equal(out.resync_count, 1);
            assert_true((seen & GG_HEALTH_RESYNC) != 0U);
            assert_true(e < 1e-3L); /* as test_bridge: two steps bridged */
        }
    }
}

/* Parity: zero (to the curvature terms) for a healthy platform; a step on
 * the y axis of accelerometer 0 (at +a on x) shows in the antisymmetric
 * residual as (Gao eq. 27) step / (2 * 2a) on z and raises the health flag.
 * Stabilized: 1e-8 m/s^2 step, threshold 1e-9; strapdown: the gyro-derived
 * angular acceleration has its own 1.3e-8 rad/s^2 error (nav3d.h), so a
 * 1e-6 m/s^2 step against a 1e-7 threshold. */
static void test_parity(void **state)
{
    (void)state;
    for (int fault = 0; fault < 2; ++fault) {
        for (int platform = 0; platform < 2; ++platform) {
            const int sd = (platform == GG_PLATFORM_STRAPDOWN);
            const double step = sd ? 1e-6 : 1e-8;
            truth3_t T;
            default_truth(&T);
            if (sd) {
                T.p = 0.05L;
                T.s = 0.2L;
            }
            static gg_nav3d_t nav;
            gg_nav3d_config_t cfg;
            gg_nav3d_output_t out;
            gg_frame_t fr;
            make_config(&T, platform, 0, 10000, &cfg);
            cfg.asym_max = sd ? 1e-7 : 1e-9;
            assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
            for (long long k = 0; k <= 100; ++k) {
                if (fault && k == 50) T.bias[0][1] = step;
                make_frame(&T, k, 10000, &fr);
                assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_OK);
                if (k < 50 || !fault) {
                    if ((out.health & GG_HEALTH_GAMMA_ASYM) != 0U)
                        fail_msg("platform %d step %lld: parity %g %g %g %g", platform, k, out.parity[0],
                                 out.parity[1], out.parity[2], out.parity[3]);
                } else {
                    assert_true((out.health & GG_HEALTH_GAMMA_ASYM) != 0U);
                    /* M[1][0] = (f0y - f3y)/(2a) gains step/(2a); omega_dot_z = (M10 - M01)/2 */
                    assert_near(out.parity[2], step / (2.0 * 2.0 * 0.5), sd ? 2e-8 : 1e-11);
                }
            }
        }
    }
}

static void test_config(void **state)
{
    (void)state;
    truth3_t T;
    default_truth(&T);
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg, bad;
    make_config(&T, GG_PLATFORM_STRAPDOWN, 1, 10000, &cfg);
    assert_int_equal(gg_nav3d_init(&nav, &cfg), GG_OK);
    bad = cfg; bad.q0_b_e[0] = 0.9L;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_CONFIG);
    bad = cfg; bad.geometry.half_base_m[2] = 0.0L;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_CONFIG);
    bad = cfg; bad.platform = 7;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_CONFIG);
    bad = cfg; bad.dt_us = 0;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_CONFIG);
    bad = cfg; bad.r0_e[1] = NAN;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_CONFIG);
    bad = cfg; bad.v0_e[0] = 1e6L;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_RANGE);
    bad = cfg; bad.r0_e[0] = 1.0L; bad.r0_e[1] = 0.0L; bad.r0_e[2] = 0.0L;
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_RANGE);
    assert_int_equal(gg_nav3d_init(NULL, &cfg), GG_ERR_NULL);
    /* not configured: a step is refused and flagged */
    gg_frame_t fr;
    gg_nav3d_output_t out;
    make_frame(&T, 0, 10000, &fr);
    assert_int_equal(gg_nav3d_init(&nav, &bad), GG_ERR_RANGE);
    assert_int_equal(gg_nav3d_step(&nav, &fr, NULL, &out), GG_ERR_NOT_INIT);
    assert_true((out.health & GG_HEALTH_NOT_INIT) != 0U);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_geodetic),
        cmocka_unit_test(test_config),
        cmocka_unit_test(test_rejections),
        cmocka_unit_test(test_model_prior_rejected),
        cmocka_unit_test(test_poisoned_isolation),
        cmocka_unit_test(test_stabilized_ignores_gyro),
        cmocka_unit_test(test_parity),
        cmocka_unit_test(test_bridge),
        cmocka_unit_test(test_recovery3d),
        cmocka_unit_test(test_rebuilt3d),
        cmocka_unit_test(test_fdi3d_isolation),
        cmocka_unit_test(test_earth_rate_matters),
        cmocka_unit_test(test_stabilized_parked_1h),
        cmocka_unit_test(test_strapdown_tumbling_flight_1h),
        cmocka_unit_test(test_strapdown_startup_fast_body),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
