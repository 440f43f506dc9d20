/* libFuzzer harness: the 3-D navigation step from arbitrary configurations
 * and frames (gg_nav3d_init, gg_nav3d_step).
 *
 * Input layout (fuzz_bytes.h cursor; missing bytes read as 0):
 *   byte 0    bit 0 strapdown, bit 1 gravity-model mode, bit 2 barometer,
 *             bit 3 fault detection on (GG_FDI3D_FLOOR_MPS2), bits 4-7: number
 *             of configuration changes that follow
 *   byte 1    aiding sources: bit 0 the gradient-map UKF (aid_mmukf.h), bit 1
 *             the cold-atom particle filter (aid_pf.h), bit 2 the filter's
 *             velocity feedback, bit 3 its INS process model, bit 4 the UKF's
 *             NIS gate, bit 5 the frozen-reading monitor (4 frames: the
 *             reference readings at rest are constant, so every reading
 *             is set aside from the 4th frame on); both read one map storage of a single tile (the
 *             reference field at rest: the point-mass gradient, constant over
 *             the tile; a tensor tile and a Gamma_zz-only one, each aid served
 *             its kind), handed to the task through the HAL
 *   changes   field index (1 byte) + value (fz_value): one of the reference
 *             configuration's numbers replaced (raw bits or a small change),
 *             the aids' numbers among them
 *   frames    up to 64 ops of 1 byte each and their operands: 0 the
 *             reference frame of the next step; 1 that frame with readings,
 *             statuses, gyro or barometer changed; 2 raw bytes over the whole
 *             gg_frame_t; 3 seq and utime replaced; 4 a lost frame (skip);
 *             5 repeat: a count n (1 byte, 1..256) and one op 0-4 with its
 *             operands, applied to each of the next n frames (the same
 *             change each time: a run of rejected or lost frames, a
 *             stuck reading, in a few bytes); 6 a lasting offset from here
 *             on: seq (int16) and utime (int32, us) added to every later
 *             frame (a clock step, a restarted or jumping counter)
 *             At most MAX_STEPS frames handed to the task and MAX_LOST lost
 *             ones (op 4, which cost nothing): every input's work is bounded
 *             and small, while a gap beyond the bridge (GG_NAV3D_MAX_BRIDGE
 *             = 100 lost frames, or a seq/utime jump of op 3 or 6), the
 *             coasting through it, the re-synchronisation
 *             (GG_TASK_RESYNC_FRAMES = 3 consistent frames) and the
 *             aids' epochs (a map-UKF epoch every 6 steps, a cold-atom
 *             shot every 10) stay reachable within those few steps
 *             (docs/robustness.md, "Bounds").
 * The reference is a platform at rest relative to inertial space at the
 * equator (point-mass field, body = ECEF axes), so unchanged frames are
 * accepted and mutations start from plausible input; with the particle filter
 * on, every 10th reference frame carries a cold-atom shot (a fringe pair).
 * Invariants (abort = a finding): no crash or sanitizer report; a refused
 * configuration makes every step GG_ERR_NOT_INIT; a rejected frame leaves the
 * navigation state byte for byte as it was (apart from the stream follower,
 * during an outage longer than the bridge the coasting, and with the particle
 * filter on its time-sliced work and the correction it may feed back at that
 * step, flagged pf_corrected), and is flagged
 * FRAME_REJECTED; no NaN/Inf in any output or in the state's position,
 * velocity, G, gradient and specific force; no freeze: with the reference
 * configuration, TAIL_FRAMES consistent reference frames after the fuzzed
 * ones end with a frame used (or the outage being coasted through); the
 * particle filter switched off, its state never changes. With FUZZ_TRACE set
 * in the environment, the tail frames' status, health and the task's bias
 * estimates are printed (to read a finding). */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ggins/gmap.h"
#include "ggins/hal.h"
#include "ggins/nav3d.h"
#include "ggins/navtask.h"
#include "fuzz_bytes.h"
#include "fuzz_nav3d_checks.h"

#define GM 3.986004418e14
#define R0 6378137.0
#define DT_US 10000
#define MAX_OPS 64
#define MAX_STEPS 10 /* fuzzed frames stepped per input */
#define MAX_LOST 160 /* lost frames per input: more than the bridge */
#define TAIL_FRAMES (2 * GG_TASK_RESYNC_FRAMES + 2)
#define SHOT_EVERY 10 /* a cold-atom shot every 0.1 s at 100 Hz */



