/* Generated fault matrix, in process: every kind of accelerometer fault on
 * every single reading, every pair of readings (the same kind on both), every
 * known-bad reading together with a stepped one, and the common-mode cases
 * (every reading of one axis, every reading), for the 2-D task (nav2d, four
 * dual-axis accelerometers, parity detection on) and the 3-D task (nav3d,
 * six tri-axis accelerometers on a stabilized platform, pair-mean detection
 * on), fed synthetic frames of closed-form flights:
 *   2-D  the analytic north flight of truth2d.h (300 m/s along a circle of
 *        the point-mass Earth, every reading the exact field at its sensor);
 *   3-D  a straight inertial line at 300 m/s, 3 km up at 0.7 rad latitude
 *        (non-rotating point-mass Earth, a = 0 so f_p = -G(r + d_p) exactly).
 * For each case: detected (a validation or parity health bit from the first
 * faulty frame on), flagged (a degraded-mode bit: readings rebuilt, group
 * degraded, gradient or force held, frames rejected/coasted), navigating (no
 * freeze: at the end the state has caught up with the frame stream, within
 * the bridge, and every output is finite), and the position error at the end
 * against the truth, compared with a bound computed for that case before it
 * runs from what its health says was held (GRAD_COAST, FORCE_COAST, COAST) and
 * which faulty readings were not set aside (see case_bound).
 *
 * Geometry (what parity can and cannot see): an equal fault on every reading
 * of one axis - all x, all z (2-D), all x, y or z (3-D), or all readings - is
 * indistinguishable from a change of the centre specific force: no parity
 * relation moves, so an additive one (step, drift) is neither detected nor
 * flagged, and its error is the fault's own (the matrix checks that bound,
 * nothing more). Every other additive pattern moves some parity residual and
 * must be detected. A stuck reading, alone or common to an axis, is seen by
 * the frozen-reading monitor (navtask.h, on in both tasks here with
 * FROZEN_FRAMES: the readings of these flights change every frame, as noisy
 * readings do) and must be detected and flagged.
 *
 *   test_fault_matrix            reduced matrix (3 s flights), exit 1 on any
 *                                freeze, rejected frame, unflagged visible fault
 *                                or error above its bound (CTest unit.test_fault_matrix)
 *   test_fault_matrix --full     30 s flights; --md prints the markdown table
 *                                (scripts/fault-matrix puts it in docs/faults.md) */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_common.h"
#include "truth2d.h"
#include "ggins/nav2d.h"
#include "ggins/nav3d.h"
#include "truth3.h"

#define DT_US 10000
#define K0 100 /* first faulty step (1 s) */

enum { K_NAN, K_RANGE, K_STATUS, K_STUCK, K_STEP, K_DRIFT, K_COUNT };
static const char *kKind[K_COUNT] = {"NaN", "out of range", "status bad", "stuck", "step 1e-9",
                                     "drift 1e-10/s"};
#define STEP_MPS2 1e-9L
#define DRIFT_MPS3 1e-10L

enum { C_SINGLE, C_PAIR_IN, C_PAIR_ACROSS, C_MIXED, C_AXIS, C_ALL, C_COUNT };
static const char *kClass[C_COUNT] = {"single reading", "pair, same axis group",
                                      "pair, different axes", "known-bad + step on another",
                                      "common mode: one axis, every sensor",
                                      "common mode: every reading"};

#define DETECT_BITS (GG_HEALTH_ACC_NONFINITE | GG_HEALTH_ACC_RANGE | GG_HEALTH_ACC_SENSOR | \
                     GG_HEALTH_ACC_FAULT | GG_HEALTH_GAMMA_ASYM | GG_HEALTH_ACC_FROZEN)
/* frozen-reading window of both tasks (navtask.h), frames */
#ifndef FROZEN_FRAMES
#define FROZEN_FRAMES 10
#endif
#define FLAG_BITS (GG_HEALTH_ACC_REBUILT | GG_HEALTH_ACC_DEGRADED | GG_HEALTH_GRAD_COAST | \
                   GG_HEALTH_FORCE_COAST | GG_HEALTH_COAST | GG_HEALTH_FRAME_REJECTED)

typedef struct {
    int dim;          /* 2 or 3 */
    int cls;
    int kind;         /* on mask */
    uint32_t mask;    /* readings: 2-D bit 2 s + ax (ax 0 x, 1 z), 3-D bit 3 s + j */
    uint32_t step_mask; /* C_MIXED: readings stepped (kind on mask is known-bad) */
} fcase_t;

typedef struct {
    int det;          /* steps from K0 to the first detection bit, -1 none */
    uint32_t seen;    /* health bits seen from K0 on */
    int rejected;
    int navigating;
    long double err;  /* |dr| at the end, m */
    long double bound;
    int64_t last_used[18]; /* last step from K0 on at which the reading was in use (neither
                              rebuilt nor excluded), K0 - 1 if never */
} fresult_t;

static int g_n = 300;   /* steps per flight */
static long double g_ref_err[4];

/* ---------------- truth ---------------- */
static const t_flight_t kFlight2 = {300.0L, 0.0L, 0.0L};

static const long double kHb3[3] = {0.5L, 0.4L, 0.6L};
static void truth3(long double t, long double r[3], long double v[3])
{
    const long double lat = 0.7L, lon = 0.2L, R = T_RE + 3000.0L;
    v[0] = -300.0L * sinl(lon);
    v[1] = 300.0L * cosl(lon);
    v[2] = 0.0L;
    r[0] = R * cosl(lat) * cosl(lon) + v[0] * t;
    r[1] = R * cosl(lat) * sinl(lon) + v[1] * t;
    r[2] = R * sinl(lat) + v[2] * t;
}

static void frame3(int64_t k, gg_frame_t *fr)
{
    long double r[3], v[3];
    truth3((long double)k * DT_US * 1e-6L, r, v);
    memset(fr, 0, sizeof *fr);
    fr->utime = k * DT_US;
    fr->seq = k;
    fr->n_acc = 6;
    for (int s = 0; s < 6; ++s) {
        long double p[3] = {r[0], r[1], r[2]}, g[3];
        p[s % 3] += (s < 3 ? 1.0L : -1.0L) * kHb3[s % 3];
        t_point_mass_g(p, g);
        for (int j = 0; j < 3; ++j) {
            fr->f[s][j] = (double)-g[j];
            fr->f_lo[s][j] = (double)(-g[j] - (long double)fr->f[s][j]);
        }
        fr->acc_status[s] = GG_SENSOR_OK;
    }
    fr->gyro_status = GG_SENSOR_OK;
    fr->baro_status = GG_SENSOR_ABSENT;
}

