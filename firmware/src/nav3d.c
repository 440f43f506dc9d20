/* Navigation task of the 3-D gravity-gradiometer INS on a rotating WGS-84
 * Earth; frames, equations and the reasons for them in nav3d.h. */
#include "ggins/nav3d.h"
#include "ggins/navtask.h"

#include <stddef.h>

#include "ggins/geo.h"
#include "ggins/ggmath.h"
#include "ggins/quat.h"
#include "nav3d_int.h"

#define N_ACC_3D 6
#if (GG_NAV3D_MAX_BRIDGE + GG_TASK_CATCHUP_STEPS + 1) > GG_LIM_AID_MM_STEPS_MAX
#error "one step may advance the state further than the map aid propagates (limits.h)"
#endif
/* a residual below double resolution can never exceed ulp(f_max)/2 (nav2d.c) */
/* |q0| must be 1 to this tolerance */
#define Q_NORM_TOL 1.0e-6L
/* half step of the onboard model's central differences (n3_model_prior), m */
#define GG_NAV3D_MODEL_DX_M 10.0L

/* ---------------------------------------------------------------- config */

static int cfg_finite(const gg_nav3d_config_t *cfg)
{
    int ok = 1;
    size_t j;
    if ((gg_finite3(cfg->r0_e) == 0) || (gg_finite3(cfg->v0_e) == 0) ||
        (gg_finite3(cfg->g0_e) == 0) || !GG_ISFINITE(cfg->omega_ie) || !GG_ISFINITE(cfg->f_max) ||
        !GG_ISFINITE(cfg->asym_max)) {
        ok = 0;
    }
    for (j = 0U; j < 4U; ++j) {
        if (!GG_ISFINITE(cfg->q0_b_e[j])) {
            ok = 0;
        }
    }
    return ok;
}

static int n3_in_limits(const gg_nav3d_config_t *cfg)
{
    const gg_real_t rn = sqrtl(gg_vec3_dot(cfg->r0_e, cfg->r0_e));
    int ok = 1;
    size_t k;
    if ((rn < GG_LIM_R_MIN_M) || (rn > GG_LIM_R_MAX_M) ||
        (sqrtl(gg_vec3_dot(cfg->v0_e, cfg->v0_e)) > GG_LIM_V_MAX_MPS) ||
        (sqrtl(gg_vec3_dot(cfg->g0_e, cfg->g0_e)) > GG_LIM_G_MAX_MPS2) || (cfg->dt_us > GG_LIM_DT_MAX_US) ||
        (cfg->f_max > GG_LIM_F_MAX_MPS2) || (cfg->asym_max > GG_LIM_ASYM_MAX) ||
        (cfg->omega_ie > GG_LIM_OMEGA_IE_MAX_RPS)) {
        ok = 0;
    }
    for (k = 0U; k < 3U; ++k) {
        if ((cfg->geometry.half_base_m[k] < GG_LIM_BASE_MIN_M) ||
            (cfg->geometry.half_base_m[k] > GG_LIM_BASE_MAX_M)) {
            ok = 0;
        }
    }
    return ok;
}

gg_status_t gg_nav3d_init(gg_nav3d_t *nav, const gg_nav3d_config_t *cfg)
{
    gg_diff3d_t diff;
    gg_status_t st;
    gg_real_t qn2;
    if ((nav == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    nav->configured = 0;
    nav->started = 0;
    st = gg_diff3d_init(&diff, &cfg->geometry);
    if (st != GG_OK) {
        return st;
    }
    if ((cfg_finite(cfg) == 0) || (cfg->dt_us <= 0) || (cfg->dt_tol_us < 0) ||
        (cfg->dt_tol_us >= cfg->dt_us) || !(cfg->f_max > 0.0) || !(cfg->asym_max > 0.0) ||
        ((cfg->platform != GG_PLATFORM_STABILIZED) && (cfg->platform != GG_PLATFORM_STRAPDOWN)) ||
        ((cfg->gravity_mode != GG_GRAVITY_GRADIOMETER) && (cfg->gravity_mode != GG_GRAVITY_MODEL)) ||
        (cfg->baro_enable < 0) || (cfg->baro_enable > 1)) {
        return GG_ERR_CONFIG;
    }
    qn2 = (cfg->q0_b_e[0] * cfg->q0_b_e[0]) + (cfg->q0_b_e[1] * cfg->q0_b_e[1]) +
          (cfg->q0_b_e[2] * cfg->q0_b_e[2]) + (cfg->q0_b_e[3] * cfg->q0_b_e[3]);
    if ((qn2 > (1.0L + Q_NORM_TOL)) || (qn2 < (1.0L - Q_NORM_TOL))) {
        return GG_ERR_CONFIG;
    }
    if (n3_in_limits(cfg) == 0) {
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
        int32_t gstate = 0;
        if (cfg->gravity_mode == GG_GRAVITY_GRADIOMETER) {
            gstate = 1; /* the gravitation error is a state of dead reckoning */
        }
        st = gg_aid_mm_init(&nav->aid_mm, &cfg->aid_mm, gstate);
        if (st != GG_OK) {
            return st;
        }
    }
    st = gg_aid_pf_init(&nav->aid_pf, &cfg->aid_pf);
    if (st != GG_OK) {
        return st;
    }
    nav->pf_last_utime = 0;
    nav->pf_have_shot = 0;
    nav->aid_step = -1;
    {
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            nav->aid_corr_m[j] = 0.0;
            nav->loop_k[j] = 0.0;
            nav->loop_u_i[j] = 0.0;
            nav->bias_w[j] = 0.0;
            nav->bias_f[j] = 0.0;
        }
    }
    nav->cfg = *cfg;
    nav->diff = diff;
    nav->omega_ie = (cfg->omega_ie == 0.0L) ? GG_WGS84_OMEGA_IE
                                            : ((cfg->omega_ie < 0.0L) ? 0.0L : cfg->omega_ie);
    nav->dt_s = (gg_real_t)cfg->dt_us * 1.0e-6L;
    st = gg_sincos(0.5L * nav->omega_ie * nav->dt_s, &nav->sin_hstep, &nav->cos_hstep);
    if (st != GG_OK) {
        return GG_ERR_CONFIG;
    }
    nav->gravdr.initialized = 0;
    nav->mech.initialized = 0;
    st = gg_task_seq_init(&nav->seq, cfg->dt_us, cfg->dt_tol_us);
    if (st == GG_OK) {
        gg_fdi3d_config_t fc;
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            fc.half_base_m[j] = cfg->geometry.half_base_m[j];
        }
        fc.parity_f_max = cfg->fdi_parity_f_max;
        fc.stabilized = 0;
        if (cfg->platform == GG_PLATFORM_STABILIZED) {
            fc.stabilized = 1;
        }
        if ((cfg->fdi_parity_f_max != 0.0) && !(cfg->fdi_parity_f_max >= GG_FDI3D_FLOOR_MPS2)) {
            st = GG_ERR_CONFIG; /* below the curvature differences: false alarms */
        } else {
            st = gg_fdi3d_init(&nav->fdi, &fc);
        }
    }
    if (st == GG_OK) {
        st = gg_task_frozen_init(&nav->frozen, cfg->acc_frozen_frames);
    }
    if (st != GG_OK) {
        return st;
    }
    nav->state_step = 0;
    nav->state_clock_us = 0;
    nav->input_step = 0;
    nav->coast_steps = 0U;
    nav->configured = 1;
    return GG_OK;
}