static void ref_aids(gg_nav3d_config_t *c, uint8_t aid)
{
    gg_aid_mm_config_t *m = &c->aid_mm;
    gg_aid_pf_config_t *a = &c->aid_pf;
    m->enable = (aid & 1u) ? 1 : 0;
    m->update_steps = 6; /* the shortest epoch of 2 passes (2 * max_passes + 2) */
    m->max_passes = 2;
    m->sigma_meas_s2 = 1e-11;
    m->sigma_db_s2 = 1e-12;
    m->offdiag_ratio = 0.70710678118654752;
    m->sig0_pos_m = 50.0;
    m->sig0_vel_mps = 0.05;
    m->sig0_att_rad = 1e-6;
    m->sig0_g_mps2 = 1e-7;
    m->q_vel_mps_rts = 1e-6;
    m->q_att_rad_rts = 1e-9;
    m->q_g_mps2_rts = 1e-9;
    m->gate_nis = (aid & 16u) ? 30.0 : 0.0;
    m->average_steps = 4;
    m->sigma_gyro_rps = 1e-8;
    /* the bias states (18 or 15 error states; the task subtracts the estimates) */
    m->bias_states = (aid & 32u) ? 1 : 0;
    m->sig0_gyro_bias_rps = 1e-7;
    m->sig0_acc_bias_mps2 = 1e-4;
    m->q_gyro_bias_rps_rts = 1e-10;
    m->q_acc_bias_mps2_rts = 1e-8;
    a->enable = (aid & 2u) ? 1 : 0;
    a->chunk = 8;
    a->end_chunk = 16;
    a->feedback = (aid & 4u) ? GG_AID_PF_FB_POS_VEL : GG_AID_PF_FB_POS;
    a->pf.n = 16;
    a->pf.seed = 7u;
    a->pf.k_eff = 4.0 * 3.14159265358979323846 / 852.347e-9;
    a->pf.T = 0.16;
    a->pf.dz = 1.0;
    a->pf.contrast = 0.5;
    a->pf.c0 = 0.5;
    a->pf.c1 = 0.5;
    a->pf.sigma = 0.005;
    a->pf.sigma0_pos = 100.0;
    a->pf.sigma0_vel = 0.1;
    a->pf.q_pos = 1.0;
    a->pf.q_vel = 0.01;
    a->pf.model = (aid & 8u) ? GG_PF_MODEL_INS : GG_PF_MODEL_RW;
    a->pf.sigma0_acc = 1e-4;
    a->pf.q_acc = 1e-6;
    a->pf.dt = SHOT_EVERY * DT_US * 1e-6;
    a->pf.gain = 1.0;
    a->pf.ess_frac = 0.5;
}

static void ref_config(gg_nav3d_config_t *c, uint8_t sel, uint8_t aid)
{
    memset(c, 0, sizeof *c);
    ref_aids(c, aid);
    for (int j = 0; j < 3; ++j) c->geometry.half_base_m[j] = 0.5L;
    c->platform = (sel & 1u) ? GG_PLATFORM_STRAPDOWN : GG_PLATFORM_STABILIZED;
    c->dt_us = DT_US;
    c->dt_tol_us = 100;
    c->r0_e[0] = R0;
    c->g0_e[0] = -GM / (R0 * R0);
    c->q0_b_e[0] = 1.0L;
    c->omega_ie = -1.0L; /* non-rotating: the reference frames are exact at rest */
    c->f_max = 100.0;
    c->asym_max = 1e-6;
    c->fdi_parity_f_max = (sel & 8u) ? GG_FDI3D_FLOOR_MPS2 : 0.0;
    c->gravity_mode = (sel & 2u) ? GG_GRAVITY_MODEL : GG_GRAVITY_GRADIOMETER;
    if (sel & 2u) {
        c->model.gm = (gg_real_t)GM;
        c->model.a_m = (gg_real_t)R0;
    }
    c->baro_enable = (sel & 4u) ? 1 : 0;
    c->baro.poles[0] = 0.01L;
    c->baro.poles[1] = 0.012L;
    c->baro.poles[2] = 0.014L;
    c->baro.omega_s2 = 9.8L / 6.4e6L;
    c->baro.period_us = 10 * DT_US;
    c->baro.max_age_us = 10 * DT_US;
    c->baro.coast_us = 100 * DT_US;
    c->baro.alt_min_m = -1000.0;
    c->baro.alt_max_m = 30000.0;
    c->baro.gate_m = 50.0;
    c->baro.max_rejects = 10;
    c->acc_frozen_frames = (aid & 32u) ? 4 : 0;
}

