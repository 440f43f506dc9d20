/* Gradient-map UKF as an aiding source of the 3-D task: error dynamics,
 * measurement model and the real-time schedule (aid_mmukf.h). */
#include "ggins/aid_mmukf.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ggins/geo.h"
#include "ggins/gmap.h"
#include "ggins/quat.h"

#define NXM GG_UKF_NX_MAX

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
        (c->bias_states > 1)) {
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

static void mat_identity(int32_t n, double m[NXM][NXM])
{
    int32_t j;
    int32_t k;
    for (j = 0; j < NXM; ++j) {
        for (k = 0; k < NXM; ++k) {
            m[j][k] = 0.0;
        }
        if (j < n) {
            m[j][j] = 1.0;
        }
    }
}

static void mat_zero(double m[NXM][NXM])
{
    (void)memset(m, 0, sizeof(double) * (size_t)NXM * (size_t)NXM);
}

/* Empty the epoch's averaging window. */
static void window_reset(gg_aid_mm_t *a)
{
    size_t j;
    size_t k;
    a->av_n = 0;
    a->av_ksum = 0.0;
    for (j = 0U; j < 3U; ++j) {
        a->av_r0[j] = 0.0;
        a->av_dr[j] = 0.0;
        a->av_rl[j] = 0.0;
        for (k = 0U; k < 3U; ++k) {
            a->av_g_e[j][k] = 0.0;
        }
        for (k = 0U; k < 6U; ++k) {
            a->av_s[j][k] = 0.0;
        }
    }
    for (j = 0U; j < 6U; ++j) {
        for (k = 0U; k < 6U; ++k) {
            a->av_ss[j][k] = 0.0;
        }
    }
}

gg_status_t gg_aid_mm_init(gg_aid_mm_t *a, const gg_aid_mm_config_t *cfg, int32_t gravity_state)
{
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
    /* cppcheck-suppress misra-c2012-17.7 */
    st = gg_ukf_init(&a->ukf, &uc, zero, (const double(*)[NXM])P0);
    if (st != GG_OK) {
        return st;
    }
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
    window_reset(a);
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

/* ---------------------------------------------------------------- dynamics */

/* The error dynamics' A h of one navigation step (aid_mmukf.h) as a sparse
 * matrix: at most 3 + 9 + 6 + 3 + 9 + 9 + 2 = 41 non-zeros in 18 x 18, so
 * products with it cost 41 n multiply-adds instead of n^3. */
#define AID_BNZ 48
typedef struct {
    int32_t n;
    int32_t r[AID_BNZ];
    int32_t c[AID_BNZ];
    double v[AID_BNZ];
} aid_sparse_t;

static void sp_add(aid_sparse_t *b, int32_t r, int32_t c, double v)
{
    if ((v != 0.0) && (b->n < AID_BNZ)) {
        b->r[b->n] = r;
        b->c[b->n] = c;
        b->v[b->n] = v;
        b->n++;
    }
}

/* B = A h with the INS quantities of this step. */
static void transition(const gg_aid_mm_t *a, const gg_aid_ins_t *ins, aid_sparse_t *b)
{
    const double h = ins->dt_s;
    const double w = ins->omega_ie;
    const double *f = ins->f_i;
    int32_t j;
    int32_t k;
    b->n = 0;
    for (j = 0; j < 3; ++j) {
        sp_add(b, j, 3 + j, h);
        for (k = 0; k < 3; ++k) {
            sp_add(b, 3 + j, k, ins->gamma_i[j][k] * h);
        }
    }
    /* -[f x] psi */
    sp_add(b, 3, 7, f[2] * h);
    sp_add(b, 3, 8, -f[1] * h);
    sp_add(b, 4, 6, -f[2] * h);
    sp_add(b, 4, 8, f[0] * h);
    sp_add(b, 5, 6, f[1] * h);
    sp_add(b, 5, 7, -f[0] * h);
    if (a->nb == GG_AID_MM_NX_DR) {
        for (j = 0; j < 3; ++j) {
            sp_add(b, 3 + j, 9 + j, h);
        }
        /* [w_ie x] dg, w_ie along z */
        sp_add(b, 9, 10, -w * h);
        sp_add(b, 10, 9, w * h);
    }
    if (a->nx > a->nb) {
        /* psi' = -C_b_i db_w, dv' = -C_b_i db_f */
        const int32_t nb = a->nb;
        for (j = 0; j < 3; ++j) {
            for (k = 0; k < 3; ++k) {
                sp_add(b, 6 + j, nb + k, -ins->c_b_i[j][k] * h);
                sp_add(b, 3 + j, nb + 3 + k, -ins->c_b_i[j][k] * h);
            }
        }
    }
}

/* o = B m (n x n used; o zeroed first) */
static void sp_mul(const aid_sparse_t *b, int32_t n, const double m[NXM][NXM], double o[NXM][NXM])
{
    int32_t e;
    int32_t k;
    mat_zero(o);
    for (e = 0; e < b->n; ++e) {
        const int32_t r = b->r[e];
        const int32_t c = b->c[e];
        const double v = b->v[e];
        for (k = 0; k < n; ++k) {
            o[r][k] += v * m[c][k];
        }
    }
}

/* o = F m with F = I + B + B^2 / 2 (its error is O((w_s h)^3), ~1e-15 at 100 Hz) */
static void f_apply(const aid_sparse_t *b, int32_t n, const double m[NXM][NXM], double o[NXM][NXM])
{
    double t1[NXM][NXM];
    double t2[NXM][NXM];
    int32_t j;
    int32_t k;
    sp_mul(b, n, m, t1);
    sp_mul(b, n, (const double(*)[NXM])t1, t2);
    for (j = 0; j < n; ++j) {
        for (k = 0; k < n; ++k) {
            o[j][k] = m[j][k] + t1[j][k] + (0.5 * t2[j][k]);
        }
    }
}

static gg_status_t propagate(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
{
    aid_sparse_t b;
    double T[NXM][NXM];
    double U[NXM][NXM];
    const int32_t n = a->nx;
    const double qv = a->cfg.q_vel_mps_rts * a->cfg.q_vel_mps_rts * ins->dt_s;
    /* angle random walk: the configured one plus the gyro's (sigma_w h per step) */
    const double qa = (a->cfg.q_att_rad_rts * a->cfg.q_att_rad_rts * ins->dt_s) +
                      (a->cfg.sigma_gyro_rps * a->cfg.sigma_gyro_rps * ins->dt_s * ins->dt_s);
    const double qg = a->cfg.q_g_mps2_rts * a->cfg.q_g_mps2_rts * ins->dt_s;
    const double qbw = a->cfg.q_gyro_bias_rps_rts * a->cfg.q_gyro_bias_rps_rts * ins->dt_s;
    const double qbf = a->cfg.q_acc_bias_mps2_rts * a->cfg.q_acc_bias_mps2_rts * ins->dt_s;
    int32_t i;
    int32_t j;
    int32_t k;
    transition(a, ins, &b);
    for (i = 0; (i < ins->n_steps) && (i < GG_LIM_AID_MM_STEPS_MAX); ++i) {
        /* Phi <- F Phi */
        f_apply(&b, n, (const double(*)[NXM])a->phi, T);
        for (j = 0; j < n; ++j) {
            for (k = 0; k < n; ++k) {
                a->phi[j][k] = T[j][k];
            }
        }
        /* Q <- F Q F^T = F (F Q)^T (Q symmetric) */
        f_apply(&b, n, (const double(*)[NXM])a->q, T);
        for (j = 0; j < n; ++j) {
            for (k = 0; k < n; ++k) {
                U[j][k] = T[k][j];
            }
        }
        f_apply(&b, n, (const double(*)[NXM])U, a->q);
        for (j = 0; j < 3; ++j) {
            a->q[3 + j][3 + j] += qv;
            a->q[6 + j][6 + j] += qa;
            if (a->nb == GG_AID_MM_NX_DR) {
                a->q[9 + j][9 + j] += qg;
            }
            if (n > a->nb) {
                a->q[a->nb + j][a->nb + j] += qbw;
                a->q[a->nb + 3 + j][a->nb + 3 + j] += qbf;
            }
        }
    }
    /* exactly symmetric */
    for (j = 0; j < n; ++j) {
        for (k = j + 1; k < n; ++k) {
            const double s = 0.5 * (a->q[j][k] + a->q[k][j]);
            a->q[j][k] = s;
            a->q[k][j] = s;
        }
    }
    return GG_OK;
}

/* UKF process model over the accumulated interval: x_out = Phi x_in. */
static gg_status_t fx_phi(void *ctx, const double *x_in, double *x_out)
{
    /* cppcheck-suppress misra-c2012-11.5 */
    const gg_aid_mm_t *a = (const gg_aid_mm_t *)ctx;
    int32_t j;
    int32_t k;
    for (j = 0; j < NXM; ++j) {
        double s = 0.0;
        if (j < a->nx) {
            for (k = 0; k < a->nx; ++k) {
                s += a->phi[j][k] * x_in[k];
            }
        }
        x_out[j] = s;
    }
    return GG_OK;
}

/* Predict through the accumulated interval, then restart the accumulation. */
static gg_status_t predict_accumulated(gg_aid_mm_t *a)
{
    /* cppcheck-suppress misra-c2012-17.7 */
    const gg_status_t st = gg_ukf_predict(&a->ukf, fx_phi, a, (const double(*)[NXM])a->q);
    if (st == GG_OK) {
        mat_identity(a->nx, a->phi);
        mat_zero(a->q);
    }
    return st;
}

/* ---------------------------------------------------------------- measurement */

gg_status_t gg_aid_mm_predict(const gg_gmap_t *tile, const gg_real_t r_e[3],
                              gg_real_t c_b_e[3][3], gg_real_t sin_th, gg_real_t cos_th,
                              const double *x, double z[6])
{
    gg_real_t dr_i[3];
    gg_real_t dr_e[3];
    gg_real_t psi_i[3];
    gg_real_t psi_e[3];
    gg_real_t r[3];
    gg_real_t dq[4];
    gg_real_t cbe[3][3];
    gg_real_t cen[3][3];
    gg_real_t gn[3][3];
    gg_real_t lat = 0.0L;
    gg_real_t lon = 0.0L;
    gg_real_t h = 0.0L;
    gg_real_t h2 = 0.0L;
    gg_gmap_sample_t smp;
    gg_status_t st;
    size_t j;
    if ((tile == NULL) || (r_e == NULL) || (c_b_e == NULL) || (x == NULL) || (z == NULL)) {
        return GG_ERR_NULL;
    }
    for (j = 0U; j < 3U; ++j) {
        dr_i[j] = (gg_real_t)x[j];
        psi_i[j] = (gg_real_t)x[6U + j];
    }
    gg_rot3(sin_th, cos_th, -1, dr_i, dr_e);
    gg_rot3(sin_th, cos_th, -1, psi_i, psi_e);
    for (j = 0U; j < 3U; ++j) {
        r[j] = r_e[j] + dr_e[j];
    }
    st = gg_quat_from_rotvec(psi_e, dq);
    if (st == GG_OK) {
        gg_real_t dc[3][3];
        gg_quat_to_dcm(dq, dc);
        gg_mat3_mul(dc, c_b_e, cbe);
        st = gg_geo_ecef_to_geodetic(r, &lat, &lon, &h);
    }
    if (st == GG_OK) {
        st = gg_geo_local_frame(r, &h2, cen);
    }
    if (st == GG_OK) {
        st = gg_gmap_eval(tile, lat, lon, h,
                          /* MISRA 12.2: false positive on the constant mask macros */
                          /* cppcheck-suppress misra-c2012-12.2 */
                          GG_GMAP_MASK_ALL | GG_GMAP_H_EXTRAPOLATE, 0, &smp);
    }
    if (st == GG_OK) {
        st = gg_gmap_to_matrix(smp.gamma, gn);
    }
    if (st == GG_OK) {
        /* Gamma_b = C_n_b Gamma_n C_b_n, C_b_n = C_e_n C_b_e */
        gg_real_t cbn[3][3];
        gg_real_t cnb[3][3];
        gg_real_t gb[3][3];
        gg_mat3_mul(cen, cbe, cbn);
        gg_mat3_transpose(cbn, cnb);
        {
            gg_mat3_t gm;
            const gg_mat3_t *gp = &gm;
            gg_mat3_copy(gn, &gm);
            gg_mat3_similarity(cnb, gp->m, gb);
        }
        z[0] = (double)gb[0][0];
        z[1] = (double)gb[1][1];
        z[2] = (double)gb[2][2];
        z[3] = (double)gb[0][1];
        z[4] = (double)gb[0][2];
        z[5] = (double)gb[1][2];
    }
    return st;
}

typedef struct {
    const gg_aid_mm_t *a;
} aid_hctx_t;

static gg_status_t aid_meas_model(void *ctx, const double *x, double *z)
{
    /* cppcheck-suppress misra-c2012-11.5 */
    const aid_hctx_t *hc = (const aid_hctx_t *)ctx;
    const gg_aid_mm_t *a = hc->a;
    gg_real_t c[3][3];
    gg_real_t r[3];
    gg_status_t st;
    size_t j;
    size_t k;
    int two = 0;
    if ((a->ep_dq[0] != 0.0) || (a->ep_dq[1] != 0.0) || (a->ep_dq[2] != 0.0)) {
        two = 1;
    }
    double xm[GG_UKF_NX_MAX];
    /* the window's mean position error: dr - tau dv (the error state is the epoch's) */
    for (j = 0U; j < (size_t)GG_UKF_NX_MAX; ++j) {
        xm[j] = x[j];
    }
    for (j = 0U; j < 3U; ++j) {
        xm[j] = x[j] - (a->ep_tau_s * x[3U + j]);
    }
    for (j = 0U; j < 3U; ++j) {
        r[j] = (gg_real_t)(a->ep_r_e[j] - a->ep_dq[j]);
        if (two == 0) {
            r[j] = (gg_real_t)a->ep_r_e[j];
        }
        for (k = 0U; k < 3U; ++k) {
            c[j][k] = (gg_real_t)a->ep_c_b_e[j][k];
        }
    }
    st = gg_aid_mm_predict(a->tile, r, c, (gg_real_t)a->ep_sin_th, (gg_real_t)a->ep_cos_th, xm, z);
    if ((st == GG_OK) && (two != 0)) {
        /* the window's mean of the field along its track: two-point Gauss-Legendre (exact for
         * a field cubic along a straight track flown at constant speed) */
        double z2[GG_UKF_NZ_MAX];
        for (j = 0U; j < 3U; ++j) {
            r[j] = (gg_real_t)(a->ep_r_e[j] + a->ep_dq[j]);
        }
        st = gg_aid_mm_predict(a->tile, r, c, (gg_real_t)a->ep_sin_th, (gg_real_t)a->ep_cos_th, xm, z2);
        for (j = 0U; (j < 6U) && (st == GG_OK); ++j) {
            z[j] = 0.5 * (z[j] + z2[j]);
        }
    }
    if ((st == GG_OK) && (a->nx > a->nb)) {
        /* the gyro bias left in the [w x]^2 removal: sum_i db_w,i S_i (window mean, body axes) */
        const size_t nb = (size_t)a->nb;
        for (j = 0U; j < 6U; ++j) {
            for (k = 0U; k < 3U; ++k) {
                z[j] += x[nb + k] * a->ep_sb[k][j];
            }
        }
    }
    return st;
}

/* ---------------------------------------------------------------- epoch average */

/* The six independent components (xx, yy, zz, xy, xz, yz) of a symmetric matrix. */
static void sym_vec6(const double m[3][3], double v[6])
{
    v[0] = m[0][0];
    v[1] = m[1][1];
    v[2] = m[2][2];
    v[3] = 0.5 * (m[0][1] + m[1][0]);
    v[4] = 0.5 * (m[0][2] + m[2][0]);
    v[5] = 0.5 * (m[1][2] + m[2][1]);
}

/* o = c m c^T (3 x 3, double) */
static void sim3(const double c[3][3], const double m[3][3], double o[3][3])
{
    double t[3][3];
    size_t j;
    size_t k;
    size_t l;
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            double sum = 0.0;
            for (l = 0U; l < 3U; ++l) {
                sum += c[j][l] * m[l][k];
            }
            t[j][k] = sum;
        }
    }
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            double sum = 0.0;
            for (l = 0U; l < 3U; ++l) {
                sum += t[j][l] * c[k][l];
            }
            o[j][k] = sum;
        }
    }
}