static void frame2(int64_t k, gg_frame_t *fr) { t_make_frame(&kFlight2, k, DT_US, 1000000, NULL, 0, fr); }

/* largest |dGamma_jk/dt| and |df_c/dt| along the flight (central differences of the truth) */
static void rates(int dim, long double *gdot, long double *fdot)
{
    *gdot = 0.0L;
    *fdot = 0.0L;
    for (int i = 0; i <= 10; ++i) {
        const long double t = (long double)g_n * DT_US * 1e-6L * i / 10.0L;
        long double r1[3], r2[3], v[3], a1[3], a2[3], g1[3], g2[3], G1[3][3], G2[3][3];
        if (dim == 2) {
            t_flight(&kFlight2, t - 0.5L, r1, v, a1);
            t_flight(&kFlight2, t + 0.5L, r2, v, a2);
        } else {
            truth3(t - 0.5L, r1, v);
            truth3(t + 0.5L, r2, v);
            memset(a1, 0, sizeof a1);
            memset(a2, 0, sizeof a2);
        }
        t_point_mass_g(r1, g1);
        t_point_mass_g(r2, g2);
        t_point_mass_gamma(r1, G1);
        t_point_mass_gamma(r2, G2);
        long double df = 0.0L;
        for (int j = 0; j < 3; ++j) {
            const long double d = (a2[j] - g2[j]) - (a1[j] - g1[j]);
            df += d * d;
            for (int k = 0; k < 3; ++k)
                if (fabsl(G2[j][k] - G1[j][k]) > *gdot) *gdot = fabsl(G2[j][k] - G1[j][k]);
        }
        if (sqrtl(df) > *fdot) *fdot = sqrtl(df);
    }
}

/* ---------------- one flight ---------------- */
static void apply(int dim, int kind, uint32_t mask, int64_t k, const gg_frame_t *f0, gg_frame_t *fr)
{
    const int per = (dim == 2) ? 2 : 3;
    for (int r = 0; r < per * (dim == 2 ? 4 : 6); ++r) {
        if (!(mask & (1u << r))) continue;
        const int s = r / per;
        const int ax = (dim == 2) ? ((r % 2) ? 2 : 0) : r % 3;
        long double v = (long double)fr->f[s][ax] + (long double)fr->f_lo[s][ax];
        switch (kind) {
        case K_NAN: fr->f[s][ax] = NAN; continue;
        case K_RANGE: fr->f[s][ax] = 1e3; fr->f_lo[s][ax] = 0.0; continue;
        case K_STATUS: fr->acc_status[s] = GG_SENSOR_BAD; continue;
        case K_STUCK: fr->f[s][ax] = f0->f[s][ax]; fr->f_lo[s][ax] = f0->f_lo[s][ax]; continue;
        case K_STEP: v += STEP_MPS2; break;
        default: v += DRIFT_MPS3 * (long double)(k - K0) * DT_US * 1e-6L; break;
        }
        fr->f[s][ax] = (double)v;
        fr->f_lo[s][ax] = (double)(v - (long double)fr->f[s][ax]);
    }
}

static void config2(gg_nav2d_config_t *cfg)
{
    long double r[3], v[3], a[3], g[3];
    memset(cfg, 0, sizeof *cfg);
    t_flight(&kFlight2, 0.0L, r, v, a);
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
    cfg->asym_max = 1e-6;
    cfg->fdi_parity_f_max = 1e-11;
    cfg->fdi_asym_max = 1e-11;
    cfg->acc_frozen_frames = FROZEN_FRAMES;
}

static void config3(gg_nav3d_config_t *cfg)
{
    long double r[3], v[3], g[3];
    truth3(0.0L, r, v);
    t_point_mass_g(r, g);
    memset(cfg, 0, sizeof *cfg);
    for (int j = 0; j < 3; ++j) {
        cfg->geometry.half_base_m[j] = kHb3[j];
        cfg->r0_e[j] = r[j];
        cfg->v0_e[j] = v[j];
        cfg->g0_e[j] = g[j];
    }
    cfg->q0_b_e[0] = 1.0L;
    cfg->platform = GG_PLATFORM_STABILIZED;
    cfg->dt_us = DT_US;
    cfg->dt_tol_us = 100;
    cfg->omega_ie = -1.0L; /* non-rotating */
    cfg->f_max = 100.0;
    cfg->asym_max = 1e-6;
    cfg->fdi_parity_f_max = 1e-11;
    cfg->gravity_mode = GG_GRAVITY_GRADIOMETER;
    cfg->acc_frozen_frames = FROZEN_FRAMES;
}

static long double err_at(int dim, const void *out, int64_t k)
{
    long double r[3], v[3], a[3], rn[3];
    const long double t = (long double)k * DT_US * 1e-6L;
    if (dim == 2) {
        const gg_nav_output_t *o = out;
        t_flight(&kFlight2, t, r, v, a);
        for (int j = 0; j < 3; ++j) rn[j] = o->r_i[j];
    } else {
        const gg_nav3d_output_t *o = out;
        truth3(t, r, v);
        for (int j = 0; j < 3; ++j) rn[j] = (long double)o->r_e[j] + (long double)o->r_e_lo[j];
    }
    return norm3l(rn, r);
}

static int finite_out(int dim, const void *out)
{
    if (dim == 2) {
        const gg_nav_output_t *o = out;
        for (int j = 0; j < 3; ++j)
            if (!isfinite(o->r_i[j]) || !isfinite(o->v_i[j]) || !isfinite(o->g_i[j])) return 0;
    } else {
        const gg_nav3d_output_t *o = out;
        for (int j = 0; j < 3; ++j)
            if (!isfinite(o->r_e[j]) || !isfinite(o->v_e[j]) || !isfinite(o->g_e[j])) return 0;
    }
    return 1;
}

