/* Gradient-map UKF as an aiding source of the 3-D task: configuration, start and
 * the real-time schedule (aid_mmukf.h); the error dynamics are in aid_mmukf_dyn.c,
 * the measurement model and the epoch average in aid_mmukf_meas.c. */
#include "ggins/aid_mmukf.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ggins/geo.h"
#include "ggins/gmap.h"
#include "ggins/quat.h"

#include "aid_mmukf_int.h"

/* no over-aligned member (aid_mmukf.h, after gg_aid_mm_t) */
_Static_assert(_Alignof(gg_aid_mm_t) <= _Alignof(double), "gg_aid_mm_t must not be over-aligned");

/* ---------------------------------------------------------------- config */

static int pos_finite(double v)
{
    int ok = 0;
    if ((v > 0.0) && (v < 1.0e300)) {
        ok = 1;
    }
    return ok;
}

static int nonneg_finite(double v)
{
    int ok = 0;
    if ((v >= 0.0) && (v < 1.0e300)) {
        ok = 1;
    }
    return ok;
}

static gg_status_t aid_cfg_ok(const gg_aid_mm_config_t *c)
{
    gg_status_t st = GG_OK;
    if ((c->max_passes < 1) || (c->max_passes > GG_MM_MAX_PASSES) ||
        (c->update_steps < ((2 * c->max_passes) + 2)) || (c->update_steps > GG_LIM_AID_MM_UPDATE_STEPS_MAX) ||
        (pos_finite(c->sigma_meas_s2) == 0) || (nonneg_finite(c->sigma_db_s2) == 0) ||
        (nonneg_finite(c->offdiag_ratio) == 0) || (c->offdiag_ratio > GG_LIM_MM_OFFDIAG_MAX) ||
        (pos_finite(c->sig0_pos_m) == 0) || (pos_finite(c->sig0_vel_mps) == 0) ||
        (pos_finite(c->sig0_att_rad) == 0) || (pos_finite(c->sig0_g_mps2) == 0) ||
        (nonneg_finite(c->q_vel_mps_rts) == 0) || (nonneg_finite(c->q_att_rad_rts) == 0) ||
        (nonneg_finite(c->q_g_mps2_rts) == 0) || (nonneg_finite(c->lambda) == 0) ||
        !GG_ISFINITE(c->gate_nis) || (c->average_steps < 0) || (c->average_steps > c->update_steps) ||
        (nonneg_finite(c->sigma_gyro_rps) == 0) || (c->sigma_gyro_rps > GG_LIM_AID_MM_SIGMA_W_MAX_RPS) ||
        (nonneg_finite(c->sigma_gyro_bias_rps) == 0) ||
        (c->sigma_gyro_bias_rps > GG_LIM_AID_MM_SIGMA_W_MAX_RPS) || (c->bias_states < 0) ||
        (c->bias_states > 1) || (nonneg_finite(c->sigma_baro_m) == 0) ||
        (c->sigma_baro_m > GG_LIM_AID_MM_SIGMA_BARO_MAX_M)) {
        st = GG_ERR_CONFIG;
    }
    if ((st == GG_OK) && (c->bias_states == 1) &&
        ((pos_finite(c->sig0_gyro_bias_rps) == 0) || (c->sig0_gyro_bias_rps > GG_LIM_AID_MM_SIGMA_W_MAX_RPS) ||
         (pos_finite(c->sig0_acc_bias_mps2) == 0) || (c->sig0_acc_bias_mps2 > GG_LIM_AID_MM_ACC_BIAS_MAX_MPS2) ||
         (nonneg_finite(c->q_gyro_bias_rps_rts) == 0) || (nonneg_finite(c->q_acc_bias_mps2_rts) == 0))) {
        st = GG_ERR_CONFIG;
    }
    return st;
}

