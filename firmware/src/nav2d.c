/* Navigation task of the 2-D gravity-gradiometer INS (Welker, Pachter &
 * Huffman, sections III-V): validate the frame, difference, obtain G (dead
 * reckoning or onboard model), mechanize, damp the vertical channel with the
 * barometer; one fixed step per frame. */
#include "ggins/nav2d.h"
#include "ggins/navtask.h"

#include <stddef.h>

/* frame axis indices of the paper's (x, z) plane */
#define AX_X 0U
#define AX_Z 2U
#define N_ACC_2D 4
static gg_real_t norm3(const gg_real_t v[3])
{
    return sqrtl((v[0] * v[0]) + (v[1] * v[1]) + (v[2] * v[2]));
}

/* Physical plausibility of a (finite) configuration: GG_NAV2D_LIMITS. A
 * finite but absurd value (|v0| = 1e289 m/s, found by fuzzing) would
 * overflow within a few steps. */
static int in_limits(const gg_nav2d_config_t *cfg)
{
    const gg_real_t rn = norm3(cfg->r0);
    int ok = 1;
    if ((rn < GG_LIM_R_MIN_M) || (rn > GG_LIM_R_MAX_M) || (norm3(cfg->v0) > GG_LIM_V_MAX_MPS) ||
        (norm3(cfg->g0) > GG_LIM_G_MAX_MPS2) || (cfg->geometry.a_m < GG_LIM_BASE_MIN_M) ||
        (cfg->geometry.b_m < GG_LIM_BASE_MIN_M) || (cfg->geometry.a_m > GG_LIM_BASE_MAX_M) ||
        (cfg->geometry.b_m > GG_LIM_BASE_MAX_M) || (cfg->dt_us > GG_LIM_DT_MAX_US) ||
        (cfg->f_max > GG_LIM_F_MAX_MPS2) || (cfg->asym_max > 1.0) ||
        (cfg->fdi_parity_f_max > 1.0) || (cfg->fdi_asym_max > 1.0) ||
        ((cfg->r_ref_m != 0.0L) &&
         ((cfg->r_ref_m < GG_LIM_R_MIN_M) || (cfg->r_ref_m > GG_LIM_R_MAX_M)))) {
        ok = 0;
    }
    return ok;
}