/* fly one case (kind < 0: no fault) */
static void fly(const fcase_t *c, fresult_t *res, uint32_t *set_aside)
{
    static gg_nav2d_t nav2;
    static gg_nav3d_t nav3;
    gg_nav2d_config_t c2;
    gg_nav3d_config_t c3;
    gg_frame_t fr, f0;
    gg_nav_output_t o2;
    gg_nav3d_output_t o3;
    memset(res, 0, sizeof *res);
    memset(&f0, 0, sizeof f0);
    res->det = -1;
    res->navigating = 1;
    for (int i = 0; i < 18; ++i) res->last_used[i] = K0 - 1;
    if (c->dim == 2) {
        config2(&c2);
        if (gg_nav2d_init(&nav2, &c2) != GG_OK) abort();
    } else {
        config3(&c3);
        if (gg_nav3d_init(&nav3, &c3) != GG_OK) abort();
    }
    for (int64_t k = 0; k < g_n; ++k) {
        if (c->dim == 2) frame2(k, &fr);
        else frame3(k, &fr);
        if (k == K0) f0 = fr;
        if (c->kind >= 0 && k >= K0) {
            apply(c->dim, c->kind, c->mask, k, &f0, &fr);
            if (c->step_mask) apply(c->dim, K_STEP, c->step_mask, k, &f0, &fr);
        }
        uint32_t h, not_used;
        double lag;
        const void *out;
        if (c->dim == 2) {
            (void)gg_nav2d_step(&nav2, &fr, NULL, &o2);
            h = o2.health;
            lag = o2.state_lag_s;
            out = &o2;
            *set_aside = o2.acc_excluded;
            not_used = o2.acc_excluded | o2.acc_rebuilt;
            if (h & GG_HEALTH_FRAME_REJECTED) not_used = 0xFFu;
        } else {
            (void)gg_nav3d_step(&nav3, &fr, NULL, &o3);
            h = o3.health;
            lag = o3.state_lag_s;
            out = &o3;
            *set_aside = o3.acc_excluded;
            not_used = o3.acc_excluded | o3.acc_rebuilt;
            if (h & GG_HEALTH_FRAME_REJECTED) not_used = 0x3FFFFu;
        }
        if (k >= K0)
            for (int i = 0; i < 18; ++i)
                if (!(not_used & (1u << i))) res->last_used[i] = k;
        if (!finite_out(c->dim, out)) res->navigating = 0;
        if (k >= K0) {
            res->seen |= h;
            if ((h & DETECT_BITS) && res->det < 0) res->det = (int)(k - K0);
            if (h & GG_HEALTH_FRAME_REJECTED) res->rejected++;
        }
        if (k == g_n - 1) {
            /* the output's state is that of the task clock, lag behind this
             * frame (up to the bridge while coasting): compared with the
             * truth at the state's own time */
            if (lag > (GG_NAV2D_MAX_BRIDGE + 1) * DT_US * 1e-6) res->navigating = 0;
            res->err = err_at(c->dim, out, k - (int64_t)llround(lag / (DT_US * 1e-6)));
        }
    }
}

/* Bound on the error at the end, from what the health says was held and
 * which faulty readings were in use when (T = time from the fault to the end,
 * V = 300 m/s, h = the shortest half-baseline, gd/fd the truth's largest
 * gradient and specific-force rates):
 *   clean run's own error + 1e-9 m
 *   + gradient held (GRAD_COAST):          2 x 4 gd V T^4 / 24   (up to four components)
 *   + inputs held (FORCE_COAST, COAST):    2 x (fd T^3 / 6 + 4 gd V T^4 / 24)
 *     (the factor 2 as in test_nav2d: the estimates leave out the vertical
 *     mode and the step the held value is late by)
 *   + per faulty reading still in use at the end (no parity isolated it, e.g.
 *     the partner of a lost reading, whose pair no other relation checks):
 *       step d:    d (T^2/2 + 2 V T^3 / (6 h))   (into the centre force, and into a
 *                                                 gradient through itself and a reading
 *                                                 rebuilt from it)
 *       drift d':  d' (T^3/6 + 2 V T^4 / (24 h))
 *       stuck:     fd (T^3/6 + 2 V T^4 / (24 h)) (off by the change of its true reading)
 *   + per faulty reading set aside (rebuilt or excluded) from some step to the
 *     end: d_last (T^2/2 + 2 V T^3 / (6 h)), d_last its fault on the last step
 *     it was used (0 if none). Why: the rebuild takes a set-aside reading from
 *     its partner and the other pairs' means with the pair-mean difference and
 *     column entries of the last frame used, and holds nothing else of it, so
 *     what it leaves in the state is at most the fault it had on the last frame
 *     that used it, carried to the end; before that, step, drift and stuck
 *     faults never exceed it (|stuck(t)| = |f(t_0) - f(t)| <= |df_s/dt| (t -
 *     t_0), |df_s/dt| <= 2 fd: the sensor's own rate differs from the centre's
 *     by |dGamma/dr| |d| V, 1e-6 of it). A stuck reading detected on its second
 *     frame (its first one reads the true value) leaves nothing: this replaces
 *     the stuck term above, which assumed the reading in use to the end
 *     (4e4 m on these flights, against errors of 1e-10..1e-3 m). */
static long double case_bound(const fcase_t *c, const fresult_t *r, uint32_t set_aside)
{
    long double gd, fd;
    rates(c->dim, &gd, &fd);
    const long double T = (long double)(g_n - 1 - K0) * DT_US * 1e-6L, V = 300.0L;
    const long double h = (c->dim == 2) ? 0.5L : 0.4L;
    long double b = g_ref_err[c->dim] + 1e-9L;
    const long double grad_hold = 2.0L * 4.0L * gd * V * powl(T, 4) / 24.0L;
    (void)set_aside;
    if (r->seen & (GG_HEALTH_FORCE_COAST | GG_HEALTH_COAST)) b += 2.0L * fd * powl(T, 3) / 6.0L + grad_hold;
    else if (r->seen & GG_HEALTH_GRAD_COAST) b += grad_hold;
    const uint32_t add_mask = ((c->kind >= K_STUCK) ? c->mask : 0U) | c->step_mask;
    int all_in_use = 1;
    for (int i = 0; i < 18; ++i)
        if ((add_mask & (1u << i)) && r->last_used[i] < g_n - 1) all_in_use = 0;
    if ((c->cls == C_AXIS || c->cls == C_ALL) && c->kind >= K_STUCK && all_in_use) {
        /* the same fault e(t) on every reading of n axes, none set aside: the
         * centre force of each axis is off by e(t) and no difference moves
         * (step, drift), so the error is that of a force error e integrated
         * twice, sqrt(n) e T^2/2 or sqrt(n) e' T^3/6; a stuck common mode holds
         * those axes' centre forces and their column entries from t_0, i.e.
         * the inputs-held term. The factor 2 as above. */
        const long double n_ax = (c->cls == C_ALL) ? ((c->dim == 2) ? 2.0L : 3.0L) : 1.0L;
        if (c->kind == K_STEP) b += 2.0L * sqrtl(n_ax) * STEP_MPS2 * T * T / 2.0L;
        else if (c->kind == K_DRIFT) b += 2.0L * sqrtl(n_ax) * DRIFT_MPS3 * powl(T, 3) / 6.0L;
        else b += 2.0L * fd * powl(T, 3) / 6.0L + grad_hold;
        return b;
    }
    for (int i = 0; i < 18; ++i) {
        if (!(add_mask & (1u << i))) continue;
        const int kind = (c->step_mask & (1u << i)) ? K_STEP : c->kind;
        if (r->last_used[i] < g_n - 1) {
            /* set aside from last_used + 1 to the end */
            const long double tl = (long double)(r->last_used[i] - K0) * DT_US * 1e-6L;
            long double d = 0.0L;
            if (r->last_used[i] >= K0)
                d = (kind == K_STEP) ? STEP_MPS2 : (kind == K_DRIFT) ? DRIFT_MPS3 * tl : 2.0L * fd * tl;
            b += d * (T * T / 2.0L + 2.0L * V * powl(T, 3) / (6.0L * h));
            continue;
        }
        if (kind == K_STEP) b += STEP_MPS2 * (T * T / 2.0L + 2.0L * V * powl(T, 3) / (6.0L * h));
        else if (kind == K_DRIFT) b += DRIFT_MPS3 * (powl(T, 3) / 6.0L + 2.0L * V * powl(T, 4) / (24.0L * h));
        else b += fd * (powl(T, 3) / 6.0L + 2.0L * V * powl(T, 4) / (24.0L * h));
    }
    return b;
}