/* The six-component map of X -> c X c^T on symmetric matrices: column m is
 * the image of the m-th basis matrix (E_jj, or E_jk + E_kj off the diagonal,
 * so that X = sum of its six components times the basis). */
static void sym_map6(const double c[3][3], double t6[NXM][NXM])
{
    static const size_t rj[6] = {0U, 1U, 2U, 0U, 0U, 1U};
    static const size_t rk[6] = {0U, 1U, 2U, 1U, 2U, 2U};
    size_t m;
    size_t j;
    for (m = 0U; m < 6U; ++m) {
        double e[3][3] = {{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}};
        double o[3][3];
        double v[6];
        e[rj[m]][rk[m]] = 1.0;
        e[rk[m]][rj[m]] = 1.0;
        sim3(c, (const double(*)[3])e, o);
        sym_vec6((const double(*)[3])o, v);
        for (j = 0U; j < 6U; ++j) {
            t6[j][m] = v[j];
        }
    }
}

/* Add this step's sample to the epoch's window, in ECEF axes (the map's
 * frame, where the field does not turn with the body): the tensor
 * C_b_e Gamma_b C_e_b with the estimated attitude, the position, and the
 * sensitivities of the [w x]^2 removal to the rate (Gao eqs. 28-30):
 * d[w x]^2 = sum_i dw_i S_i, S_i = e_i w^T + w e_i^T - 2 w_i I. */