gg_status_t gg_nav2d_init(gg_nav2d_t *nav, const gg_nav2d_config_t *cfg)
{
    gg_diff2d_t diff;
    gg_status_t st;
    size_t j;
    size_t k;
    if ((nav == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    nav->configured = 0;
    nav->started = 0;
    st = gg_diff2d_init(&diff, &cfg->geometry);
    if (st != GG_OK) {
        return st;
    }
    if ((cfg->dt_us <= 0) || (cfg->dt_tol_us < 0) || (cfg->dt_tol_us >= cfg->dt_us) ||
        (gg_finite3(cfg->r0) == 0) || (gg_finite3(cfg->v0) == 0) || (gg_finite3(cfg->g0) == 0) ||
        !GG_ISFINITE(cfg->f_max) || !(cfg->f_max > 0.0) || !GG_ISFINITE(cfg->asym_max) ||
        !(cfg->asym_max > 0.0) || (cfg->gravdr_trapezoid_only < 0) ||
        (cfg->gravdr_trapezoid_only > 1) || (cfg->baro_enable < 0) || (cfg->baro_enable > 1) ||
        ((cfg->gravity_mode != GG_GRAVITY_GRADIOMETER) &&
         (cfg->gravity_mode != GG_GRAVITY_MODEL)) ||
        !GG_ISFINITE(cfg->r_ref_m) || (cfg->r_ref_m < 0.0L)) {
        return GG_ERR_CONFIG;
    }
    if (in_limits(cfg) == 0) {
        return GG_ERR_RANGE;
    }
    nav->gmodel.initialized = 0;
    if (cfg->gravity_mode == GG_GRAVITY_MODEL) {
        st = gg_gmodel_init(&nav->gmodel, &cfg->model);
        if (st != GG_OK) {
            return st;
        }
    }
    nav->vchan.initialized = 0;
    if (cfg->baro_enable != 0) {
        st = gg_vchan_init(&nav->vchan, &cfg->baro);
        if (st != GG_OK) {
            return st;
        }
    }
    {
        const gg_fdi2d_config_t fc = {cfg->geometry.a_m, cfg->geometry.b_m, cfg->fdi_parity_f_max,
                                      cfg->fdi_asym_max};
        st = gg_fdi2d_init(&nav->fdi, &fc);
        if (st != GG_OK) {
            return st;
        }
    }
    nav->cfg = *cfg;
    if (nav->cfg.r_ref_m == 0.0L) {
        nav->cfg.r_ref_m = GG_R_REF_DEFAULT_M;
    }
    nav->diff = diff;
    nav->gravdr.initialized = 0;
    nav->mech.initialized = 0;
    st = gg_task_seq_init(&nav->seq, cfg->dt_us, cfg->dt_tol_us);
    if (st != GG_OK) {
        return st;
    }
    st = gg_task_frozen_init(&nav->frozen, cfg->acc_frozen_frames);
    if (st != GG_OK) {
        return st;
    }
    nav->state_step = 0;
    nav->state_clock_us = 0;
    nav->input_step = 0;
    nav->coast_steps = 0U;
    nav->asym = 0.0L;
    nav->a_c = 0.0L;
    nav->h_ins = 0.0L;
    nav->baro_innov = 0.0L;
    for (j = 0U; j < 3U; ++j) {
        nav->f_c[j] = 0.0L;
        for (k = 0U; k < 3U; ++k) {
            nav->gamma[j][k] = 0.0L;
        }
    }
    nav->configured = 1;
    return GG_OK;
}

/* Health bits of a frame's accelerometers; *known_bad gets the readings
 * (GG_FDI_BIT) that cannot be used as they are. */
static uint32_t check_frame(const gg_nav2d_t *nav, const gg_frame_t *fr, uint32_t *known_bad)
{
    uint32_t h = 0U;
    uint32_t kb = 0U;
    const uint32_t frozen = gg_task_frozen_check(&nav->frozen, fr, N_ACC_2D);
    int32_t i;
    if ((fr->n_acc < N_ACC_2D) || (fr->n_acc > GG_MAX_ACC)) {
        h |= GG_HEALTH_ACC_SENSOR;
    }
    for (i = 0; i < N_ACC_2D; ++i) {
        const double fx = fr->f[i][AX_X];
        const double fz = fr->f[i][AX_Z];
        const double lx = fr->f_lo[i][AX_X];
        const double lz = fr->f_lo[i][AX_Z];
        const uint32_t hx = gg_task_check_reading(fx, lx, nav->cfg.f_max);
        const uint32_t hz = gg_task_check_reading(fz, lz, nav->cfg.f_max);
        if (fr->acc_status[i] != GG_SENSOR_OK) {
            h |= GG_HEALTH_ACC_SENSOR;
            kb |= GG_FDI_BIT(i, 0) | GG_FDI_BIT(i, 1);
        }
        h |= hx | hz;
        kb |= (hx != 0U) ? GG_FDI_BIT(i, 0) : 0U;
        kb |= (hz != 0U) ? GG_FDI_BIT(i, 1) : 0U;
        /* a stuck reading (frozen-reading monitor) not otherwise bad is set aside */
        if (((frozen & GG_TASK_READING_BIT(i, AX_X)) != 0U) && ((kb & GG_FDI_BIT(i, 0)) == 0U)) {
            h |= GG_HEALTH_ACC_FROZEN;
            kb |= GG_FDI_BIT(i, 0);
        }
        if (((frozen & GG_TASK_READING_BIT(i, AX_Z)) != 0U) && ((kb & GG_FDI_BIT(i, 1)) == 0U)) {
            h |= GG_HEALTH_ACC_FROZEN;
            kb |= GG_FDI_BIT(i, 1);
        }
    }
    *known_bad = kb;
    return h;
}

/* Position, velocity and G of the current estimate (G from the onboard
 * model or the dead reckoning). Before the first frame, or if a module
 * fails, the configured initial state is returned with a non-OK status. */
static gg_status_t current_state(const gg_nav2d_t *nav, gg_real_t r[3], gg_real_t v[3],
                                 gg_real_t g[3])
{
    gg_status_t st = GG_ERR_NOT_INIT;
    if (nav->started != 0) {
        st = gg_mech_get(&nav->mech, r, v);
        if (st == GG_OK) {
            st = (nav->cfg.gravity_mode == GG_GRAVITY_MODEL)
                     ? gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r, g, NULL)
                     : gg_gravdr_get(&nav->gravdr, g);
        }
    }
    if (st != GG_OK) {
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            r[j] = nav->cfg.r0[j];
            v[j] = nav->cfg.v0[j];
            g[j] = nav->cfg.g0[j];
        }
    }
    return st;
}