/* an equal additive fault on a union of whole axis groups moves no parity relation */
static int visible(const fcase_t *c)
{
    if (c->step_mask) {
        /* 2-D: with one reading of pair 1x/3x (2z/4z) lost, its partner alone
         * gives Gxx (Gzz), which no parity relation contains: a fault on the
         * partner is invisible */
        if (c->dim == 2) {
            const uint32_t pa = GG_FDI_BIT(0, 0) | GG_FDI_BIT(2, 0), pb = GG_FDI_BIT(1, 1) | GG_FDI_BIT(3, 1);
            if (((c->mask & pa) && (c->step_mask & pa)) || ((c->mask & pb) && (c->step_mask & pb))) return 0;
        }
        return 1;
    }
    if (c->kind <= K_STUCK) return 1; /* a stuck reading: the frozen-reading monitor */
    const int per = (c->dim == 2) ? 2 : 3, ns = (c->dim == 2) ? 4 : 6;
    for (int ax = 0; ax < per; ++ax) {
        uint32_t g = 0U;
        for (int s = 0; s < ns; ++s) g |= 1u << (per * s + ax);
        const uint32_t in = c->mask & g;
        if (in != 0U && in != g) return 1;
    }
    return 0;
}

/* ---------------- the matrix ---------------- */
typedef struct {
    int cases, detected, flagged, navigating, pass, rejected, max_det;
    uint32_t seen;
    long double max_err, max_ratio;
    int vis;
} agg_t;

static agg_t g_agg[4][C_COUNT][K_COUNT];
static int g_fail;

static void name_readings(int dim, uint32_t m, char *buf, size_t n)
{
    const int per = (dim == 2) ? 2 : 3;
    const char *axn = (dim == 2) ? "xz" : "xyz";
    size_t o = 0;
    buf[0] = 0;
    for (int i = 0; i < 18 && o + 6 < n; ++i)
        if (m & (1u << i)) o += (size_t)snprintf(buf + o, n - o, "%s%d%c", o ? "," : "", i / per + 1, axn[i % per]);
}

static void run_case(const fcase_t *c)
{
    fresult_t r;
    uint32_t set_aside = 0U;
    fly(c, &r, &set_aside);
    r.bound = case_bound(c, &r, set_aside);
    const int vis = visible(c);
    const int det = r.det >= 0;
    const int flg = (r.seen & FLAG_BITS) != 0U;
    /* readings only are faulty, and a first frame was used before: a group that
     * loses more than it can rebuild degrades, no frame is rejected */
    int ok = r.navigating && r.err <= r.bound && r.rejected == 0;
    if (vis && !(det && flg)) ok = 0;
    agg_t *a = &g_agg[c->dim][c->cls][c->kind];
    a->cases++;
    a->vis |= vis ? 1 : 2;
    a->detected += det;
    a->flagged += flg;
    a->navigating += r.navigating;
    a->pass += ok;
    a->rejected += r.rejected;
    if (r.det > a->max_det) a->max_det = r.det;
    a->seen |= r.seen;
    if (r.err > a->max_err) a->max_err = r.err;
    if (r.err / r.bound > a->max_ratio) a->max_ratio = r.err / r.bound;
    if (!ok || getenv("FM_VERBOSE")) {
        char b1[96], b2[96];
        name_readings(c->dim, c->mask, b1, sizeof b1);
        name_readings(c->dim, c->step_mask, b2, sizeof b2);
        printf("%s %d-D %s %s on %s%s%s: detected %d (after %d), flagged %d, navigating %d, "
               "|dr| %.3Lg m (bound %.3Lg), health seen 0x%08x, excluded at end 0x%05x\n",
               ok ? "CASE" : "FAIL", c->dim, kClass[c->cls], kKind[c->kind], b1, b2[0] ? " + step on " : "", b2, det, r.det,
               flg, r.navigating, r.err, r.bound, r.seen, set_aside);
        if (!ok) g_fail++;
    }
}

static void run_matrix(int dim)
{
    const int per = (dim == 2) ? 2 : 3, ns = (dim == 2) ? 4 : 6, nr = per * ns;
    fcase_t c = {dim, 0, -1, 0U, 0U};
    fresult_t r;
    uint32_t sa;
    fly(&c, &r, &sa);
    g_ref_err[dim] = r.err;
    printf("%d-D clean flight: |dr| %.3Lg m after %.2f s\n", dim, r.err, (g_n - 1) * DT_US * 1e-6);
    for (int kind = 0; kind < K_COUNT; ++kind) {
        c.kind = kind;
        c.step_mask = 0U;
        if (kind == K_STATUS) {
            /* sensor-level: every sensor, every pair of sensors */
            for (int s = 0; s < ns; ++s) {
                c.cls = C_SINGLE;
                c.mask = ((1u << per) - 1u) << (per * s);
                run_case(&c);
                for (int t = s + 1; t < ns; ++t) {
                    c.cls = C_PAIR_ACROSS;
                    c.mask = (((1u << per) - 1u) << (per * s)) | (((1u << per) - 1u) << (per * t));
                    run_case(&c);
                }
            }
        } else {
            for (int i = 0; i < nr; ++i) {
                c.cls = C_SINGLE;
                c.mask = 1u << i;
                run_case(&c);
                for (int j = i + 1; j < nr; ++j) {
                    c.cls = (i % per == j % per) ? C_PAIR_IN : C_PAIR_ACROSS;
                    c.mask = (1u << i) | (1u << j);
                    run_case(&c);
                }
            }
        }
        for (int ax = 0; ax < per; ++ax) {
            c.cls = C_AXIS;
            c.mask = 0U;
            for (int s = 0; s < ns; ++s) c.mask |= 1u << (per * s + ax);
            if (kind == K_STATUS) continue; /* a status is per sensor */
            run_case(&c);
        }
        c.cls = C_ALL;
        c.mask = (1u << nr) - 1u;
        run_case(&c);
        if (kind <= K_STATUS) {
            for (int i = 0; i < nr; ++i) {
                for (int j = 0; j < nr; ++j) {
                    if (i == j) continue;
                    c.cls = C_MIXED;
                    c.mask = (kind == K_STATUS) ? ((1u << per) - 1u) << (per * (i / per)) : 1u << i;
                    if (c.mask & (1u << j)) continue;
                    if (kind == K_STATUS && (i % per) != 0) continue; /* once per sensor */
                    c.step_mask = 1u << j;
                    run_case(&c);
                }
            }
            c.step_mask = 0U;
        }
    }
}