/* ---------------------------------------------------------------- frames */

/* Health bits of a frame's sensors; *frozen_bad = the readings set aside as stuck only
 * (navtask.h frozen-reading monitor); *known_bad = the readings
 * (GG_FDI3D_BIT) that cannot be used as they are; *whole = 0 when the frame
 * is unusable whatever is rebuilt (accelerometer count, gyro). */
static uint32_t n3_check_frame(const gg_nav3d_t *nav, const gg_frame_t *fr, uint32_t *known_bad,
                               uint32_t *frozen_bad, int *whole)
{
    uint32_t h = 0U;
    uint32_t kb = 0U;
    const uint32_t frozen = gg_task_frozen_check(&nav->frozen, fr, N_ACC_3D);
    int32_t i;
    int32_t j;
    *whole = 1;
    *frozen_bad = 0U;
    if (fr->n_acc != N_ACC_3D) {
        h |= GG_HEALTH_ACC_SENSOR;
        *whole = 0;
    }
    for (i = 0; i < N_ACC_3D; ++i) {
        int sensor_bad = 0;
        if (fr->acc_status[i] != GG_SENSOR_OK) {
            h |= GG_HEALTH_ACC_SENSOR;
            sensor_bad = 1;
        }
        for (j = 0; j < 3; ++j) {
            const uint32_t hr = gg_task_check_reading(fr->f[i][j], fr->f_lo[i][j], nav->cfg.f_max);
            h |= hr;
            if ((hr != 0U) || (sensor_bad != 0)) {
                kb |= GG_FDI3D_BIT(i, j);
            }
            if (((frozen & GG_FDI3D_BIT(i, j)) != 0U) && ((kb & GG_FDI3D_BIT(i, j)) == 0U)) {
                h |= GG_HEALTH_ACC_FROZEN; /* stuck (navtask.h): set aside */
                kb |= GG_FDI3D_BIT(i, j);
                *frozen_bad |= GG_FDI3D_BIT(i, j);
            }
        }
    }
    *known_bad = kb;
    if (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) {
        if (fr->gyro_status != GG_SENSOR_OK) {
            h |= GG_HEALTH_GYRO_INVALID;
        }
        for (j = 0; j < 3; ++j) {
            const double w = fr->omega_b[j];
            if (!GG_ISFINITE(w) || (w > GG_LIM_W_MAX_RPS) || (w < -GG_LIM_W_MAX_RPS)) {
                h |= GG_HEALTH_GYRO_INVALID;
            }
        }
        if ((h & GG_HEALTH_GYRO_INVALID) != 0U) {
            *whole = 0;
        }
    }
    return h;
}

/* The part of the state a step changes (saved so a failure part-way leaves
 * nothing changed; the configuration and the model are not copied). */
typedef struct {
    gg_gravdr_t gravdr;
    gg_mech_t mech;
    gg_vchan_t vchan;
    gg_real_t q_b_i[4];
    gg_real_t w_k[3];
    gg_real_t w_km1[3];
    gg_real_t w_km2[3];
    gg_real_t omega_dot_b[3];
    int n_w;
    int64_t n_steps;
    gg_real_t sin_th;
    gg_real_t cos_th;
    gg_real_t gamma_b[3][3];
    gg_real_t gamma_e[3][3];
    gg_real_t f_b[3];
    gg_real_t a_c;
    double loop_k[3];
    double loop_u_i[3];
    gg_real_t h_ins;
    gg_real_t baro_innov;
} dyn_t;

static void dyn_save(const gg_nav3d_t *nav, dyn_t *d)
{
    size_t j;
    size_t k;
    d->gravdr = nav->gravdr;
    d->mech = nav->mech;
    d->vchan = nav->vchan;
    for (j = 0U; j < 4U; ++j) {
        d->q_b_i[j] = nav->q_b_i[j];
    }
    for (j = 0U; j < 3U; ++j) {
        d->w_k[j] = nav->w_k[j];
        d->w_km1[j] = nav->w_km1[j];
        d->w_km2[j] = nav->w_km2[j];
        d->omega_dot_b[j] = nav->omega_dot_b[j];
        d->f_b[j] = nav->f_b[j];
        d->loop_k[j] = nav->loop_k[j];
        d->loop_u_i[j] = nav->loop_u_i[j];
        for (k = 0U; k < 3U; ++k) {
            d->gamma_b[j][k] = nav->gamma_b[j][k];
            d->gamma_e[j][k] = nav->gamma_e[j][k];
        }
    }
    d->n_w = nav->n_w;
    d->n_steps = nav->n_steps;
    d->sin_th = nav->sin_th;
    d->cos_th = nav->cos_th;
    d->a_c = nav->a_c;
    d->h_ins = nav->h_ins;
    d->baro_innov = nav->baro_innov;
}

static void dyn_restore(gg_nav3d_t *nav, const dyn_t *d)
{
    size_t j;
    size_t k;
    nav->gravdr = d->gravdr;
    nav->mech = d->mech;
    nav->vchan = d->vchan;
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = d->q_b_i[j];
    }
    for (j = 0U; j < 3U; ++j) {
        nav->w_k[j] = d->w_k[j];
        nav->w_km1[j] = d->w_km1[j];
        nav->w_km2[j] = d->w_km2[j];
        nav->omega_dot_b[j] = d->omega_dot_b[j];
        nav->f_b[j] = d->f_b[j];
        nav->loop_k[j] = d->loop_k[j];
        nav->loop_u_i[j] = d->loop_u_i[j];
        for (k = 0U; k < 3U; ++k) {
            nav->gamma_b[j][k] = d->gamma_b[j][k];
            nav->gamma_e[j][k] = d->gamma_e[j][k];
        }
    }
    nav->n_w = d->n_w;
    nav->n_steps = d->n_steps;
    nav->sin_th = d->sin_th;
    nav->cos_th = d->cos_th;
    nav->a_c = d->a_c;
    nav->h_ins = d->h_ins;
    nav->baro_innov = d->baro_innov;
}