static void fill_output(const gg_nav2d_t *nav, const gg_frame_t *fr, gg_status_t status,
                        uint32_t health, gg_nav_output_t *out)
{
    size_t j;
    size_t k;
    gg_real_t r[3];
    gg_real_t v[3];
    gg_real_t g[3];
    out->utime = fr->utime;
    out->seq = fr->seq;
    out->status = (int32_t)status;
    out->health = health;
    if (current_state(nav, r, v, g) != GG_OK) {
        out->health |= GG_HEALTH_NOT_INIT;
    }
    for (j = 0U; j < 3U; ++j) {
        out->r_i[j] = (double)r[j];
        out->v_i[j] = (double)v[j];
        out->g_i[j] = (double)g[j];
        out->f_i[j] = (double)nav->f_c[j];
        for (k = 0U; k < 3U; ++k) {
            out->gamma_i[j][k] = (double)nav->gamma[j][k];
        }
    }
    out->gamma_asym = (double)nav->asym;
    out->h_ins_m = (double)nav->h_ins;
    out->baro_innov_m = (double)nav->baro_innov;
    out->g_up_corr = (double)nav->a_c;
    out->acc_excluded = nav->fdi.excluded;
}

/* Unit up vector u = r/|r| and |r|. */
static gg_status_t up_vector(const gg_real_t r[3], gg_real_t u[3], gg_real_t *rn)
{
    const gg_real_t rr = (r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]);
    size_t j;
    if (!GG_ISFINITE(rr) || !(rr > 0.0L)) {
        return GG_ERR_RANGE;
    }
    *rn = sqrtl(rr);
    for (j = 0U; j < 3U; ++j) {
        u[j] = r[j] / *rn;
    }
    return GG_OK;
}

/* G at the mechanization's current position, as compensated values; model
 * flags (GG_GMODEL_*) into *mflags. */
static gg_status_t current_g(const gg_nav2d_t *nav, gg_acc_t g[3], uint32_t *mflags)
{
    gg_status_t st;
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        gg_real_t r[3];
        gg_real_t v[3];
        gg_real_t gm[3];
        st = gg_mech_get(&nav->mech, r, v);
        if (st == GG_OK) {
            st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r, gm, mflags);
        }
        if (st == GG_OK) {
            size_t j;
            for (j = 0U; j < 3U; ++j) {
                gg_acc_set(&g[j], gm[j]);
            }
        }
    } else {
        st = gg_gravdr_get_acc(&nav->gravdr, g);
    }
    return st;
}

/* First accepted frame: start the modules at the configured state. */
static gg_status_t start(gg_nav2d_t *nav, const gg_diff2d_output_t *d)
{
    gg_gravdr_config_t gc;
    gg_mech_config_t mc;
    gg_real_t g0[3];
    gg_status_t st = GG_OK;
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        g0[j] = nav->cfg.g0[j];
    }
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, nav->cfg.r0, g0, NULL);
    }
    for (j = 0U; j < 3U; ++j) {
        gc.g0[j] = g0[j];
        for (k = 0U; k < 3U; ++k) {
            gc.gamma0[j][k] = d->gamma[j][k];
        }
        mc.r0[j] = nav->cfg.r0[j];
        mc.v0[j] = nav->cfg.v0[j];
        mc.a0[j] = d->f_c[j] + g0[j];
    }
    gc.trapezoid_only = nav->cfg.gravdr_trapezoid_only;
    gc.g0[1] = 0.0L;
    mc.r0[1] = 0.0L;
    mc.v0[1] = 0.0L;
    mc.a0[1] = 0.0L;
    mc.dt_s = (gg_real_t)nav->cfg.dt_us * 1.0e-6L;
    if (st == GG_OK) {
        st = gg_gravdr_init(&nav->gravdr, &gc);
    }
    if (st == GG_OK) {
        st = gg_mech_init(&nav->mech, &mc);
    }
    return st;
}

/* Expected accelerometer parity residuals (the finite-baseline curvature
 * terms, fdi2d.h) at the current estimate, for a point-mass field with
 * mu = |G| |r|^2 taken from the estimate itself. */