static const char *geometry_note(int dim, int cls)
{
    if (dim == 2) {
        switch (cls) {
        case C_SINGLE: return "2x, 4x, 1z, 3z isolated (excluded, rebuilt); 1x/3x and 2z/4z only as a pair (Gxx / Gzz held); known-bad rebuilt";
        case C_PAIR_IN: return "not isolable within the group: the group degrades (its pair or the symmetry Gxz = Gzx, else held)";
        case C_PAIR_ACROSS: return "one per group rebuilt when known; additive pairs fit no single reading: the tested readings are set aside (group degrades)";
        case C_MIXED: return "the stepped reading is isolated by the remaining parity where it can be, else the affected groups degrade";
        case C_AXIS: return "additive: invisible to parity (a change of the centre force); stuck: set aside by the frozen-reading monitor; known-bad and stuck: the axis force and its gradients held";
        default: return "additive: invisible; stuck: set aside by the frozen-reading monitor; known-bad and stuck: nothing usable, frames rejected, the task coasts on held inputs";
        }
    }
    switch (cls) {
    case C_SINGLE: return "isolated from the pair means with trace / antisymmetric part, excluded and rebuilt (a drift, while its isolation is not yet clear, is set aside frame by frame: DEGRADED)";
    case C_PAIR_IN: return "both readings of a pair: its mean isolated, the pair excluded, its column entry from symmetry/trace; two pairs of one axis: not isolable from the pair means (the good pair looks like the odd one out), so the axis is set aside and the pair whose two readings agree with the column entry symmetry/trace give is kept; known-bad: rebuilt from the other pairs and symmetry/trace, nothing held";
    case C_PAIR_ACROSS: return "different axes: each isolated on its own axis; two diagonal readings (both move the trace) or two feeding one antisymmetric entry: isolated to their pairs only, the column entry then rests on a residual the other fault moves (detected, flagged, error as shown)";
    case C_MIXED: return "the stepped reading isolated where its axis keeps three whole pairs; with one pair broken the compared pairs are set aside and the axis rebuilt from the broken pair's reading and symmetry/trace; the partner of a lost reading is checked by no relation (its fault is in the error)";
    case C_AXIS: return "additive: invisible to the pair means (a change of the centre force); stuck: set aside by the frozen-reading monitor; known-bad and stuck: no reading of the axis left, its centre force held (FORCE_COAST), its column entries from symmetry and trace";
    default: return "additive: invisible; stuck: set aside by the frozen-reading monitor; known-bad and stuck: nothing usable, every centre force and column entry held (frames still used, FORCE_COAST, GRAD_COAST)";
    }
}

static void health_names(uint32_t h, char *buf, size_t n)
{
    static const struct { uint32_t b; const char *s; } t[] = {
        {GG_HEALTH_ACC_REBUILT, "REBUILT"}, {GG_HEALTH_ACC_DEGRADED, "DEGRADED"},
        {GG_HEALTH_GRAD_COAST, "GRAD_COAST"}, {GG_HEALTH_FORCE_COAST, "FORCE_COAST"},
        {GG_HEALTH_FRAME_REJECTED, "REJECTED"}, {GG_HEALTH_COAST, "COAST"}};
    size_t o = 0;
    buf[0] = 0;
    for (size_t i = 0; i < sizeof t / sizeof t[0]; ++i)
        if (h & t[i].b) o += (size_t)snprintf(buf + o, n - o, "%s%s", o ? "+" : "", t[i].s);
    if (o == 0) snprintf(buf, n, "-");
}

static void print_table(void)
{
    printf("| dim | class | fault | cases | detected (max latency, steps) | flagged | degraded modes seen | navigating | frames rejected | max \\|dr\\| at end | max \\|dr\\|/bound | result | geometry |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int dim = 2; dim <= 3; ++dim)
        for (int cls = 0; cls < C_COUNT; ++cls)
            for (int k = 0; k < K_COUNT; ++k) {
                const agg_t *a = &g_agg[dim][cls][k];
                if (a->cases == 0) continue;
                char hn[96];
                health_names(a->seen, hn, sizeof hn);
                const char *res = a->pass == a->cases ? (a->vis == 2 ? "pass (invisible: fault's own error)" : "pass") : "FAIL";
                char lat[16];
                if (a->detected) snprintf(lat, sizeof lat, "%d", a->max_det);
                else snprintf(lat, sizeof lat, "-");
                printf("| %d-D | %s | %s | %d | %d/%d (%s) | %d/%d | %s | %d/%d | %d | %.2Le m | %.2Lf | %s | %s |\n", dim,
                       kClass[cls], kKind[k], a->cases, a->detected, a->cases, lat, a->flagged, a->cases, hn,
                       a->navigating, a->cases, a->rejected, a->max_err, a->max_ratio, res,
                       (k == 0 || cls >= C_AXIS) ? geometry_note(dim, cls) : "");
            }
}

/* Gravity-model mode: when every reading is lost the degraded rebuild
 * takes the gradient from the onboard model (here the truth's own point
 * mass), not the value of the last frame used. After 2 s of NaN on all 18
 * readings the output gradient must match the point-mass gradient at the
 * state's position to 1e-15 s^-2 (central differences of the model over
 * +-10 m: 1e-17), where a held value is off by |dGamma/dt| t (~1e-9 here);
 * in gradiometer mode (no model) it is held. */
static void check_model_prior(void)
{
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t o;
    gg_frame_t fr;
    long double e_mode[2] = {0.0L, 0.0L};
    for (int mode = 0; mode < 2; ++mode) {
        config3(&cfg);
        if (mode == 1) {
            cfg.gravity_mode = GG_GRAVITY_MODEL;
            cfg.model.gm = T_GM;
            cfg.model.a_m = T_RE;
        }
        if (gg_nav3d_init(&nav, &cfg) != GG_OK) abort();
        const int64_t n = 300;
        for (int64_t k = 0; k < n; ++k) {
            frame3(k, &fr);
            if (k >= K0)
                for (int s = 0; s < 6; ++s)
                    for (int j = 0; j < 3; ++j) fr.f[s][j] = NAN;
            if (gg_nav3d_step(&nav, &fr, NULL, &o) != GG_OK) {
                printf("FAIL model prior: step %lld status %d health 0x%08x\n", (long long)k, (int)o.status, o.health);
                g_fail++;
                return;
            }
        }
        long double r[3], v[3], rn[3], G[3][3];
        for (int j = 0; j < 3; ++j) rn[j] = (long double)o.r_e[j] + (long double)o.r_e_lo[j];
        truth3((long double)(n - 1) * DT_US * 1e-6L, r, v);
        (void)r;
        t_point_mass_gamma(rn, G);
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) {
                const long double d = fabsl((long double)o.gamma_e[j][k] - G[j][k]);
                if (d > e_mode[mode]) e_mode[mode] = d;
            }
        if (!(o.health & GG_HEALTH_GRAD_COAST) || !(o.health & GG_HEALTH_FORCE_COAST)) {
            printf("FAIL model prior: mode %d health 0x%08x lacks GRAD_COAST/FORCE_COAST\n", mode, o.health);
            g_fail++;
        }
    }
    printf("3-D every reading NaN 2 s: output gradient off the point mass by %.3Lg s^-2 held (gradiometer "
           "mode), %.3Lg s^-2 from the onboard model (model mode)\n", e_mode[0], e_mode[1]);
    if (!(e_mode[1] < 1e-15L) || !(e_mode[0] > 100.0L * e_mode[1])) {
        printf("FAIL model prior: the model-mode gradient is not the model's\n");
        g_fail++;
    }
}