/* pointers to the configuration's numbers the fuzzer may change */
static void change_config(gg_nav3d_config_t *c, fz_cur_t *cur)
{
    const unsigned idx = fz_u8(cur) % 36u;
    gg_real_t *lr[] = {&c->geometry.half_base_m[0], &c->geometry.half_base_m[1],
                       &c->geometry.half_base_m[2], &c->r0_e[0], &c->r0_e[1], &c->r0_e[2],
                       &c->v0_e[0], &c->v0_e[1], &c->v0_e[2], &c->g0_e[0], &c->g0_e[1],
                       &c->g0_e[2], &c->q0_b_e[0], &c->q0_b_e[1], &c->q0_b_e[2],
                       &c->q0_b_e[3], &c->omega_ie, &c->baro.poles[0], &c->baro.omega_s2};
    if (idx < 19u) {
        *lr[idx] = (gg_real_t)fz_value(cur, (double)*lr[idx]);
    } else if (idx == 19u) {
        c->f_max = fz_value(cur, c->f_max);
    } else if (idx == 20u) {
        c->asym_max = fz_value(cur, c->asym_max);
    } else if (idx == 21u) {
        c->fdi_parity_f_max = fz_value(cur, c->fdi_parity_f_max);
    } else if (idx == 22u) {
        c->dt_us = fz_i64(cur);
    } else if (idx == 23u) {
        c->dt_tol_us = fz_i64(cur);
    } else {
        /* the aids' numbers */
        double *ad[] = {&c->aid_mm.sigma_meas_s2, &c->aid_mm.sig0_pos_m, &c->aid_mm.sig0_att_rad,
                        &c->aid_mm.q_g_mps2_rts, &c->aid_mm.gate_nis, &c->aid_mm.lambda,
                        &c->aid_pf.pf.sigma, &c->aid_pf.pf.sigma0_pos, &c->aid_pf.pf.q_pos,
                        &c->aid_pf.pf.dz};
        const unsigned a = idx - 24u;
        if (a < 10u) {
            *ad[a] = fz_value(cur, *ad[a]);
        } else if (a == 10u) {
            /* small epochs (below the smallest accepted, 2 * passes + 2, too)
             * or one beyond the limit: every branch of the check, bounded work */
            const int v = (int)(int8_t)fz_u8(cur);
            c->aid_mm.update_steps = (v > 24) ? (GG_LIM_AID_MM_UPDATE_STEPS_MAX + 1) : (int32_t)v;
        } else {
            /* few particles (the same code as thousands) or one too many */
            const int v = (int)(int8_t)fz_u8(cur);
            c->aid_pf.pf.n = (v > 24) ? (GG_PF_MAX + 1) : v;
        }
    }
}