static void window_add(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
{
    double c[3][3];
    double gb[3][3];
    double ge[3][3];
    size_t j;
    size_t k;
    for (j = 0U; j < 3U; ++j) {
        if (a->av_n == 0) {
            a->av_r0[j] = (double)ins->r_e[j];
        }
        a->av_rl[j] = (double)(ins->r_e[j] - (gg_real_t)a->av_r0[j]);
        a->av_dr[j] += a->av_rl[j];
        for (k = 0U; k < 3U; ++k) {
            c[j][k] = (double)ins->c_b_e[j][k];
        }
    }
    gb[0][0] = ins->z_b[0];
    gb[1][1] = ins->z_b[1];
    gb[2][2] = ins->z_b[2];
    gb[0][1] = ins->z_b[3];
    gb[1][0] = ins->z_b[3];
    gb[0][2] = ins->z_b[4];
    gb[2][0] = ins->z_b[4];
    gb[1][2] = ins->z_b[5];
    gb[2][1] = ins->z_b[5];
    sim3((const double(*)[3])c, (const double(*)[3])gb, ge);
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            a->av_g_e[j][k] += ge[j][k];
        }
    }
    if (ins->w_gyro != 0) {
        for (size_t i = 0U; i < 3U; ++i) {
            double si[3][3];
            double se[3][3];
            double v[6];
            for (j = 0U; j < 3U; ++j) {
                for (k = 0U; k < 3U; ++k) {
                    double e_j = (j == i) ? 1.0 : 0.0;
                    double e_k = (k == i) ? 1.0 : 0.0;
                    si[j][k] = (e_j * ins->w_b[k]) + (ins->w_b[j] * e_k);
                }
                si[j][j] -= 2.0 * ins->w_b[i];
            }
            sim3((const double(*)[3])c, (const double(*)[3])si, se);
            sym_vec6((const double(*)[3])se, v);
            for (j = 0U; j < 6U; ++j) {
                a->av_s[i][j] += v[j];
                for (k = 0U; k < 6U; ++k) {
                    a->av_ss[j][k] += v[j] * v[k];
                }
            }
        }
    }
    a->av_ksum += (double)a->steps_since_epoch;
    a->av_n++;
}