gg_status_t gg_aid_mm_init(gg_aid_mm_t *a, const gg_aid_mm_config_t *cfg, int32_t gravity_state)
{
    gg_integ_t integ;
    double zero[NXM];
    double P0[NXM][NXM];
    gg_ukf_config_t uc;
    gg_status_t st;
    int32_t j;
    int32_t nx = GG_AID_MM_NX_MODEL;
    if ((a == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    (void)memset(zero, 0, sizeof zero);
    a->initialized = 0;
    if (cfg->enable == 0) {
        return GG_OK;
    }
    if ((cfg->enable != 1) || ((gravity_state != 0) && (gravity_state != 1))) {
        return GG_ERR_CONFIG;
    }
    st = aid_cfg_ok(cfg);
    if (st != GG_OK) {
        return st;
    }
    if (gravity_state != 0) {
        nx = GG_AID_MM_NX_DR;
    }
    a->nb = nx;
    mat_zero(P0);
    for (j = 0; j < 3; ++j) {
        P0[j][j] = cfg->sig0_pos_m * cfg->sig0_pos_m;
        P0[3 + j][3 + j] = cfg->sig0_vel_mps * cfg->sig0_vel_mps;
        P0[6 + j][6 + j] = cfg->sig0_att_rad * cfg->sig0_att_rad;
        if (nx == GG_AID_MM_NX_DR) {
            P0[9 + j][9 + j] = cfg->sig0_g_mps2 * cfg->sig0_g_mps2;
        }
        if (cfg->bias_states != 0) {
            P0[a->nb + j][a->nb + j] = cfg->sig0_gyro_bias_rps * cfg->sig0_gyro_bias_rps;
            P0[a->nb + 3 + j][a->nb + 3 + j] = cfg->sig0_acc_bias_mps2 * cfg->sig0_acc_bias_mps2;
        }
    }
    if (cfg->bias_states != 0) {
        nx += GG_AID_MM_NX_BIAS;
    }
    uc.nx = nx;
    uc.lambda = cfg->lambda;
    uc.gate_nis = cfg->gate_nis;
    if (gg_integ_init(&integ, &cfg->integ, 6.0) != GG_OK) {
        return GG_ERR_CONFIG;
    }
    /* cppcheck-suppress misra-c2012-17.7 */
    st = gg_ukf_init(&a->ukf, &uc, zero, (const double(*)[NXM])P0);
    if (st != GG_OK) {
        return st;
    }
    a->integ = integ;
    a->n_isolated = 0U;
    a->cfg = *cfg;
    a->nx = nx;
    mat_identity(nx, a->phi);
    mat_zero(a->q);
    a->tile = NULL;
    {
        const double sm = cfg->sigma_meas_s2;
        double ratio = cfg->offdiag_ratio;
        double so;
        const double rdb = cfg->sigma_db_s2 * cfg->sigma_db_s2;
        if (!(ratio > 0.0)) {
            ratio = 1.0;
        }
        so = ratio * sm;
        for (j = 0; j < 3; ++j) {
            a->rk[j] = (sm * sm) + rdb;
            a->rk[3 + j] = (so * so) + rdb;
        }
    }
    a->w_pass = 1.0;
    a->remaining = 1.0;
    a->pass = 0;
    a->phase = GG_AID_MM_PH_PROPAGATE;
    a->steps_since_epoch = 0;
    a->accepted_any = 0;
    a->health = 0U;
    a->n_epochs = 0U;
    a->n_updates = 0U;
    a->n_rejected = 0U;
    a->n_no_map = 0U;
    a->last_nis = 0.0;
    a->last_n_avg = 0;
    for (j = 0; j < 6; ++j) {
        a->last_innov[j] = 0.0;
    }
    (void)memset(a->ep_r, 0, sizeof a->ep_r);
    aid_mm_window_reset(a);
    a->initialized = 1;
    return GG_OK;
}

gg_status_t gg_aid_mm_start(gg_aid_mm_t *a, const double gamma_i[3][3])
{
    double zero[NXM];
    double P0[NXM][NXM];
    gg_ukf_t u;
    int32_t j;
    int32_t k;
    if ((a == NULL) || (gamma_i == NULL)) {
        return GG_ERR_NULL;
    }
    if (a->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    if (a->nb != GG_AID_MM_NX_DR) {
        return GG_OK;
    }
    for (j = 0; j < 3; ++j) {
        for (k = 0; k < 3; ++k) {
            if (!GG_ISFINITE(gamma_i[j][k])) {
                return GG_ERR_NONFINITE;
            }
        }
    }
    for (j = 0; j < NXM; ++j) {
        for (k = 0; k < NXM; ++k) {
            P0[j][k] = a->ukf.P[j][k];
        }
    }
    /* dg = -Gamma dr + n_g with dr ~ P_rr (diagonal, sig0_pos) */
    {
        const double prr = a->cfg.sig0_pos_m * a->cfg.sig0_pos_m;
        const double pgg = a->cfg.sig0_g_mps2 * a->cfg.sig0_g_mps2;
        for (j = 0; j < 3; ++j) {
            for (k = 0; k < 3; ++k) {
                double s = 0.0;
                int32_t l;
                for (l = 0; l < 3; ++l) {
                    s += gamma_i[j][l] * gamma_i[k][l];
                }
                P0[9 + j][9 + k] = prr * s;
                P0[9 + j][k] = -prr * gamma_i[j][k];
                P0[k][9 + j] = -prr * gamma_i[j][k];
            }
            P0[9 + j][9 + j] += pgg;
        }
    }
    u = a->ukf;
    (void)memset(zero, 0, sizeof zero);
    /* cppcheck-suppress misra-c2012-17.7 */
    if (gg_ukf_init(&u, &a->ukf.cfg, zero, (const double(*)[NXM])P0) != GG_OK) {
        return GG_ERR_RANGE;
    }
    a->ukf = u;
    return GG_OK;
}


/* ---------------------------------------------------------------- schedule */

static int ins_ok(const gg_aid_ins_t *ins)
{
    int ok = 1;
    size_t j;
    size_t k;
    if ((ins->n_steps < 1) || (ins->n_steps > GG_LIM_AID_MM_STEPS_MAX) || !(ins->dt_s > 0.0) ||
        !(ins->dt_s <= 1.0) || !GG_ISFINITE(ins->omega_ie) || !GG_ISFINITE(ins->sin_th) ||
        !GG_ISFINITE(ins->cos_th)) {
        ok = 0;
    }
    for (j = 0U; j < 3U; ++j) {
        if (!GG_ISFINITE(ins->r_e[j]) || !GG_ISFINITE(ins->f_i[j]) || !GG_ISFINITE(ins->loop_k[j]) ||
            !(fabs(ins->loop_u_i[j]) <= 1.0)) {
            ok = 0;
        }
        for (k = 0U; k < 3U; ++k) {
            if (!GG_ISFINITE(ins->c_b_e[j][k]) || !GG_ISFINITE(ins->gamma_i[j][k]) ||
                !GG_ISFINITE(ins->c_b_i[j][k])) {
                ok = 0;
            }
        }
    }
    for (j = 0U; j < 6U; ++j) {
        if (!GG_ISFINITE(ins->z_b[j]) || (ins->z_b[j] > GG_LIM_MM_GAMMA_MAX_S2) ||
            (ins->z_b[j] < -GG_LIM_MM_GAMMA_MAX_S2)) {
            ok = 0;
        }
    }
    return ok;
}

/* Start an epoch: tile from the map storage, the measurement and its
 * nominal, UKF predict to the epoch. */
static void start_epoch(gg_aid_mm_t *a, const gg_aid_ins_t *ins, const gg_hal_map_t *map)
{
    gg_real_t lat = 0.0L;
    gg_real_t lon = 0.0L;
    gg_real_t h = 0.0L;
    const gg_gmap_t *tile = NULL;
    gg_status_t st = GG_ERR_RANGE;
    size_t j;
    size_t k;
    a->n_epochs++;
    aid_mm_window_epoch(a, ins);
    aid_mm_window_reset(a);
    a->steps_since_epoch = 0;
    if ((map != NULL) && (map->tile_at != NULL) &&
        (gg_geo_ecef_to_geodetic(ins->r_e, &lat, &lon, &h) == GG_OK)) {
        const double dlat = (double)lat;
        const double dlon = (double)lon;
        st = map->tile_at(map->ctx, GG_GMAP_KIND_TENSOR, dlat, dlon, (double)h, &tile);
    }
    if ((st == GG_OK) && (tile != NULL) && !(fabs((double)h - tile->tile.h0_m) <= tile->tile.h_range_m)) {
        st = GG_ERR_RANGE; /* the tile's height band does not hold the position */
    }
    if ((st != GG_OK) || (tile == NULL)) {
        a->health |= GG_AID_MM_H_NO_MAP;
        a->n_no_map++;
        return; /* the covariance keeps accumulating */
    }
    if (aid_mm_predict_accumulated(a) != GG_OK) {
        a->health |= GG_AID_MM_H_FAIL;
        a->n_rejected++;
        return;
    }
    a->tile = tile;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            a->ep_c_b_e[j][k] = (double)ins->c_b_e[j][k];
        }
    }
    a->ep_sin_th = (double)ins->sin_th;
    a->ep_cos_th = (double)ins->cos_th;
    a->pass = 0;
    a->remaining = 1.0;
    a->w_pass = 1.0;
    a->accepted_any = 0;
    a->phase = GG_AID_MM_PH_SPREAD;
}

static void fill_r(const gg_aid_mm_t *a, double w, double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX])
{
    int32_t j;
    int32_t k;
    for (j = 0; j < GG_UKF_NZ_MAX; ++j) {
        for (k = 0; k < GG_UKF_NZ_MAX; ++k) {
            R[j][k] = 0.0;
        }
    }
    for (j = 0; j < 6; ++j) {
        for (k = 0; k < 6; ++k) {
            R[j][k] = a->ep_r[j][k] / w;
        }
    }
}