static gg_status_t expected_parity(const gg_nav2d_t *nav, gg_real_t p_exp[2])
{
    gg_real_t r[3];
    gg_real_t v[3];
    gg_real_t g[3];
    gg_status_t st = current_state(nav, r, v, g);
    if (nav->started == 0) {
        st = GG_OK; /* before the first frame: the configured initial state */
    }
    if (st == GG_OK) {
        const gg_real_t rr = (r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]);
        const gg_real_t gg2 = (g[0] * g[0]) + (g[1] * g[1]) + (g[2] * g[2]);
        st = gg_fdi2d_expected_parity(nav->cfg.geometry.a_m, nav->cfg.geometry.b_m,
                                      sqrtl(gg2) * rr, r, p_exp);
    }
    return st;
}

/* Fault-detection outcome -> navigation health bits. */
static uint32_t fdi_health(const gg_fdi2d_output_t *fo)
{
    uint32_t h = 0U;
    if ((fo->flags & GG_FDI_DETECTED) != 0U) {
        h |= GG_HEALTH_ACC_FAULT;
    }
    if ((fo->flags & GG_FDI_REBUILT) != 0U) {
        h |= GG_HEALTH_ACC_REBUILT;
    }
    if ((fo->flags & (GG_FDI_COAST_GXX | GG_FDI_COAST_GZZ | GG_FDI_COAST_OFFD)) != 0U) {
        h |= GG_HEALTH_GRAD_COAST;
    }
    if ((fo->flags & (GG_FDI_DEGRADED | GG_FDI_SUSPECT)) != 0U) {
        h |= GG_HEALTH_ACC_DEGRADED;
    }
    if ((fo->flags & GG_FDI_HOLD_FORCE) != 0U) {
        h |= GG_HEALTH_FORCE_COAST;
    }
    return h;
}

/* Vertical-channel health bits -> navigation health bits. */
static uint32_t baro_health(uint32_t vh)
{
    uint32_t h = 0U;
    if ((vh & GG_VCHAN_INVALID) != 0U) {
        h |= GG_HEALTH_BARO_INVALID;
    }
    if ((vh & GG_VCHAN_STALE) != 0U) {
        h |= GG_HEALTH_BARO_STALE;
    }
    if ((vh & GG_VCHAN_OUTLIER) != 0U) {
        h |= GG_HEALTH_BARO_OUTLIER;
    }
    if ((vh & GG_VCHAN_RECAPTURE) != 0U) {
        h |= GG_HEALTH_BARO_RECAPTURE;
    }
    if ((vh & GG_VCHAN_COAST) != 0U) {
        h |= GG_HEALTH_BARO_COAST;
    }
    return h;
}

/* One step of the barometric loop after the mechanization step; applies
 * its corrections along up. Returns the loop's health bits in *health. */
static gg_status_t baro_step(gg_nav2d_t *nav, const gg_frame_t *fr, const gg_real_t gamma[3][3],
                             uint32_t *health)
{
    gg_real_t r[3];
    gg_real_t v[3];
    gg_real_t u[3];
    gg_real_t rn = 0.0L;
    gg_vchan_output_t vo;
    gg_status_t st = gg_mech_get(&nav->mech, r, v);
    if (st == GG_OK) {
        st = up_vector(r, u, &rn);
    }
    if (st == GG_OK) {
        nav->h_ins = rn - nav->cfg.r_ref_m;
        if (nav->cfg.baro_enable != 0) {
            gg_vchan_sample_t smp;
            smp.alt_m = fr->baro_alt_m;
            smp.utime = fr->baro_utime;
            smp.status = fr->baro_status;
            st = gg_vchan_step(&nav->vchan, fr->utime, nav->h_ins, &smp, &vo);
            if (st == GG_OK) {
                gg_real_t dr[3];
                gg_real_t dv[3];
                gg_real_t dg[3];
                size_t j;
                size_t k;
                for (j = 0U; j < 3U; ++j) {
                    dr[j] = vo.dh_m * u[j];
                    dv[j] = vo.dv_mps * u[j];
                }
                for (j = 0U; j < 3U; ++j) {
                    dg[j] = 0.0L;
                    for (k = 0U; k < 3U; ++k) {
                        dg[j] += gamma[j][k] * dr[k];
                    }
                }
                /* the stored acceleration follows the G correction and the
                 * change of the loop's integral state */
                {
                    gg_real_t da[3];
                    for (j = 0U; j < 3U; ++j) {
                        da[j] = dg[j] - ((vo.a_c - nav->a_c) * u[j]);
                    }
                    st = gg_mech_correct(&nav->mech, dr, dv, da);
                }
                if ((st == GG_OK) && (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER)) {
                    st = gg_gravdr_correct(&nav->gravdr, dg);
                }
                if (st == GG_OK) {
                    nav->a_c = vo.a_c;
                    if (vo.accepted != 0) {
                        nav->baro_innov = vo.innov_m;
                    }
                    *health |= baro_health(vo.health);
                }
            }
        }
    }
    return st;
}