/* Found by fuzz_nav3d: with fault detection off, one frame whose reading
 * 1x reads 0 differences to Gamma_xx ~ 9.8 s^-2; used, then held through a
 * long outage, such a gradient made the gravity dead reckoning diverge
 * (e^(3.1 t)) until the position left the geodetic range, after which every
 * coast step failed and the task stayed frozen. Now the frame is rejected
 * (ACC_RANGE: |Gamma| above GG_LIM_GAMMA_MAX_S2) and, after the stream jumps
 * 141 s ahead, the task coasts on the last good inputs and uses frames again. */
static void check_absurd_gradient(void)
{
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_nav3d_output_t o;
    gg_frame_t fr;
    config3(&cfg);
    cfg.fdi_parity_f_max = 0.0;
    if (gg_nav3d_init(&nav, &cfg) != GG_OK) abort();
    int ok = 1, used_after = 0;
    uint32_t h_bad = 0U;
    for (int64_t k = 0; k < 2000; ++k) {
        const int64_t kf = (k <= 10) ? k : k + 14100; /* the stream jumps 141 s ahead */
        frame3(kf, &fr);
        if (k == 10) fr.f[0][0] = 0.0, fr.f_lo[0][0] = 0.0;
        const gg_status_t st = gg_nav3d_step(&nav, &fr, NULL, &o);
        if (k == 10) {
            h_bad = o.health;
            if (st != GG_ERR_RANGE || !(o.health & GG_HEALTH_ACC_RANGE) || !(o.health & GG_HEALTH_FRAME_REJECTED)) ok = 0;
        }
        if (!finite_out(3, &o)) ok = 0;
        if (k > 10 && st == GG_OK) used_after++;
    }
    printf("3-D absurd gradient (1x reads 0, detection off): health 0x%08x; then a 141 s jump: %d frames used "
           "after it, state lag at the end %.2f s\n", h_bad, used_after, o.state_lag_s);
    if (!ok || used_after == 0 || o.state_lag_s != 0.0) {
        printf("FAIL absurd gradient: rejected %d, frames used after %d, final lag %g s\n", ok, used_after, o.state_lag_s);
        g_fail++;
    }
}

/* ---------------- strapdown: the GAMMA_ASYM parity with gyro noise ----------------
 * nav3d on a strapdown body (truth3.h: the circle of latitude 3 km up, a body spinning
 * about x and precessing, every reading from rigid-body kinematics), with Gao et al.'s
 * gyro white noise (2.909e-6 rad/s per 10 ms sample) and 5.5e-10 m/s^2 accelerometer
 * noise, pair-mean detection and the frozen-reading monitor off: GAMMA_ASYM alone.
 * The threshold is the one a 3-D scenario derives (scenario3d.hpp), computed here from
 * the noise propagation, not taken from the code:
 *   S_j = sqrt(530)/6 sigma_g/h (+ the accelerometers' sigma_a sqrt((1/d1^2 + 1/d2^2)/8)),
 *   S_3 = sqrt(16 W^2 sigma_g^2 + sigma_a^2 sum 1/(2 d_k^2)), W = GG_LIM_W_MAX_RPS,
 *   asym_max = 7 max(S_x, S_y, S_z, S_3) + 1e-6 s^-2.
 * The firmware also rejects a frame one of whose differenced gradient components exceeds
 * GG_LIM_GAMMA_MAX_S2 = 1e-4 s^-2 (ACC_RANGE, limits.h) - before its parity is formed. A
 * fault on one reading moves the symmetric part as much as the antisymmetric one (reading
 * 0y by beta: M[1][0] by beta/(2a), Gamma_xy and p_z both by beta/(4a)), so with this gyro
 * noise (asym_max 7.8e-3 s^-2, 78 x that range) what GAMMA_ASYM could see of one reading
 * is rejected by the range check first; GAMMA_ASYM is what sees a fault that moves the
 * antisymmetric part alone. Rows (expected outcome from the analysis, checked):
 *   healthy, slow body (spin 0.2, precession 0.05 rad/s) and fast body (1, 0.3 rad/s): no
 *     detection bit on any step (the former fixed 1e-6 would flag nearly every step:
 *     counted from the same residuals); the measured sd of p_x..p_z against S_j;
 *   0y biased by 2 x 4a asym_max: ACC_RANGE on every faulty step (Gamma_xy moved by 2 asym_max);
 *   antisymmetric-only pair, 0y by +beta and 1x by -beta b/a (M[1][0] and M[0][1] by
 *     +-beta/(2a): p_z by beta/(2a), the symmetric part unchanged), beta/(2a) = 2 asym_max:
 *     GAMMA_ASYM on every faulty step; at 0.25 asym_max: below the check, silent;
 *   0y stuck (fast body): detected no later than the step at which |f_0y(t) - f_0y(t_0)| / (4a)
 *     exceeds GG_LIM_GAMMA_MAX_S2 + 2e-5 s^-2 (the truth's gradient and the gyro noise's
 *     share of [w x]^2, below 1e-5, as margin; the truth's own readings);
 *   the firmware's y half-baseline 5% long (fast body): Gamma_yy and the trace move by
 *     (1 - 1/1.05) |(W - Gamma)_yy| >= 0.0476 s^2 = 0.0476 s^-2: ACC_RANGE on every step. */