/* The monitor's health bits for this step (aid_integ.h). */
static void integ_health(gg_aid_mm_t *a)
{
    if (a->integ.state == GG_INTEG_SUSPECT) {
        a->health |= GG_AID_MM_H_SUSPECT;
    } else if (a->integ.state == GG_INTEG_ISOLATED) {
        a->health |= GG_AID_MM_H_ISOLATED;
    } else {
        /* OK */
    }
}

/* Pass weight from the predicted spread (aid_mmukf.h, progressive passes). */
static void do_spread(gg_aid_mm_t *a)
{
    double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX];
    double spread[GG_UKF_NZ_MAX];
    double nis = 0.0;
    aid_hctx_t hc;
    gg_status_t st;
    double w;
    hc.a = a;
    fill_r(a, 1.0, R);
    st = gg_ukf_meas_spread(&a->ukf, 6, aid_mm_meas_model, &hc, spread, a->ep_z,
                            /* cppcheck-suppress misra-c2012-17.7 */
                            (const double(*)[GG_UKF_NZ_MAX])R, &nis);
    if (st != GG_OK) {
        a->health |= GG_AID_MM_H_FAIL;
        a->phase = GG_AID_MM_PH_FINISH;
        return;
    }
    if (a->pass == 0) {
        /* the epoch's test statistic: NIS with the nominal R, before any update */
        a->last_nis = nis;
        (void)gg_integ_test(&a->integ, nis); /* initialized with the aid: always GG_OK */
        if (a->integ.state == GG_INTEG_ISOLATED) {
            a->n_isolated++;
            a->phase = GG_AID_MM_PH_FINISH; /* tested, not fed: no update, no correction */
            return;
        }
    }
    w = a->remaining;
    if (a->pass < (a->cfg.max_passes - 1)) {
        int32_t k;
        for (k = 0; k < 6; ++k) {
            const double rkk = a->ep_r[k][k];
            if ((spread[k] > rkk) && ((rkk / spread[k]) < w)) {
                w = rkk / spread[k];
            }
        }
    }
    a->w_pass = w;
    a->phase = GG_AID_MM_PH_UPDATE;
}