/* Advance the modules by one step (or start them on the first frame).
 * The caller restores the module states when this fails. */
static gg_status_t advance(gg_nav2d_t *nav, const gg_frame_t *fr, const gg_diff2d_output_t *d,
                           const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st;
    uint32_t t0;
    if (nav->started == 0) {
        st = start(nav, d);
    } else {
        gg_real_t dr[3];
        gg_acc_t g[3];
        gg_real_t r[3];
        gg_real_t u[3];
        gg_real_t rn = 0.0L;
        uint32_t t1;
        t0 = gg_task_cycles(hal);
        st = gg_mech_step_position(&nav->mech, dr);
        t1 = gg_task_cycles(hal);
        cyc[GG_MOD_MECH] = t1 - t0;
        if ((st == GG_OK) && (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER)) {
            st = gg_gravdr_step(&nav->gravdr, d->gamma, dr);
        }
        if (st == GG_OK) {
            uint32_t mflags = 0U;
            st = current_g(nav, g, &mflags);
            if ((mflags & GG_GMODEL_OUTSIDE_GRID) != 0U) {
                *health |= GG_HEALTH_MODEL_OUTSIDE;
            }
        }
        t0 = gg_task_cycles(hal);
        cyc[GG_MOD_GRAVDR] = t0 - t1;
        /* specific force less the vertical loop's integral state along up */
        if (st == GG_OK) {
            gg_real_t v[3];
            st = gg_mech_get(&nav->mech, r, v);
        }
        if (st == GG_OK) {
            st = up_vector(r, u, &rn);
        }
        if (st == GG_OK) {
            gg_real_t f_next[3];
            size_t j;
            for (j = 0U; j < 3U; ++j) {
                f_next[j] = d->f_c[j] - (nav->a_c * u[j]);
            }
            st = gg_mech_step_velocity(&nav->mech, f_next, g);
        }
        cyc[GG_MOD_MECH] += gg_task_cycles(hal) - t0;
    }
    t0 = gg_task_cycles(hal);
    if (st == GG_OK) {
        st = baro_step(nav, fr, d->gamma, health);
    }
    cyc[GG_MOD_VCHAN] = gg_task_cycles(hal) - t0;
    return st;
}

/* Bridge `missing` lost frames (a seq gap whose time stamp is consistent):
 * one fixed step each, with the gradient and centre specific force
 * interpolated linearly between the last accepted frame and this one, and no
 * barometer. Degraded, flagged GG_HEALTH_SEQ_GAP by the caller. */
static gg_status_t bridge(gg_nav2d_t *nav, const gg_frame_t *fr, const gg_diff2d_output_t *d,
                          int64_t missing, const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT],
                          uint32_t *health)
{
    gg_status_t st = GG_OK;
    int64_t i;
    for (i = 1; (i <= missing) && (i <= GG_NAV2D_MAX_BRIDGE) && (st == GG_OK); ++i) {
        const gg_real_t w = (gg_real_t)i / ((gg_real_t)missing + 1.0L);
        gg_diff2d_output_t di;
        gg_frame_t fi = *fr;
        size_t j;
        size_t k;
        for (j = 0U; j < 3U; ++j) {
            di.f_c[j] = nav->f_c[j] + (w * (d->f_c[j] - nav->f_c[j]));
            for (k = 0U; k < 3U; ++k) {
                di.gamma[j][k] = nav->gamma[j][k] + (w * (d->gamma[j][k] - nav->gamma[j][k]));
            }
        }
        di.asym = d->asym;
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        fi.baro_status = GG_SENSOR_ABSENT;
        st = advance(nav, &fi, &di, hal, cyc, health);
    }
    return st;
}