/* Inputs of one step, body axes. */
typedef struct {
    gg_real_t gamma_b[3][3];
    gg_real_t f_b[3];
    gg_real_t w[3];
    gg_real_t omega_dot[3];
    gg_real_t trace;
} step_in_t;

/* ---------------------------------------------------------------- state */

/* current G in ECI as compensated values, at the mechanization's position */
static gg_status_t current_g_i(gg_nav3d_t *nav, gg_real_t s, gg_real_t c, gg_acc_t g_i[3],
                               uint32_t *health)
{
    gg_status_t st;
    gg_real_t hi[3];
    gg_real_t lo[3];
    size_t j;
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        gg_real_t r_i[3];
        gg_real_t v_i[3];
        gg_real_t g_e[3];
        uint32_t mflags = 0U;
        st = gg_mech_get(&nav->mech, r_i, v_i);
        if (st == GG_OK) {
            gg_real_t r_e[3];
            gg_rot3(s, c, -1, r_i, r_e);
            st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r_e, g_e, &mflags);
        }
        if ((mflags & GG_GMODEL_OUTSIDE_GRID) != 0U) {
            *health |= GG_HEALTH_MODEL_OUTSIDE;
        }
        if (st == GG_OK) {
            gg_rot3(s, c, +1, g_e, hi);
            lo[0] = 0.0L;
            lo[1] = 0.0L;
            lo[2] = 0.0L;
        }
    } else {
        gg_acc_t ge[3];
        st = gg_gravdr_get_acc(&nav->gravdr, ge);
        if (st == GG_OK) {
            gg_real_t gh[3];
            gg_real_t gl[3];
            for (j = 0U; j < 3U; ++j) {
                gh[j] = ge[j].hi;
                gl[j] = ge[j].lo;
            }
            gg_rot3(s, c, +1, gh, hi);
            gg_rot3(s, c, +1, gl, lo);
        }
    }
    if (st == GG_OK) {
        for (j = 0U; j < 3U; ++j) {
            gg_acc_set(&g_i[j], hi[j]);
            gg_acc_add(&g_i[j], lo[j]);
        }
    }
    return st;
}

/* First accepted frame: start every module at the configured state. */
static gg_status_t n3_start(gg_nav3d_t *nav, const step_in_t *in)
{
    gg_real_t c[3][3];
    gg_real_t gamma_i[3][3];
    gg_real_t f_i[3];
    gg_real_t g0[3];
    gg_status_t st = GG_OK;
    size_t j;
    size_t k;
    for (j = 0U; j < 4U; ++j) {
        nav->q_b_i[j] = nav->cfg.q0_b_e[j];
    }
    st = gg_quat_normalize(nav->q_b_i);
    if (st != GG_OK) {
        return st;
    }
    gg_quat_to_dcm(nav->q_b_i, c);
    gg_mat3_similarity(c, in->gamma_b, gamma_i);
    gg_mat3_vec(c, in->f_b, f_i);
    for (j = 0U; j < 3U; ++j) {
        g0[j] = nav->cfg.g0_e[j];
    }
    if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
        st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, nav->cfg.r0_e, g0, NULL);
    }
    if (st == GG_OK) {
        gg_gravdr_config_t gc;
        for (j = 0U; j < 3U; ++j) {
            gc.g0[j] = g0[j];
            for (k = 0U; k < 3U; ++k) {
                gc.gamma0[j][k] = gamma_i[j][k];
            }
        }
        gc.trapezoid_only = 0;
        st = gg_gravdr_init(&nav->gravdr, &gc);
    }
    if (st == GG_OK) {
        gg_mech_config_t mc;
        const gg_real_t w = nav->omega_ie;
        mc.dt_s = nav->dt_s;
        for (j = 0U; j < 3U; ++j) {
            mc.r0[j] = nav->cfg.r0_e[j];
            mc.a0[j] = f_i[j] + g0[j];
        }
        /* inertial velocity = Earth-relative + omega x r */
        mc.v0[0] = nav->cfg.v0_e[0] - (w * nav->cfg.r0_e[1]);
        mc.v0[1] = nav->cfg.v0_e[1] + (w * nav->cfg.r0_e[0]);
        mc.v0[2] = nav->cfg.v0_e[2];
        st = gg_mech_init(&nav->mech, &mc);
    }
    if (st == GG_OK) {
        nav->n_steps = 0;
        nav->sin_th = 0.0L;
        nav->cos_th = 1.0L;
        nav->n_w = 1;
        nav->a_c = 0.0L;
        nav->h_ins = 0.0L;
        nav->baro_innov = 0.0L;
        for (j = 0U; j < 3U; ++j) {
            nav->w_k[j] = in->w[j];
            nav->w_km1[j] = in->w[j];
            nav->w_km2[j] = in->w[j];
            nav->omega_dot_b[j] = in->omega_dot[j];
            for (k = 0U; k < 3U; ++k) {
                nav->gamma_e[j][k] = gamma_i[j][k];
            }
        }
    }
    return st;
}

static uint32_t n3_baro_health(uint32_t vh)
{
    uint32_t h = 0U;
    h |= ((vh & GG_VCHAN_INVALID) != 0U) ? GG_HEALTH_BARO_INVALID : 0U;
    h |= ((vh & GG_VCHAN_STALE) != 0U) ? GG_HEALTH_BARO_STALE : 0U;
    h |= ((vh & GG_VCHAN_OUTLIER) != 0U) ? GG_HEALTH_BARO_OUTLIER : 0U;
    h |= ((vh & GG_VCHAN_RECAPTURE) != 0U) ? GG_HEALTH_BARO_RECAPTURE : 0U;
    h |= ((vh & GG_VCHAN_COAST) != 0U) ? GG_HEALTH_BARO_COAST : 0U;
    return h;
}