/* The epoch's measurement and R from the window (n samples):
 *   z = C_e_b Gamma_e,mean C_b_e with the epoch's attitude; its model is the
 *     map at the window's mean position (the field is linear over the few
 *     hundred metres flown), the attitude error psi being common to the
 *     window (C_b_e,est = (I - [psi x]) C_b_e,true at every step);
 *   R = the gradiometer's white noise / n + the map's
 *     + sigma_w^2 / n^2 sum_k sum_i s_ik s_ik^T   (white rate noise)
 *     + sigma_b^2 sum_i s_i,mean s_i,mean^T       (rate bias, one per axis)
 *   in body axes, and the second-order part of the removal, E[[dw x]^2] =
 *   -2 sigma_w^2 I, taken out of the diagonal. */
static void window_epoch(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
{
    double cbe[3][3];
    double ceb[3][3];
    const double n = (double)a->av_n;
    const double sw2 = a->cfg.sigma_gyro_rps * a->cfg.sigma_gyro_rps;
    double sb2 = a->cfg.sigma_gyro_bias_rps * a->cfg.sigma_gyro_bias_rps;
    const double sm = a->cfg.sigma_meas_s2;
    const double rdb = a->cfg.sigma_db_s2 * a->cfg.sigma_db_s2;
    double ratio = a->cfg.offdiag_ratio;
    size_t j;
    size_t k;
    if (!(ratio > 0.0)) {
        ratio = 1.0;
    }
    if (a->nx > a->nb) {
        sb2 = 0.0; /* the bias is a state, in the measurement model */
    }
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            cbe[j][k] = (double)ins->c_b_e[j][k];
            ceb[k][j] = cbe[j][k];
        }
    }
    (void)memset(a->ep_sb, 0, sizeof a->ep_sb);
    if ((ins->w_gyro != 0) && (a->av_n > 0)) {
        /* the window's mean rate sensitivities S_i, ECEF -> the epoch's body axes */
        double t6[NXM][NXM];
        size_t i;
        sym_map6((const double(*)[3])ceb, t6);
        for (i = 0U; i < 3U; ++i) {
            for (j = 0U; j < 6U; ++j) {
                double sum = 0.0;
                for (k = 0U; k < 6U; ++k) {
                    sum += t6[j][k] * (a->av_s[i][k] / n);
                }
                a->ep_sb[i][j] = sum;
            }
        }
    }
    for (j = 0U; j < 3U; ++j) {
        a->ep_dq[j] = 0.0;
    }
    a->ep_tau_s = 0.0;
    if (a->av_n > 0) {
        a->ep_tau_s = ((double)a->steps_since_epoch - (a->av_ksum / n)) * ins->dt_s;
    }
    if (a->av_n <= 1) {
        /* the epoch's own sample, as measured */
        for (j = 0U; j < 3U; ++j) {
            a->ep_r_e[j] = (double)ins->r_e[j];
        }
        for (j = 0U; j < 6U; ++j) {
            a->ep_z[j] = ins->z_b[j];
        }
    } else {
        double gm[3][3];
        double gbm[3][3];
        /* n samples evenly spaced over the track r0 .. r0 + rl: their positions' standard deviation
         * is |rl| / 2 sqrt((n + 1) / (3 (n - 1))), the Gauss-Legendre nodes sit at the mean +- it */
        const double sd = 0.5 * sqrt((n + 1.0) / (3.0 * (n - 1.0)));
        for (j = 0U; j < 3U; ++j) {
            a->ep_dq[j] = sd * a->av_rl[j];
            a->ep_r_e[j] = a->av_r0[j] + (a->av_dr[j] / n);
            for (k = 0U; k < 3U; ++k) {
                gm[j][k] = a->av_g_e[j][k] / n;
            }
        }
        sim3((const double(*)[3])ceb, (const double(*)[3])gm, gbm);
        sym_vec6((const double(*)[3])gbm, a->ep_z);
    }
    if (ins->w_gyro != 0) {
        for (j = 0U; j < 3U; ++j) {
            a->ep_z[j] += 2.0 * sw2;
        }
    }
    /* R: white gradiometer noise and the map */
    (void)memset(a->ep_r, 0, sizeof a->ep_r);
    for (j = 0U; j < 3U; ++j) {
        a->ep_r[j][j] = ((sm * sm) / n) + rdb;
        a->ep_r[3U + j][3U + j] = (((ratio * sm) * (ratio * sm)) / n) + rdb;
    }
    if ((ins->w_gyro != 0) && ((sw2 > 0.0) || (sb2 > 0.0))) {
        double t6[NXM][NXM];
        double ss[NXM][NXM];
        /* the rate terms, ECEF -> body axes of the epoch */
        for (j = 0U; j < 6U; ++j) {
            for (k = 0U; k < 6U; ++k) {
                double sum = (sw2 / (n * n)) * a->av_ss[j][k];
                for (size_t i = 0U; i < 3U; ++i) {
                    sum += (sb2 / (n * n)) * a->av_s[i][j] * a->av_s[i][k];
                }
                ss[j][k] = sum;
            }
        }
        /* T S T^T, T the map of X -> C_e_b X C_b_e on the six components */
        sym_map6((const double(*)[3])ceb, t6);
        /* cppcheck-suppress misra-c2012-17.7 */
        if (gg_ukf_congruence(6, (const double(*)[NXM])t6, (const double(*)[NXM])ss, ss) == GG_OK) {
            for (j = 0U; j < 6U; ++j) {
                for (k = 0U; k < 6U; ++k) {
                    a->ep_r[j][k] += 0.5 * (ss[j][k] + ss[k][j]);
                }
            }
        } else {
            a->health |= GG_AID_MM_H_FAIL;
        }
    }
    a->last_n_avg = a->av_n;
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
        if (!GG_ISFINITE(ins->r_e[j]) || !GG_ISFINITE(ins->f_i[j])) {
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
    window_epoch(a, ins);
    window_reset(a);
    a->steps_since_epoch = 0;
    if ((map != NULL) && (map->tile_at != NULL) &&
        (gg_geo_ecef_to_geodetic(ins->r_e, &lat, &lon, &h) == GG_OK)) {
        const double dlat = (double)lat;
        const double dlon = (double)lon;
        st = map->tile_at(map->ctx, GG_GMAP_KIND_TENSOR, dlat, dlon, &tile);
    }
    if ((st != GG_OK) || (tile == NULL)) {
        a->health |= GG_AID_MM_H_NO_MAP;
        a->n_no_map++;
        return; /* the covariance keeps accumulating */
    }
    if (predict_accumulated(a) != GG_OK) {
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
    st = gg_ukf_meas_spread(&a->ukf, 6, aid_meas_model, &hc, spread, a->ep_z,
                            /* cppcheck-suppress misra-c2012-17.7 */
                            (const double(*)[GG_UKF_NZ_MAX])R, &nis);
    if (st != GG_OK) {
        a->health |= GG_AID_MM_H_FAIL;
        a->phase = GG_AID_MM_PH_FINISH;
        return;
    }
    if (a->pass == 0) {
        a->last_nis = nis;
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
    fill_r(a, a->w_pass, R);
    st = gg_ukf_update(&a->ukf, 6, a->ep_z,
                       /* cppcheck-suppress misra-c2012-17.7 */
                       (const double(*)[GG_UKF_NZ_MAX])R, aid_meas_model, &hc, &info);
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
    if (predict_accumulated(a) != GG_OK) {
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
    st = propagate(a, ins);
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
            window_add(a, ins);
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
    return GG_OK; /* a gated or failed epoch is counted once, at its finish */
}