static void do_update(gg_aid_mm_t *a)
{
    double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX];
    gg_ukf_update_info_t info;
    aid_hctx_t hc;
    gg_status_t st;
    hc.a = a;
    if (a->integ.state == GG_INTEG_SUSPECT) {
        fill_r(a, a->w_pass / GG_INTEG_DEWEIGHT_R, R); /* de-weighted while SUSPECT */
    } else {
        fill_r(a, a->w_pass, R);
    }
    st = gg_ukf_update(&a->ukf, 6, a->ep_z,
                       /* cppcheck-suppress misra-c2012-17.7 */
                       (const double(*)[GG_UKF_NZ_MAX])R, aid_mm_meas_model, &hc, &info);
    a->phase = GG_AID_MM_PH_FINISH;
    if (st != GG_OK) {
        a->health |= GG_AID_MM_H_FAIL;
    } else if (info.accepted == 0) {
        a->health |= GG_AID_MM_H_GATED;
    } else {
        if (a->pass == 0) {
            int32_t j;
            for (j = 0; j < 6; ++j) {
                a->last_innov[j] = info.innov[j];
            }
        }
        a->accepted_any = 1;
        a->remaining -= a->w_pass;
        a->pass++;
        if ((a->remaining > 1.0e-12) && (a->pass < a->cfg.max_passes)) {
            a->phase = GG_AID_MM_PH_SPREAD;
        }
    }
}