/* Barometric loop along the ellipsoid normal, after the step. */
static gg_status_t n3_baro_step(gg_nav3d_t *nav, const gg_frame_t *fr, uint32_t *health)
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t cen[3][3];
    gg_real_t h;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st == GG_OK) {
        gg_real_t r_e[3];
        gg_rot3(nav->sin_th, nav->cos_th, -1, r_i, r_e);
        st = gg_geo_local_frame(r_e, &h, cen);
    }
    if (st == GG_OK) {
        nav->h_ins = h;
    }
    if ((st == GG_OK) && (nav->cfg.baro_enable != 0)) {
        gg_vchan_sample_t smp;
        gg_vchan_output_t vo;
        smp.alt_m = fr->baro_alt_m;
        smp.utime = fr->baro_utime;
        smp.status = fr->baro_status;
        st = gg_vchan_step(&nav->vchan, fr->utime, h, &smp, &vo);
        if (st == GG_OK) {
            gg_real_t u_e[3];
            gg_real_t u_i[3];
            gg_real_t dr_e[3];
            gg_real_t dr_i[3];
            gg_real_t dv_i[3];
            gg_real_t dg_e[3];
            gg_real_t dg_i[3];
            gg_real_t da[3];
            size_t j;
            for (j = 0U; j < 3U; ++j) {
                u_e[j] = -cen[2][j]; /* up = -down */
                dr_e[j] = vo.dh_m * u_e[j];
            }
            gg_rot3(nav->sin_th, nav->cos_th, +1, u_e, u_i);
            for (j = 0U; j < 3U; ++j) {
                dr_i[j] = vo.dh_m * u_i[j];
                dv_i[j] = vo.dv_mps * u_i[j];
            }
            /* the correction is Earth-relative: moving r_i by dr at fixed v_i would
             * change v_e = v_i - w x r_i by -w x dr (east, ~7e-5 m/s per metre), so
             * v_i moves by w x dr as well */
            dv_i[0] -= nav->omega_ie * dr_i[1];
            dv_i[1] += nav->omega_ie * dr_i[0];
            gg_mat3_vec(nav->gamma_e, dr_e, dg_e);
            gg_rot3(nav->sin_th, nav->cos_th, +1, dg_e, dg_i);
            for (j = 0U; j < 3U; ++j) {
                da[j] = dg_i[j] - ((vo.a_c - nav->a_c) * u_i[j]);
            }
            st = gg_mech_correct(&nav->mech, dr_i, dv_i, da);
            if ((st == GG_OK) && (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER)) {
                st = gg_gravdr_correct(&nav->gravdr, dg_e);
            }
            if ((st == GG_OK) &&
                ((vo.k_applied[0] != 0.0L) || (vo.k_applied[1] != 0.0L) || (vo.k_applied[2] != 0.0L))) {
                for (j = 0U; j < 3U; ++j) {
                    nav->loop_k[j] = (double)vo.k_applied[j]; /* the latest, if the aid lags by two */
                    nav->loop_u_i[j] = (double)u_i[j];
                }
            }
            if (st == GG_OK) {
                nav->a_c = vo.a_c;
                if (vo.accepted != 0) {
                    nav->baro_innov = vo.innov_m;
                }
                *health |= n3_baro_health(vo.health);
            }
        }
    }
    return st;
}

/* Up unit vector in ECI at the mechanization's current position. */
static gg_status_t up_i(const gg_nav3d_t *nav, gg_real_t s, gg_real_t c, gg_real_t u_i[3])
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t cen[3][3];
    gg_real_t h;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st == GG_OK) {
        gg_real_t r_e[3];
        gg_rot3(s, c, -1, r_i, r_e);
        st = gg_geo_local_frame(r_e, &h, cen);
    }
    if (st == GG_OK) {
        const gg_real_t u_e[3] = {-cen[2][0], -cen[2][1], -cen[2][2]};
        gg_rot3(s, c, +1, u_e, u_i);
    }
    return st;
}

/* Advance the modules by one step with the inputs of its end point (or
 * start them on the first frame). The caller restores the state on failure. */
static gg_status_t n3_advance(gg_nav3d_t *nav, const gg_frame_t *fr, const step_in_t *in,
                           const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st = GG_OK;
    uint32_t t0;
    if (nav->started == 0) {
        st = n3_start(nav, in);
    } else {
        const int64_t n1 = nav->n_steps + 1;
        const gg_real_t th1 = nav->omega_ie * ((gg_real_t)n1 * nav->dt_s);
        /* half-step angle and mid-step angle (addition theorem from theta_k) */
        const gg_real_t sh = nav->sin_hstep;
        const gg_real_t ch = nav->cos_hstep;
        const gg_real_t sm = (nav->sin_th * ch) + (nav->cos_th * sh);
        const gg_real_t cm = (nav->cos_th * ch) - (nav->sin_th * sh);
        gg_real_t s1 = 0.0L;
        gg_real_t c1 = 1.0L;
        gg_real_t gamma_i[3][3];
        gg_real_t f_i[3];
        gg_real_t r_k[3];
        gg_real_t dr_i[3];
        gg_acc_t g_i[3];
        uint32_t t1;
        size_t j;
        t0 = gg_task_cycles(hal);
        st = gg_sincos(th1, &s1, &c1);
        if ((st == GG_OK) && (nav->cfg.platform == GG_PLATFORM_STRAPDOWN)) {
            st = n3_attitude_step(nav, in->w, in->omega_dot);
        }
        if (st == GG_OK) {
            gg_real_t cb[3][3];
            gg_real_t v_k[3];
            gg_quat_to_dcm(nav->q_b_i, cb);
            gg_mat3_similarity(cb, in->gamma_b, gamma_i);
            gg_mat3_vec(cb, in->f_b, f_i);
            st = gg_mech_get(&nav->mech, r_k, v_k);
        }
        t1 = gg_task_cycles(hal);
        cyc[GG_MOD_DIFF] += t1 - t0;
        if (st == GG_OK) {
            st = gg_mech_step_position(&nav->mech, dr_i);
        }
        t0 = gg_task_cycles(hal);
        cyc[GG_MOD_MECH] += t0 - t1;
        if (st == GG_OK) {
            /* dr_e = R3(-th1) dr_i + [R3(-th1) - R3(-th0)] r_i(k); c1 - c0 = -2 sh sm,
             * s1 - s0 = 2 sh cm (half-angle identities: no cancellation) */
            const gg_real_t dc = -2.0L * sh * sm;
            const gg_real_t ds = 2.0L * sh * cm;
            gg_real_t dr_e[3];
            gg_real_t r_inv[3][3];
            gg_rot3(s1, c1, -1, dr_i, dr_e);
            dr_e[0] += (dc * r_k[0]) + (ds * r_k[1]);
            dr_e[1] += (-ds * r_k[0]) + (dc * r_k[1]);
            gg_rot3_mat(s1, c1, -1, r_inv);
            gg_mat3_t gi;
            const gg_mat3_t *gip = &gi;
            gg_mat3_t ge;
            const gg_mat3_t *gep = &ge;
            gg_mat3_copy(gamma_i, &gi);
            gg_mat3_similarity(r_inv, gip->m, nav->gamma_e);
            gg_mat3_copy(nav->gamma_e, &ge);
            if (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER) {
                st = gg_gravdr_step(&nav->gravdr, gep->m, dr_e);
            }
        }
        if (st == GG_OK) {
            st = current_g_i(nav, s1, c1, g_i, health);
        }
        t1 = gg_task_cycles(hal);
        cyc[GG_MOD_GRAVDR] += t1 - t0;
        if (st == GG_OK) {
            gg_real_t u[3] = {0.0L, 0.0L, 0.0L};
            if (nav->cfg.baro_enable != 0) {
                st = up_i(nav, s1, c1, u);
            }
            if (st == GG_OK) {
                gg_real_t f_next[3];
                for (j = 0U; j < 3U; ++j) {
                    f_next[j] = f_i[j] - (nav->a_c * u[j]);
                }
                st = gg_mech_step_velocity(&nav->mech, f_next, g_i);
            }
        }
        cyc[GG_MOD_MECH] += gg_task_cycles(hal) - t1;
        if (st == GG_OK) {
            nav->n_steps += 1;
            nav->sin_th = s1;
            nav->cos_th = c1;
            for (j = 0U; j < 3U; ++j) {
                nav->w_km2[j] = nav->w_km1[j];
                nav->w_km1[j] = nav->w_k[j];
                nav->w_k[j] = in->w[j];
                nav->omega_dot_b[j] = in->omega_dot[j];
            }
            nav->n_w = (nav->n_w < 3) ? (nav->n_w + 1) : 3;
        }
    }
    t0 = gg_task_cycles(hal);
    if (st == GG_OK) {
        st = n3_baro_step(nav, fr, health);
    }
    cyc[GG_MOD_VCHAN] += gg_task_cycles(hal) - t0;
    return st;
}