/* the frame of step k of the reference flight (at rest, body = ECEF, point mass) */
static void ref_frame(int64_t k, gg_frame_t *f)
{
    static const double off[6][3] = {{0.5, 0, 0}, {0, 0.5, 0}, {0, 0, 0.5},
                                     {-0.5, 0, 0}, {0, -0.5, 0}, {0, 0, -0.5}};
    memset(f, 0, sizeof *f);
    f->utime = k * DT_US;
    f->seq = k;
    f->n_acc = 6;
    for (int s = 0; s < 6; ++s) {
        long double p[3] = {R0 + off[s][0], off[s][1], off[s][2]};
        const long double rr = sqrtl(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int j = 0; j < 3; ++j) {
            const long double fv = (long double)GM * p[j] / (rr * rr * rr); /* f = -G */
            f->f[s][j] = (double)fv;
            f->f_lo[s][j] = (double)(fv - (long double)f->f[s][j]);
        }
        f->acc_status[s] = GG_SENSOR_OK;
    }
    f->gyro_status = GG_SENSOR_OK;
    f->baro_alt_m = 0.0;
    f->baro_utime = f->utime;
    f->baro_status = (k % 10 == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
    f->ca_status = GG_SENSOR_ABSENT;
    if (k % SHOT_EVERY == 0) {
        /* a pair on the ellipse of the reference field's Gamma_zz (phase 0.3 rad) */
        fz_fringe_pair(2.0 * GM / (R0 * R0 * R0), f->ca_s);
        f->ca_utime = f->utime;
        f->ca_status = GG_SENSOR_OK;
    }
}

/* the map storage: a tile of each kind of the reference field at rest around
 * (0, 0), the point-mass gradient in NED axes, constant over the tile: the
 * whole tensor (the map UKF's kind) and Gamma_DD alone (GG_GMAP_GZZ_ONLY, the
 * cold-atom aid's kind) */
static const gg_hal_t *map_hal(void)
{
    return fz_map_hal(8, -3.5 * 2e-4, -3.5 * 2e-4, 2e-4, 2e-4, 1000.0, GM / (R0 * R0 * R0));
}

static void change_frame(gg_frame_t *f, fz_cur_t *cur)
{
    const unsigned n = 1u + (fz_u8(cur) & 7u);
    for (unsigned i = 0; i < n; ++i) {
        const unsigned idx = fz_u8(cur) % 49u;
        if (idx < 18u) {
            f->f[idx / 3u][idx % 3u] = fz_value(cur, f->f[idx / 3u][idx % 3u]);
        } else if (idx < 36u) {
            const unsigned j = idx - 18u;
            f->f_lo[j / 3u][j % 3u] = fz_value(cur, f->f_lo[j / 3u][j % 3u]);
        } else if (idx < 42u) {
            f->acc_status[idx - 36u] = (int32_t)(int8_t)fz_u8(cur);
        } else if (idx < 45u) {
            f->omega_b[idx - 42u] = fz_value(cur, 1e-3);
        } else if (idx < 46u) {
            f->gyro_status = (int32_t)(int8_t)fz_u8(cur);
            f->n_acc = (int32_t)(int8_t)fz_u8(cur);
            f->baro_alt_m = fz_value(cur, f->baro_alt_m);
            f->baro_status = (int32_t)(int8_t)fz_u8(cur);
        } else if (idx < 48u) {
            f->ca_s[idx - 46u] = fz_value(cur, f->ca_s[idx - 46u]);
        } else {
            f->ca_status = (int32_t)(int8_t)fz_u8(cur);
            f->ca_utime = f->utime + (int64_t)(int16_t)(fz_u8(cur) | (fz_u8(cur) << 8));
        }
    }
}

/* The task state without the particle filter's own (GG_PF_MAX particles, most
 * of gg_nav3d_t): a rejected frame may advance the filter's time-sliced work;
 * when the filter is off its state is checked once per input instead. */
#define PF_LO offsetof(gg_nav3d_t, aid_pf)
#define PF_HI (offsetof(gg_nav3d_t, aid_pf) + sizeof(gg_aid_pf_t))

static void save_state(gg_nav3d_t *dst, const gg_nav3d_t *src)
{
    memcpy(dst, src, PF_LO);
    memcpy((uint8_t *)dst + PF_HI, (const uint8_t *)src + PF_HI, sizeof *src - PF_HI);
}

static int same_state(const gg_nav3d_t *a, const gg_nav3d_t *b)
{
    return memcmp(a, b, PF_LO) == 0 &&
           memcmp((const uint8_t *)a + PF_HI, (const uint8_t *)b + PF_HI, sizeof *a - PF_HI) == 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gg_nav3d_t nav, saved, cmp;
    static gg_aid_pf_t pf_after_init;
    gg_nav3d_config_t cfg;
    fz_cur_t cur = {data, size, 0};
    const uint8_t sel = fz_u8(&cur);
    const uint8_t aid = fz_u8(&cur);
    const gg_hal_t *hal = map_hal();
    ref_config(&cfg, sel, aid);
    const unsigned nchg = sel >> 4;
    for (unsigned i = 0; i < nchg; ++i) change_config(&cfg, &cur);
    const gg_status_t st_init = gg_nav3d_init(&nav, &cfg);
    memcpy(&pf_after_init, &nav.aid_pf, sizeof pf_after_init);
    int64_t k = 0;
    int64_t seq_off = 0;
    int64_t ut_off = 0;
    int steps = 0;
    int lost = 0;
    for (int op_i = 0; op_i < MAX_OPS && fz_left(&cur) && steps < MAX_STEPS; ++op_i) {
        uint8_t op = fz_u8(&cur) % 7u;
        int rep = 1;
        if (op == 6u) {
            seq_off += (int16_t)(fz_u8(&cur) | (fz_u8(&cur) << 8));
            ut_off += (int32_t)((uint32_t)fz_u8(&cur) | ((uint32_t)fz_u8(&cur) << 8) |
                                ((uint32_t)fz_u8(&cur) << 16) | ((uint32_t)fz_u8(&cur) << 24));
            continue;
        }
        if (op == 5u) {
            rep = 1 + (int)fz_u8(&cur);
            op = fz_u8(&cur) % 5u;
        }
        const size_t operands = cur.off;
        for (int r = 0; r < rep && steps < MAX_STEPS && lost < MAX_LOST; ++r) {
            gg_frame_t f;
            gg_nav3d_output_t out;
            cur.off = operands; /* a repeated op reads the same operands */
            ref_frame(k, &f);
            f.seq += seq_off;
            f.utime += ut_off;
            f.baro_utime += ut_off;
            if (op == 1u) {
                change_frame(&f, &cur);
            } else if (op == 2u) {
                for (size_t b = 0; b < sizeof f; ++b) ((uint8_t *)&f)[b] = fz_u8(&cur);
            } else if (op == 3u) {
                f.seq = fz_i64(&cur);
                f.utime = fz_i64(&cur);
            } else if (op == 4u) {
                ++k;
                ++lost;
                continue;
            }
            ++k;
            ++steps;
            save_state(&saved, &nav);
            const gg_status_t st = gg_nav3d_step(&nav, &f, hal, &out);
            if (st_init != GG_OK) {
                if (st != GG_ERR_NOT_INIT) FAIL("refused configuration (status %d), but a step ran (status %d)", (int)st_init, (int)st);
                continue;
            }
            if (st != GG_OK) {
                save_state(&cmp, &nav);
                memcpy(&cmp.seq, &saved.seq, sizeof saved.seq);
                if (nav.aid_pf.initialized != 0) {
                    /* the particle filter's time-sliced work goes on (a shot of a rejected
                     * frame is taken and dropped as stale) */
                    cmp.pf_last_utime = saved.pf_last_utime;
                    cmp.pf_have_shot = saved.pf_have_shot;
                }
                if (!(out.health & GG_HEALTH_COAST) && (out.pf_corrected == 0) &&
                    !same_state(&saved, &cmp))
                    FAIL("3-D frame seq %lld rejected (status %d) but the state changed", (long long)f.seq, (int)st);
                if (!(out.health & GG_HEALTH_FRAME_REJECTED)) FAIL("rejected 3-D frame not flagged FRAME_REJECTED");
            }
            check_state(&nav);
            check_output(&out);
        }
    }
    /* the particle filter switched off: its state never moves */
    if ((st_init == GG_OK) && (nav.aid_pf.initialized == 0) &&
        (memcmp(&pf_after_init, &nav.aid_pf, sizeof pf_after_init) != 0))
        FAIL("the particle filter is off, but its state changed");
    /* No freeze: whatever came before, a reference configuration that then
     * gets TAIL_FRAMES consistent reference frames uses the last one (or is
     * still coasting through an outage it re-synchronised to). */
    if ((st_init == GG_OK) && (nchg == 0U)) {
        if ((k + seq_off < 0) || ((k * DT_US) + ut_off < 0)) {
            seq_off = 0;
            ut_off = 0;
        }
        gg_nav3d_output_t out;
        for (int r = 0; r < TAIL_FRAMES; ++r, ++k) {
            gg_frame_t f;
            ref_frame(k, &f);
            f.seq += seq_off;
            f.utime += ut_off;
            f.baro_utime += ut_off;
            (void)gg_nav3d_step(&nav, &f, hal, &out);
            if (getenv("FUZZ_TRACE") != NULL)
                fprintf(stderr, "tail %d: status %d health 0x%x bias_w %g %g %g bias_f %g %g %g\n", r, (int)out.status,
                        (unsigned)out.health, nav.bias_w[0], nav.bias_w[1], nav.bias_w[2], nav.bias_f[0], nav.bias_f[1],
                        nav.bias_f[2]);
            check_state(&nav);
            check_output(&out);
        }
        if ((out.health & GG_HEALTH_FRAME_REJECTED) && !(out.health & GG_HEALTH_COAST))
            FAIL("the task stays frozen: %d consistent reference frames, the last rejected (status %d, health 0x%x)",
                 TAIL_FRAMES, (int)out.status, (unsigned)out.health);
    }
    return 0;
}