/* Coast n steps on the last usable gradient and centre specific force
 * (an outage longer than the bridge), no barometer. Degraded, flagged
 * GG_HEALTH_COAST by the caller. */
static gg_status_t coast(gg_nav2d_t *nav, const gg_frame_t *fr, int64_t n, const gg_hal_t *hal,
                         uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st = GG_OK;
    gg_diff2d_output_t dh;
    gg_frame_t fi = *fr;
    int64_t i;
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        dh.f_c[j] = nav->f_c[j];
        for (k = 0U; k < 3U; ++k) {
            dh.gamma[j][k] = nav->gamma[j][k];
        }
    }
    dh.asym = nav->asym;
    fi.baro_status = GG_SENSOR_ABSENT;
    for (i = 1; (i <= n) && (i <= GG_TASK_CATCHUP_STEPS) && (st == GG_OK); ++i) {
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        st = advance(nav, &fi, &dh, hal, cyc, health);
    }
    return st;
}

gg_status_t gg_nav2d_step(gg_nav2d_t *nav, const gg_frame_t *frame, const gg_hal_t *hal,
                          gg_nav_output_t *out)
{
    uint32_t cyc[GG_MOD_COUNT] = {0U, 0U, 0U, 0U, 0U};
    const uint32_t t_start = gg_task_cycles(hal);
    uint32_t health;
    gg_status_t st = GG_OK;
    gg_status_t st_read = GG_OK;
    gg_diff2d_output_t d = {0};
    gg_fdi2d_output_t fo = {0};
    gg_fdi2d_t fdi_saved;
    uint32_t known_bad = 0U;
    gg_real_t p_exp[2] = {0.0L, 0.0L};
    int64_t fstep = -1;
    int used = 0;
    if ((nav == NULL) || (frame == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (nav->configured == 0) {
        const gg_nav_output_t empty = {0};
        *out = empty;
        out->utime = frame->utime;
        out->seq = frame->seq;
        out->status = (int32_t)GG_ERR_NOT_INIT;
        out->health = GG_HEALTH_NOT_INIT | GG_HEALTH_FRAME_REJECTED;
        return GG_ERR_NOT_INIT;
    }
    fdi_saved = nav->fdi;
    health = check_frame(nav, frame, &known_bad);
    health |= gg_task_seq_update(&nav->seq, frame, &fstep);
    if (fstep < 0) {
        st_read = GG_ERR_SEQUENCE;
    } else if ((frame->n_acc < N_ACC_2D) || (frame->n_acc > GG_MAX_ACC)) {
        st_read = GG_ERR_SENSOR;
    } else {
        gg_diff2d_input_t in;
        uint32_t t0;
        size_t i;
        for (i = 0U; i < 4U; ++i) {
            const uint32_t bx = GG_FDI_BIT(i, 0);
            const uint32_t bz = GG_FDI_BIT(i, 1);
            /* unusable readings enter as 0: fdi2d rebuilds them */
            in.f[i][0] = ((known_bad & bx) != 0U) ? 0.0 : frame->f[i][AX_X];
            in.f[i][1] = ((known_bad & bz) != 0U) ? 0.0 : frame->f[i][AX_Z];
            in.f_lo[i][0] = ((known_bad & bx) != 0U) ? 0.0 : frame->f_lo[i][AX_X];
            in.f_lo[i][1] = ((known_bad & bz) != 0U) ? 0.0 : frame->f_lo[i][AX_Z];
        }
        t0 = gg_task_cycles(hal);
        st_read = expected_parity(nav, p_exp);
        if (st_read == GG_OK) {
            st_read = gg_fdi2d_step(&nav->fdi, known_bad, p_exp, &in, &fo);
        }
        if (st_read == GG_OK) {
            st_read = gg_diff2d_step(&nav->diff, &in, &d);
        }
        cyc[GG_MOD_DIFF] = gg_task_cycles(hal) - t0;
        health |= fdi_health(&fo);
    }
    st = st_read;
    if (fstep >= 0) {
        /* module states saved so a failure part-way leaves nothing changed */
        const gg_gravdr_t gravdr_saved = nav->gravdr;
        const gg_mech_t mech_saved = nav->mech;
        const gg_vchan_t vchan_saved = nav->vchan;
        const gg_real_t a_c_saved = nav->a_c;
        const gg_real_t h_saved = nav->h_ins;
        const gg_real_t innov_saved = nav->baro_innov;
        const int64_t step_saved = nav->state_step;
        const int64_t clock_saved = nav->state_clock_us;
        gg_task_plan_t plan = {0, 0, 0};
        gg_status_t st_nav = GG_OK;
        uint32_t step_health = 0U;
        gg_frame_t ft;
        gg_task_seq_map_frame(&nav->seq, frame, &ft);
        if (nav->started == 0) {
            if (st_read == GG_OK) {
                plan.use = 1;
            }
        } else {
            gg_task_plan(fstep, nav->state_step, (st_read == GG_OK) ? 1 : 0, GG_NAV2D_MAX_BRIDGE,
                         &plan);
        }
        if (plan.coast > 0) {
            st_nav = coast(nav, &ft, plan.coast, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                nav->state_step += plan.coast;
                nav->state_clock_us += plan.coast * nav->cfg.dt_us;
                step_health |= GG_HEALTH_COAST;
            }
        }
        if ((st_nav == GG_OK) && (plan.use != 0)) {
            st_nav = bridge(nav, &ft, &d, plan.bridge, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                st_nav = advance(nav, &ft, &d, hal, cyc, &step_health);
            }
        }
        if (st_nav != GG_OK) {
            nav->gravdr = gravdr_saved;
            nav->mech = mech_saved;
            nav->vchan = vchan_saved;
            nav->a_c = a_c_saved;
            nav->h_ins = h_saved;
            nav->baro_innov = innov_saved;
            nav->state_step = step_saved;
            nav->state_clock_us = clock_saved;
            st = st_nav;
        } else {
            health |= step_health;
            if (plan.coast > 0) {
                nav->coast_steps += (uint32_t)plan.coast;
            }
            if (plan.use != 0) {
                used = 1;
                nav->state_step = fstep;
                nav->state_clock_us = ft.utime;
            } else if (st == GG_OK) {
                st = GG_ERR_SEQUENCE; /* still catching up an outage: not used yet */
            } else {
                /* the readings' own error */
            }
        }
    }
    if (used != 0) {
        size_t j;
        size_t k;
        for (j = 0U; j < 3U; ++j) {
            nav->f_c[j] = d.f_c[j];
            for (k = 0U; k < 3U; ++k) {
                nav->gamma[j][k] = d.gamma[j][k];
            }
        }
        nav->asym = d.asym;
        if ((d.asym > (gg_real_t)nav->cfg.asym_max) || (d.asym < -(gg_real_t)nav->cfg.asym_max)) {
            health |= GG_HEALTH_GAMMA_ASYM;
        }
        nav->started = 1;
        nav->input_step = fstep;
        gg_task_frozen_commit(&nav->frozen, frame, N_ACC_2D);
    } else {
        nav->fdi = fdi_saved;
        health |= GG_HEALTH_FRAME_REJECTED;
    }
    fill_output(nav, frame, st, health, out);
    out->parity_f[0] = (double)fo.p_x;
    out->parity_f[1] = (double)fo.p_z;
    out->acc_rebuilt = fo.rebuilt;
    out->resync_count = nav->seq.resyncs;
    out->coast_steps = nav->coast_steps;
    gg_task_outage(&nav->seq, nav->started, nav->state_step, nav->input_step, nav->cfg.dt_us,
                   &out->outage_s, &out->state_lag_s);
    out->health |= gg_task_close_cycles(hal, nav->cfg.dt_us, t_start, cyc, out->cycles);
    return st;
}

gg_status_t gg_nav2d_task_cycle(gg_nav2d_t *nav, const gg_hal_t *hal)
{
    gg_frame_t frame;
    gg_nav_output_t out;
    gg_status_t st;
    gg_status_t st_step;
    if ((nav == NULL) || (hal == NULL) || (hal->read_frame == NULL) ||
        (hal->write_output == NULL)) {
        return GG_ERR_NULL;
    }
    st = hal->read_frame(hal->ctx, &frame);
    if (st != GG_OK) {
        return st;
    }
    st_step = gg_nav2d_step(nav, &frame, hal, &out);
    st = hal->write_output(hal->ctx, &out);
    if (st != GG_OK) {
        return GG_ERR_IO;
    }
    return st_step;
}