/* Differencing of one frame: body-axis gradient, centre force, angular
 * acceleration and parity. */
static gg_status_t difference(const gg_nav3d_t *nav, const gg_frame_t *fr, step_in_t *in)
{
    gg_diff3d_input_t di;
    gg_diff3d_output_t d;
    gg_status_t st;
    size_t i;
    size_t j;
    for (i = 0U; i < 6U; ++i) {
        for (j = 0U; j < 3U; ++j) {
            di.f[i][j] = fr->f[i][j];
            di.f_lo[i][j] = fr->f_lo[i][j];
        }
    }
    for (j = 0U; j < 3U; ++j) {
        di.omega_b[j] = (nav->cfg.platform == GG_PLATFORM_STRAPDOWN)
                            ? ((gg_real_t)fr->omega_b[j] - (gg_real_t)nav->bias_w[j])
                            : 0.0L;
    }
    st = gg_diff3d_step(&nav->diff, &di, &d);
    for (i = 0U; (i < 3U) && (st == GG_OK); ++i) {
        for (j = 0U; j < 3U; ++j) {
            if ((d.gamma[i][j] > GG_LIM_GAMMA_MAX_S2) || (d.gamma[i][j] < -GG_LIM_GAMMA_MAX_S2)) {
                st = GG_ERR_RANGE; /* no gradient: readings no parity check caught */
            }
        }
    }
    if (st == GG_OK) {
        for (j = 0U; j < 3U; ++j) {
            size_t k;
            in->f_b[j] = d.f_c[j] - (gg_real_t)nav->bias_f[j];
            in->w[j] = di.omega_b[j];
            in->omega_dot[j] = d.omega_dot[j];
            for (k = 0U; k < 3U; ++k) {
                in->gamma_b[j][k] = d.gamma[j][k];
            }
        }
        in->trace = d.trace;
    }
    return st;
}

/* The inputs of the last accepted frame, held through a bridge or a coast
 * (the trace is only for the parity: 0). */
static void n3_held_inputs(const gg_nav3d_t *nav, step_in_t *h)
{
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        h->f_b[j] = nav->f_b[j];
        h->w[j] = nav->w_k[j];
        h->omega_dot[j] = nav->omega_dot_b[j];
        for (k = 0U; k < 3U; ++k) {
            h->gamma_b[j][k] = nav->gamma_b[j][k];
        }
    }
    h->trace = 0.0L;
}

/* Gyro-derived angular acceleration at this step from the rate w1 and the
 * three earlier samples: third-order backward difference
 * (11 w_{k+1} - 18 w_k + 9 w_{k-1} - 2 w_{k-2}) / (6h) (nav3d.h). */
static void n3_gyro_omega_dot(const gg_nav3d_t *nav, const gg_real_t w1[3], gg_real_t wd[3])
{
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        wd[j] = ((11.0L * w1[j]) - (18.0L * nav->w_k[j]) + (9.0L * nav->w_km1[j]) -
                 (2.0L * nav->w_km2[j])) /
                (6.0L * nav->dt_s);
    }
}

/* Bridge lost frames: f_b, Gamma_b, w and omega_dot interpolated linearly between the
 * last accepted frame and this one, no barometer. */
static gg_status_t n3_bridge(gg_nav3d_t *nav, const gg_frame_t *fr, const step_in_t *in,
                          int64_t missing, const gg_hal_t *hal, uint32_t cyc[GG_MOD_COUNT],
                          uint32_t *health)
{
    gg_status_t st = GG_OK;
    step_in_t base;
    int64_t i;
    size_t j;
    size_t k;
    n3_held_inputs(nav, &base); /* the last accepted frame's (advance moves w_k on) */
    for (i = 1; (i <= missing) && (i <= GG_NAV3D_MAX_BRIDGE) && (st == GG_OK); ++i) {
        const gg_real_t w = (gg_real_t)i / ((gg_real_t)missing + 1.0L);
        step_in_t bi;
        gg_frame_t fi;
        bi = *in;
        fi = *fr;
        for (j = 0U; j < 3U; ++j) {
            bi.f_b[j] = base.f_b[j] + (w * (in->f_b[j] - base.f_b[j]));
            bi.w[j] = base.w[j] + (w * (in->w[j] - base.w[j]));
            bi.omega_dot[j] = base.omega_dot[j] + (w * (in->omega_dot[j] - base.omega_dot[j]));
            for (k = 0U; k < 3U; ++k) {
                bi.gamma_b[j][k] =
                    base.gamma_b[j][k] + (w * (in->gamma_b[j][k] - base.gamma_b[j][k]));
            }
        }
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        fi.baro_status = GG_SENSOR_ABSENT;
        st = n3_advance(nav, &fi, &bi, hal, cyc, health);
    }
    return st;
}