#define SD_SIG_G 2.909e-6L
#define SD_SIG_A 5.5e-10L
enum { SD_NONE, SD_BIAS, SD_ANTI, SD_STUCK, SD_BASE };
typedef struct {
    const char *name;
    int fast;        /* body: 0 slow, 1 fast */
    int fault;
    long double size; /* SD_BIAS: x 4a asym_max; SD_ANTI: p_z in asym_max; SD_BASE: firmware's b / true b */
    int expect;      /* 0 silent on every step, 1 flagged on every faulty step, 2 by the predicted step */
    uint32_t bit;    /* the detection bit expected */
} sd_case_t;
static const sd_case_t kSd[] = {
    {"healthy, slow body (0.2 rad/s spin, 0.05 precession)", 0, SD_NONE, 0.0L, 0, 0U},
    {"healthy, fast body (1 rad/s spin, 0.3 precession)", 1, SD_NONE, 0.0L, 0, 0U},
    {"0y biased by 2 x 4a asym_max (one reading)", 0, SD_BIAS, 2.0L, 1, GG_HEALTH_ACC_RANGE},
    {"0y +beta, 1x -beta b/a (antisymmetric part only), p_z 2 asym_max", 0, SD_ANTI, 2.0L, 1, GG_HEALTH_GAMMA_ASYM},
    {"0y +beta, 1x -beta b/a, p_z 0.25 asym_max (below the check)", 0, SD_ANTI, 0.25L, 0, 0U},
    {"0y stuck (frozen monitor off), fast body", 1, SD_STUCK, 0.0L, 2, GG_HEALTH_ACC_RANGE},
    {"firmware's b 5% long (wrong baseline), fast body", 1, SD_BASE, 1.05L, 1, GG_HEALTH_ACC_RANGE},
};
#define N_SD ((int)(sizeof kSd / sizeof kSd[0]))
static char g_sd_rows[N_SD][640];