static void do_finish(gg_aid_mm_t *a, gg_aid_corr_t *corr)
{
    double zero[NXM];
    size_t j;
    (void)memset(zero, 0, sizeof zero);
    a->phase = GG_AID_MM_PH_PROPAGATE;
    a->tile = NULL;
    if (a->accepted_any != 0) {
        a->n_updates++;
    } else {
        a->n_rejected++;
    }
    /* from the epoch to this step (the mean moves with it) */
    if (aid_mm_predict_accumulated(a) != GG_OK) {
        a->health |= GG_AID_MM_H_FAIL;
        (void)gg_ukf_set_mean(&a->ukf, zero); /* the correction is lost; P stays at the epoch */
        return;
    }
    for (j = 0U; j < 3U; ++j) {
        corr->dr_i[j] = a->ukf.x[j];
        corr->dv_i[j] = a->ukf.x[3U + j];
        corr->psi_i[j] = a->ukf.x[6U + j];
        corr->dg_i[j] = 0.0;
        corr->db_w[j] = 0.0;
        corr->db_f[j] = 0.0;
        if (a->nb == GG_AID_MM_NX_DR) {
            corr->dg_i[j] = a->ukf.x[9U + j];
        }
        if (a->nx > a->nb) {
            corr->db_w[j] = a->ukf.x[(size_t)a->nb + j];
            corr->db_f[j] = a->ukf.x[(size_t)a->nb + 3U + j];
        }
    }
    corr->valid = a->accepted_any;
    (void)gg_ukf_set_mean(&a->ukf, zero);
}

gg_status_t gg_aid_mm_step(gg_aid_mm_t *a, const gg_aid_ins_t *ins, const gg_hal_map_t *map,
                           gg_aid_corr_t *corr)
{
    gg_status_t st;
    if ((a == NULL) || (ins == NULL) || (corr == NULL)) {
        return GG_ERR_NULL;
    }
    corr->valid = 0;
    if (a->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    a->health = 0U;
    if (ins_ok(ins) == 0) {
        a->health = GG_AID_MM_H_FAIL;
        return GG_ERR_RANGE;
    }
    st = aid_mm_propagate(a, ins);
    if (st != GG_OK) {
        return st;
    }
    a->steps_since_epoch += ins->n_steps;
    if (a->phase == GG_AID_MM_PH_PROPAGATE) {
        int32_t win = a->cfg.average_steps;
        if (win < 1) {
            win = 1;
        }
        /* the window: the valid samples of the last average_steps steps before the epoch, all
         * after the last correction (only this phase follows it) */
        if ((ins->z_valid != 0) && (a->steps_since_epoch > (a->cfg.update_steps - win))) {
            aid_mm_window_add(a, ins);
        }
        if (a->steps_since_epoch >= a->cfg.update_steps) {
            if (ins->z_valid != 0) {
                start_epoch(a, ins, map);
            } else {
                a->health |= GG_AID_MM_H_BAD_MEAS; /* wait for a frame of its own readings */
            }
        }
    } else if (a->phase == GG_AID_MM_PH_SPREAD) {
        do_spread(a);
    } else if (a->phase == GG_AID_MM_PH_UPDATE) {
        do_update(a);
    } else {
        do_finish(a, corr);
    }
    integ_health(a);
    return GG_OK; /* a gated or failed epoch is counted once, at its finish */
}