/* Coast n steps on the last usable inputs (f_b, Gamma_b, w and omega_dot
 * held; an outage longer than the bridge), no barometer. */
static gg_status_t n3_coast(gg_nav3d_t *nav, const gg_frame_t *fr, int64_t n, const gg_hal_t *hal,
                            uint32_t cyc[GG_MOD_COUNT], uint32_t *health)
{
    gg_status_t st = GG_OK;
    step_in_t hold;
    gg_frame_t fi = *fr;
    int64_t i;
    n3_held_inputs(nav, &hold);
    fi.baro_status = GG_SENSOR_ABSENT;
    for (i = 1; (i <= n) && (i <= GG_TASK_CATCHUP_STEPS) && (st == GG_OK); ++i) {
        fi.utime = nav->state_clock_us + (i * nav->cfg.dt_us);
        st = n3_advance(nav, &fi, &hold, hal, cyc, health);
    }
    return st;
}

/* Column entries M = W - Gamma_b (diff3d.h) of the onboard model at the
 * state's position carried one step on (the frame's), for the entries a degraded rebuild cannot rebuild
 * (gravity-model mode): Gamma_e by central differences of the model over
 * +-GG_NAV3D_MODEL_DX_M on each ECEF axis (truncation (dx^2/6) |d3G| ~ 1e-17
 * s^-2, rounding eps |G| / dx), symmetrised, into body axes with the state's
 * attitude; W = [w x]^2 + [w' x] with the frame's rate and angular
 * acceleration (0 when unknown). */
static gg_status_t n3_model_prior(const gg_nav3d_t *nav, const gg_real_t w[3],
                                  const gg_real_t *wd, gg_real_t m[3][3])
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t r_e[3];
    gg_real_t ge[3][3];
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    gg_real_t s1 = 0.0L;
    gg_real_t c1 = 1.0L;
    size_t j;
    size_t k;
    if (st == GG_OK) {
        /* at the frame's time, one step on: r_i + v_i dt, theta_{k+1} */
        const int64_t n1 = nav->n_steps + 1;
        st = gg_sincos(nav->omega_ie * ((gg_real_t)n1 * nav->dt_s), &s1, &c1);
    }
    if (st == GG_OK) {
        for (j = 0U; j < 3U; ++j) {
            r_i[j] += v_i[j] * nav->dt_s;
        }
        gg_rot3(s1, c1, -1, r_i, r_e);
    }
    for (k = 0U; (k < 3U) && (st == GG_OK); ++k) {
        gg_real_t rp[3];
        gg_real_t rn[3];
        gg_real_t gp[3];
        gg_real_t gn[3];
        for (j = 0U; j < 3U; ++j) {
            rp[j] = r_e[j];
            rn[j] = r_e[j];
        }
        rp[k] += GG_NAV3D_MODEL_DX_M;
        rn[k] -= GG_NAV3D_MODEL_DX_M;
        st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, rp, gp, NULL);
        if (st == GG_OK) {
            st = gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, rn, gn, NULL);
        }
        if (st == GG_OK) {
            for (j = 0U; j < 3U; ++j) {
                ge[j][k] = (gp[j] - gn[j]) / (2.0L * GG_NAV3D_MODEL_DX_M);
            }
        }
    }
    if (st == GG_OK) {
        gg_real_t gi[3][3];
        gg_real_t gb[3][3];
        gg_real_t rm[3][3];
        gg_real_t cb[3][3];
        gg_real_t ct[3][3];
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < j; ++k) {
                const gg_real_t a = 0.5L * (ge[j][k] + ge[k][j]);
                ge[j][k] = a;
                ge[k][j] = a;
            }
        }
        gg_mat3_t tm;
        const gg_mat3_t *tmp = &tm;
        gg_rot3_mat(s1, c1, +1, rm);
        gg_mat3_copy(ge, &tm);
        gg_mat3_similarity(rm, tmp->m, gi);
        gg_quat_to_dcm(nav->q_b_i, cb);
        for (j = 0U; j < 3U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                ct[j][k] = cb[k][j];
            }
        }
        gg_mat3_copy(gi, &tm);
        gg_mat3_similarity(ct, tmp->m, gb);
        {
            const gg_real_t w2 = (w[0] * w[0]) + (w[1] * w[1]) + (w[2] * w[2]);
            gg_real_t a[3] = {0.0L, 0.0L, 0.0L};
            if (wd != NULL) {
                for (j = 0U; j < 3U; ++j) {
                    a[j] = wd[j];
                }
            }
            for (j = 0U; j < 3U; ++j) {
                for (k = 0U; k < 3U; ++k) {
                    gg_real_t wv = w[j] * w[k];
                    if (j == k) {
                        wv -= w2;
                    }
                    m[j][k] = wv - gb[j][k];
                }
            }
            /* [w' x] */
            m[0][1] -= a[2];
            m[0][2] += a[1];
            m[1][0] += a[2];
            m[1][2] -= a[0];
            m[2][0] -= a[1];
            m[2][1] += a[0];
        }
        if ((gg_finite3(m[0]) == 0) || (gg_finite3(m[1]) == 0) || (gg_finite3(m[2]) == 0)) {
            st = GG_ERR_NONFINITE;
        }
    }
    return st;
}

/* Parity residuals: antisymmetric part against 0 (stabilized) or against the
 * gyro-derived angular acceleration (strapdown), and the trace. */
static void n3_parity(const gg_nav3d_t *nav, const step_in_t *in, gg_real_t p[4])
{
    gg_real_t gyro_wd[3];
    size_t j;
    n3_gyro_omega_dot(nav, in->w, gyro_wd);
    for (j = 0U; j < 3U; ++j) {
        if (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) {
            /* third-order backward difference; needs three earlier gyro
             * samples, 0 (no evidence) on the first three steps */
            if ((nav->started != 0) && (nav->n_w >= 3)) {
                p[j] = in->omega_dot[j] - gyro_wd[j];
            } else {
                p[j] = 0.0L;
            }
        } else {
            p[j] = in->omega_dot[j];
        }
    }
    p[3] = in->trace;
}

/* A frame's readings through fault isolation (nav->fdi, which on entry is
 * *fdi_before) and differencing: *fixed = the frame with its unusable readings
 * rebuilt, *in = the differenced gradient and centre force. Returns the
 * readings' status; ORs their health bits into *health (whose validation bits
 * on entry name the readings' own fault) and sets *rebuilt. */