static uint64_t g_sd_rng;
static long double sd_gauss(void)
{
    /* splitmix64 -> two uniforms -> Box-Muller (one of the pair) */
    long double u[2];
    for (int i = 0; i < 2; ++i) {
        uint64_t z = (g_sd_rng += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        z ^= z >> 31;
        u[i] = ((long double)(z >> 11) + 0.5L) / 9007199254740992.0L;
    }
    return sqrtl(-2.0L * logl(u[0])) * cosl(6.283185307179586476925L * u[1]);
}

static void sd_truth(const sd_case_t *c, truth3_t *T)
{
    default_truth(T);
    T->p = c->fast ? 0.3L : 0.05L;
    T->s = c->fast ? 1.0L : 0.2L;
    rx(0.3L, T->c0);
}

static void sd_add(gg_frame_t *fr, int s, int j, long double d)
{
    const long double v = (long double)fr->f[s][j] + (long double)fr->f_lo[s][j] + d;
    fr->f[s][j] = (double)v;
    fr->f_lo[s][j] = (double)(v - (long double)fr->f[s][j]);
}

static void run_strapdown(void)
{
    const long double h = DT_US * 1e-6L;
    long double sig[4];
    truth3_t T0;
    default_truth(&T0);
    const long double *d = T0.hb;
    for (int j = 0; j < 3; ++j) {
        const long double d1 = d[(j + 1) % 3], d2 = d[(j + 2) % 3];
        const long double g = sqrtl(530.0L) / 6.0L * SD_SIG_G / h;
        sig[j] = sqrtl(g * g + SD_SIG_A * SD_SIG_A * (1.0L / (d1 * d1) + 1.0L / (d2 * d2)) / 8.0L);
    }
    sig[3] = sqrtl(16.0L * GG_LIM_W_MAX_RPS * GG_LIM_W_MAX_RPS * SD_SIG_G * SD_SIG_G +
                   SD_SIG_A * SD_SIG_A * (1.0L / (d[0] * d[0]) + 1.0L / (d[1] * d[1]) + 1.0L / (d[2] * d[2])) / 2.0L);
    long double smax = 0.0L;
    for (int j = 0; j < 4; ++j) smax = fmaxl(smax, sig[j]);
    const long double asym = 7.0L * smax + 1e-6L;
    printf("3-D strapdown parity: S_xyz %.4Lg %.4Lg %.4Lg rad/s^2, S_trace %.3Lg s^-2, derived asym_max %.5Lg s^-2 "
           "(smallest detectable bias on 0y: 4a asym_max = %.3Lg m/s^2)\n",
           sig[0], sig[1], sig[2], sig[3], asym, 4.0L * d[0] * asym);
    for (int ci = 0; ci < N_SD; ++ci) {
        const sd_case_t *c = &kSd[ci];
        static gg_nav3d_t nav;
        gg_nav3d_config_t cfg;
        gg_nav3d_output_t o;
        gg_frame_t fr, f_k0, clean_k0;
        truth3_t T;
        sd_truth(c, &T);
        make_config(&T, GG_PLATFORM_STRAPDOWN, 0, DT_US, &cfg);
        cfg.asym_max = (double)asym;
        cfg.fdi_parity_f_max = 0.0;
        cfg.acc_frozen_frames = 0;
        if (c->fault == SD_BASE) cfg.geometry.half_base_m[1] = T.hb[1] * c->size;
        if (gg_nav3d_init(&nav, &cfg) != GG_OK) abort();
        g_sd_rng = 0x5EED0000u + (uint64_t)ci;
        const int64_t k_fault = (c->fault == SD_BASE) ? 0 : K0;
        int64_t first = -1, predicted = -1;
        int flagged_before = 0, flagged_after = 0, old_flagged = 0, n_after = 0, bad = 0;
        int64_t first_any = -1;
        uint32_t seen = 0U;
        long double worst = 0.0L, ss = 0.0L;
        int n_ss = 0;
        memset(&f_k0, 0, sizeof f_k0);
        memset(&clean_k0, 0, sizeof clean_k0);
        for (int64_t k = 0; k < g_n; ++k) {
            gg_frame_t clean;
            make_frame(&T, k, DT_US, &clean);
            fr = clean;
            for (int s = 0; s < 6; ++s)
                for (int j = 0; j < 3; ++j) sd_add(&fr, s, j, SD_SIG_A * sd_gauss());
            for (int j = 0; j < 3; ++j) fr.omega_b[j] = (double)((long double)fr.omega_b[j] + SD_SIG_G * sd_gauss());
            if (k == K0) {
                f_k0 = fr;
                clean_k0 = clean;
            }
            if (k >= K0 && c->fault == SD_BIAS) sd_add(&fr, 0, 1, c->size * 4.0L * T.hb[0] * asym);
            if (k >= K0 && c->fault == SD_ANTI) {
                const long double beta = c->size * 2.0L * T.hb[0] * asym;
                sd_add(&fr, 0, 1, beta);
                sd_add(&fr, 1, 0, -beta * T.hb[1] / T.hb[0]);
            }
            if (k > K0 && c->fault == SD_STUCK) {
                fr.f[0][1] = f_k0.f[0][1];
                fr.f_lo[0][1] = f_k0.f_lo[0][1];
                /* the step by which the analysis says the check must fire */
                const long double df = ((long double)clean.f[0][1] + (long double)clean.f_lo[0][1]) -
                                       ((long double)clean_k0.f[0][1] + (long double)clean_k0.f_lo[0][1]);
                if (predicted < 0 && fabsl(df) / (4.0L * T.hb[0]) > GG_LIM_GAMMA_MAX_S2 + 2e-5L) predicted = k - K0;
            }
            (void)gg_nav3d_step(&nav, &fr, NULL, &o); /* a rejected frame is a detection here */
            seen |= o.health;
            const int f = c->bit ? ((o.health & c->bit) != 0U) : ((o.health & DETECT_BITS) != 0U);
            if (k >= k_fault && (o.health & DETECT_BITS) != 0U && first_any < 0) first_any = k - k_fault;
            long double pm = 0.0L;
            for (int j = 0; j < 4; ++j) pm = fmaxl(pm, fabsl((long double)o.parity[j]));
            if (pm > 1e-6L) old_flagged++;
            if (k < k_fault) flagged_before += f;
            else {
                n_after++;
                flagged_after += f;
                if (f && first < 0) first = k - k_fault;
            }
            if (c->fault == SD_NONE && k >= 3) {
                for (int j = 0; j < 3; ++j) {
                    worst = fmaxl(worst, fabsl((long double)o.parity[j]) / sig[j]);
                    ss += (long double)o.parity[j] * (long double)o.parity[j] / (sig[j] * sig[j]);
                    n_ss++;
                }
            }
        }
        /* healthy and below-the-check rows: no detection bit at all; fault rows: the expected bit */
        int ok = !bad && flagged_before == 0;
        if (c->expect == 0) ok = ok && flagged_after == 0 && first_any < 0;
        else if (c->expect == 1) ok = ok && flagged_after == n_after;
        else ok = ok && first >= 0 && predicted >= 0 && first <= predicted;
        if (c->fault == SD_NONE && (seen & DETECT_BITS) != 0U) ok = 0;
        char extra[160] = "";
        if (c->fault == SD_NONE) {
            /* the measured spread of p_x..p_z against the analysis; the estimate of a sigma from
             * n residuals of this moving-average noise (lag correlations -0.71, 0.25, -0.04) has a
             * relative sd of sqrt(2.15 / (2n)) (3.5% at n = 900); a second-order difference's gain
             * (sqrt(26)/2 / h) would be 34% low */
            const long double ratio = sqrtl(ss / (long double)n_ss);
            if (fabsl(ratio - 1.0L) > 5.0L * sqrtl(2.15L / (2.0L * (long double)n_ss))) ok = 0;
            snprintf(extra, sizeof extra, "measured sd / analytic %.3Lf, max \\|p_j\\| / S_j %.2Lf", ratio, worst);
        } else if (c->fault == SD_STUCK) {
            snprintf(extra, sizeof extra, "first flagged %lld steps after the fault (predicted by %lld)",
                     (long long)first, (long long)predicted);
        } else {
            if (first < 0) snprintf(extra, sizeof extra, "never flagged");
            else snprintf(extra, sizeof extra, "first flagged %lld steps after the fault", (long long)first);
        }
        const char *bn = c->bit == GG_HEALTH_GAMMA_ASYM ? "GAMMA_ASYM" : c->bit == GG_HEALTH_ACC_RANGE ? "ACC_RANGE" : "any";
        const char *ex = c->expect == 0 ? "silent" : c->expect == 1 ? "every faulty step" : "by the predicted step";
        char hn[96];
        health_names(seen, hn, sizeof hn);
        char bits[128];
        snprintf(bits, sizeof bits, "%s%s%s%s%s", (seen & GG_HEALTH_GAMMA_ASYM) ? "GAMMA_ASYM" : "",
                 ((seen & GG_HEALTH_GAMMA_ASYM) && (seen & GG_HEALTH_ACC_RANGE)) ? "+" : "",
                 (seen & GG_HEALTH_ACC_RANGE) ? "ACC_RANGE" : "", (seen & DETECT_BITS) ? "" : "none",
                 (seen & FLAG_BITS) ? "; " : "");
        if (seen & FLAG_BITS) strncat(bits, hn, sizeof bits - strlen(bits) - 1);
        snprintf(g_sd_rows[ci], sizeof g_sd_rows[ci], "| %s | %s, %s | %d/%d | %d/%d | %s | %d/%d | %s | %s |",
                 c->name, bn, ex, flagged_before, (int)k_fault, flagged_after, n_after, bits, old_flagged, (int)g_n,
                 extra, ok ? "pass" : "FAIL");
        printf("%s strapdown %s: %s before the fault %d/%lld, after %d/%d; health seen 0x%08x; former 1e-6: %d/%d; %s\n",
               ok ? "CASE" : "FAIL", c->name, bn, flagged_before, (long long)k_fault, flagged_after, n_after, seen,
               old_flagged, g_n, extra);
        if (!ok) g_fail++;
    }
}

static void print_sd_table(void)
{
    printf("ASYM | strapdown case | expected | flagged before the fault | flagged from the fault | bits seen | "
           "steps the former fixed 1e-6 would flag | measured | result |\n");
    printf("ASYM |---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < N_SD; ++i) printf("ASYM %s\n", g_sd_rows[i]);
}

int main(int argc, char **argv)
{
    int md = 0;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--full") == 0) g_n = 3000;
        else if (strcmp(argv[i], "--md") == 0) md = 1;
    }
    run_matrix(2);
    run_matrix(3);
    check_model_prior();
    check_absurd_gradient();
    run_strapdown();
    int total = 0;
    for (int d = 2; d <= 3; ++d)
        for (int c = 0; c < C_COUNT; ++c)
            for (int k = 0; k < K_COUNT; ++k) total += g_agg[d][c][k].cases;
    if (md) {
        print_table();
        print_sd_table();
    }
    printf("fault matrix: %d cases, %.1f s flights from a fault at %.1f s, %d failed\n", total,
           (g_n - 1) * DT_US * 1e-6, K0 * DT_US * 1e-6, g_fail);
    return g_fail ? 1 : 0;
}