static gg_status_t n3_read(gg_nav3d_t *nav, const gg_frame_t *frame, const gg_fdi3d_t *fdi_before,
                           uint32_t known_bad, const gg_real_t w_now[3], const gg_real_t *wd_p,
                           gg_frame_t *fixed, step_in_t *in, uint32_t *health, uint32_t *rebuilt)
{
    gg_status_t st_read;
    gg_fdi3d_output_t fo = {0U, 0U, 0U, 0U, 0U, 0U, 0.0L};
    *fixed = *frame;
    st_read = gg_fdi3d_step(&nav->fdi, known_bad, w_now, wd_p, fixed->f, fixed->f_lo, &fo);
    if ((st_read == GG_OK) && ((fo.flags & GG_FDI3D_HOLD_GRAD) != 0U) &&
        (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) && (nav->started != 0)) {
        /* gravity-model mode: what cannot be rebuilt comes from the model */
        gg_real_t mp[3][3];
        gg_fdi3d_t fdi_model;
        fdi_model = *fdi_before; /* the state before the step */
        if ((n3_model_prior(nav, w_now, wd_p, mp) == GG_OK) &&
            (gg_fdi3d_set_prior(&fdi_model, mp) == GG_OK)) {
            nav->fdi = fdi_model;
            *fixed = *frame;
            st_read = gg_fdi3d_step(&nav->fdi, known_bad, w_now, wd_p, fixed->f, fixed->f_lo, &fo);
            if (gg_fdi3d_set_prior(&nav->fdi, NULL) != GG_OK) {
                st_read = GG_ERR_NULL; /* not reached: the state is there */
            }
        }
    }
    *rebuilt = fo.rebuilt;
    if ((fo.flags & GG_FDI3D_DETECTED) != 0U) {
        *health |= GG_HEALTH_ACC_FAULT;
    }
    if ((st_read == GG_OK) && ((fo.flags & (GG_FDI3D_PAIR | GG_FDI3D_HOLD_GRAD)) != 0U)) {
        *health |= GG_HEALTH_GRAD_COAST;
    }
    if ((st_read == GG_OK) && ((fo.flags & GG_FDI3D_DEGRADED) != 0U)) {
        *health |= GG_HEALTH_ACC_DEGRADED;
    }
    if ((st_read == GG_OK) && ((fo.flags & GG_FDI3D_HOLD_FORCE) != 0U)) {
        *health |= GG_HEALTH_FORCE_COAST;
    }
    if (st_read != GG_OK) {
        /* the readings' own fault, as the health word says */
        if ((*health & GG_HEALTH_ACC_NONFINITE) != 0U) {
            st_read = GG_ERR_NONFINITE;
        } else if ((*health & GG_HEALTH_ACC_RANGE) != 0U) {
            st_read = GG_ERR_RANGE;
        } else {
            st_read = GG_ERR_SENSOR; /* flagged bad, or a fault parity cannot isolate */
        }
    } else {
        if (*rebuilt != 0U) {
            *health |= GG_HEALTH_ACC_REBUILT;
        }
        st_read = difference(nav, fixed, in);
        if (st_read == GG_ERR_RANGE) {
            *health |= GG_HEALTH_ACC_RANGE;
        }
    }
    return st_read;
}

gg_status_t gg_nav3d_step(gg_nav3d_t *nav, const gg_frame_t *frame, const gg_hal_t *hal,
                          gg_nav3d_output_t *out)
{
    uint32_t cyc[GG_MOD_COUNT] = {0U, 0U, 0U, 0U, 0U, 0U, 0U};
    const uint32_t t_start = gg_task_cycles(hal);
    int32_t mm_corrected = 0;
    int32_t pf_corrected = 0;
    uint32_t health;
    gg_status_t st = GG_OK;
    gg_status_t st_read = GG_OK;
    step_in_t in;
    gg_real_t par[4] = {0.0L, 0.0L, 0.0L, 0.0L};
    int64_t fstep = -1;
    int used = 0;
    uint32_t known_bad = 0U;
    uint32_t frozen_bad = 0U;
    uint32_t rebuilt = 0U;
    int whole = 1;
    gg_fdi3d_t fdi_saved;
    gg_frame_t fixed;
    if ((nav == NULL) || (frame == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (nav->configured == 0) {
        const gg_nav3d_output_t empty = {0};
        *out = empty;
        out->utime = frame->utime;
        out->seq = frame->seq;
        out->status = (int32_t)GG_ERR_NOT_INIT;
        out->health = GG_HEALTH_NOT_INIT | GG_HEALTH_FRAME_REJECTED;
        return GG_ERR_NOT_INIT;
    }
    fdi_saved = nav->fdi;
    health = n3_check_frame(nav, frame, &known_bad, &frozen_bad, &whole);
    health |= gg_task_seq_update(&nav->seq, frame, &fstep);
    if (fstep < 0) {
        st_read = GG_ERR_SEQUENCE;
    } else if (whole == 0) {
        st_read = GG_ERR_SENSOR;
    } else {
        const uint32_t t0 = gg_task_cycles(hal);
        gg_real_t w_now[3];
        gg_real_t wd_ref[3];
        const gg_real_t *wd_p = NULL;
        uint32_t h_read = health;
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            w_now[j] = (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) ? (gg_real_t)frame->omega_b[j]
                                                                    : 0.0L;
        }
        /* the gyro-derived angular acceleration, once three earlier samples exist */
        n3_gyro_omega_dot(nav, w_now, wd_ref);
        if ((nav->started != 0) && (nav->n_w >= 3) && (fstep == (nav->state_step + 1))) {
            wd_p = wd_ref;
        }
        st_read = n3_read(nav, frame, &fdi_saved, known_bad, w_now, wd_p, &fixed, &in, &h_read, &rebuilt);
        if ((st_read != GG_OK) && ((fdi_saved.have_good != 0) || (fdi_saved.excluded != 0U) ||
                                   (fdi_saved.excluded_pairs != 0U))) {
            /* Readings refused with the isolation's latched state (readings and pairs
             * excluded, pair means and column entries of the last frame used): that
             * state may itself be what a run of bad frames left wrong, and it would
             * refuse every frame after. The frame is tried once more from a fresh
             * isolation; used so, it is flagged ACC_FAULT and the latched state is
             * gone (acc_excluded empty until a fault is isolated again). */
            gg_fdi3d_t fresh;
            uint32_t h2 = health;
            uint32_t rb2 = 0U;
            gg_status_t st2 = GG_ERR_SENSOR;
            if (gg_fdi3d_init(&fresh, &fdi_saved.cfg) == GG_OK) {
                nav->fdi = fresh;
                /* the refused try's fixed and in are not used: the retries write there */
                st2 = n3_read(nav, frame, &fresh, known_bad, w_now, wd_p, &fixed, &in, &h2, &rb2);
                if ((st2 != GG_OK) && (frozen_bad != 0U)) {
                    /* Nothing usable with the stuck readings set aside: they are used as
                     * they are (still flagged ACC_FROZEN). A stuck value is a plausible
                     * reading; refusing it would refuse every frame for as long as it
                     * stays stuck (a noise-free sensor at rest, the monitor on). */
                    h2 = health;
                    rb2 = 0U;
                    nav->fdi = fresh;
                    st2 = n3_read(nav, frame, &fresh, known_bad & ~frozen_bad, w_now, wd_p, &fixed,
                                  &in, &h2, &rb2);
                }
            }
            if (st2 == GG_OK) {
                st_read = GG_OK;
                h_read = h2 | GG_HEALTH_ACC_FAULT;
                rebuilt = rb2;
            }
        }
        health = h_read;
        cyc[GG_MOD_DIFF] = gg_task_cycles(hal) - t0;
    }
    st = st_read;
    if (fstep >= 0) {
        /* module states saved so a failure part-way leaves nothing changed */
        dyn_t saved;
        const int64_t step_saved = nav->state_step;
        const int64_t clock_saved = nav->state_clock_us;
        gg_task_plan_t plan = {0, 0, 0};
        gg_status_t st_nav = GG_OK;
        uint32_t step_health = 0U;
        gg_frame_t ft;
        gg_task_seq_map_frame(&nav->seq, frame, &ft);
        if (st_read == GG_OK) {
            n3_parity(nav, &in, par);
        }
        dyn_save(nav, &saved);
        if (nav->started == 0) {
            if (st_read == GG_OK) {
                plan.use = 1;
            }
        } else {
            gg_task_plan(fstep, nav->state_step, (st_read == GG_OK) ? 1 : 0, GG_NAV3D_MAX_BRIDGE,
                         &plan);
        }
        if (plan.coast > 0) {
            st_nav = n3_coast(nav, &ft, plan.coast, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                nav->state_step += plan.coast;
                nav->state_clock_us += plan.coast * nav->cfg.dt_us;
                step_health |= GG_HEALTH_COAST;
            }
        }
        if ((st_nav == GG_OK) && (plan.use != 0)) {
            st_nav = n3_bridge(nav, &ft, &in, plan.bridge, hal, cyc, &step_health);
            if (st_nav == GG_OK) {
                st_nav = n3_advance(nav, &ft, &in, hal, cyc, &step_health);
            }
        }
        if (st_nav != GG_OK) {
            dyn_restore(nav, &saved);
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
            nav->f_b[j] = in.f_b[j];
            for (k = 0U; k < 3U; ++k) {
                nav->gamma_b[j][k] = in.gamma_b[j][k];
            }
        }
        for (j = 0U; j < 4U; ++j) {
            const gg_real_t lim = (gg_real_t)nav->cfg.asym_max;
            nav->parity[j] = par[j];
            if ((par[j] > lim) || (par[j] < -lim)) {
                health |= GG_HEALTH_GAMMA_ASYM;
            }
        }
        nav->started = 1;
        nav->input_step = fstep;
        gg_task_frozen_commit(&nav->frozen, frame, N_ACC_3D);
    } else {
        nav->fdi = fdi_saved;
        rebuilt = 0U;
        health |= GG_HEALTH_FRAME_REJECTED;
    }
    if ((nav->aid_mm.initialized != 0) && (nav->started != 0)) {
        const uint32_t ta = gg_task_cycles(hal);
        if (nav->aid_step < 0) {
            nav->aid_step = nav->state_step; /* the aid starts with the state */
            n3_aid_start(nav, &nav->aid_mm, &health);
        } else if (nav->state_step > nav->aid_step) {
            int z_ok = 0;
            if ((used != 0) && ((nav->state_step - nav->aid_step) == 1) && (rebuilt == 0U) &&
                ((health & (GG_HEALTH_GRAD_COAST | GG_HEALTH_COAST)) == 0U)) {
                z_ok = 1;
            }
            n3_aid_step(nav, nav->state_step - nav->aid_step, z_ok, hal, &health, &mm_corrected);
            nav->aid_step = nav->state_step;
        } else {
            /* the state did not advance: nothing for the aid */
        }
        cyc[GG_MOD_AID_MM] = gg_task_cycles(hal) - ta;
    }
    if ((nav->aid_pf.initialized != 0) && (nav->started != 0)) {
        const uint32_t ta = gg_task_cycles(hal);
        n3_pf_step(nav, frame, used, hal, &health, &pf_corrected);
        cyc[GG_MOD_AID_PF] = gg_task_cycles(hal) - ta;
    }
    n3_fill_output(nav, frame, st, health, out);
    n3_aid_output(nav, out);
    n3_pf_output(nav, out);
    out->pf_corrected = pf_corrected;
    out->mm_corrected = mm_corrected;
    out->acc_rebuilt = rebuilt;
    out->acc_excluded = nav->fdi.excluded;
    out->resync_count = nav->seq.resyncs;
    out->coast_steps = nav->coast_steps;
    gg_task_outage(&nav->seq, nav->started, nav->state_step, nav->input_step, nav->cfg.dt_us,
                   &out->outage_s, &out->state_lag_s);
    out->health |= gg_task_close_cycles(hal, nav->cfg.dt_us, t_start, cyc, out->cycles);
    return st;
}

gg_status_t gg_nav3d_task_cycle(gg_nav3d_t *nav, const gg_hal_t *hal)
{
    gg_frame_t frame;
    gg_nav3d_output_t out;
    gg_status_t st;
    gg_status_t st_step;
    if ((nav == NULL) || (hal == NULL) || (hal->read_frame == NULL) ||
        (hal->write_output3d == NULL)) {
        return GG_ERR_NULL;
    }
    st = hal->read_frame(hal->ctx, &frame);
    if (st != GG_OK) {
        return st;
    }
    st_step = gg_nav3d_step(nav, &frame, hal, &out);
    st = hal->write_output3d(hal->ctx, &out);
    if (st != GG_OK) {
        return GG_ERR_IO;
    }
    return st_step;
}
