/* Gravity-gradient map matching UKF (see mmukf.h). */
/* MISRA notes (inline suppressions below): 17.7 is a cppcheck 2.10 false positive on the
 * array-pointer casts (const double(*)[N]) (every returned status is checked); 9.3 is the
 * false positive on whole-struct copies also noted for nav2d.c; 15.4 (advisory): the
 * progressive-update loop leaves at its first failure from several places, each of which
 * records the cause in health first - a flag would need every later statement guarded. */
#include "ggins/mmukf.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ggins/ggmath.h"
#include "ggins/quat.h"
#include "mmukf_int.h"

/* the six independent components (xx yy zz xy xz yz, Gao eq. 31 order) of a symmetric matrix */
static void sym6(double m[3][3], double v[6]) /* not const: C11 cannot pass a double[3][3] as const */
{
    v[0] = m[0][0];
    v[1] = m[1][1];
    v[2] = m[2][2];
    v[3] = m[0][1];
    v[4] = m[0][2];
    v[5] = m[1][2];
}

gg_status_t gg_mm_predict_gradient(const gg_gmap_t *map, const gg_mm_nav_t *x, double g6[6])
{
    if ((map == NULL) || (x == NULL) || (g6 == NULL)) {
        return GG_ERR_NULL;
    }
    gg_gmap_sample_t smp;
    const gg_status_t st = gg_gmap_eval(map, (gg_real_t)x->lat, (gg_real_t)x->lon, (gg_real_t)x->h,
                                        /* MISRA 12.2: false positive on the constant mask macros */
                                        /* cppcheck-suppress misra-c2012-12.2 */
                                        GG_GMAP_MASK_ALL | GG_GMAP_H_EXTRAPOLATE, 0, &smp);
    if (st != GG_OK) {
        return st;
    }
    gg_mat3_t gn;
    const gg_mat3_t *gnp = &gn;
    gg_real_t q[4];
    gg_real_t C[3][3];
    gg_real_t Ct[3][3];
    gg_real_t gb[3][3];
    double Gb[3][3];
    (void)gg_gmap_to_matrix(smp.gamma, gn.m);
    for (int k = 0; k < 4; ++k) {
        q[k] = (gg_real_t)x->q[k];
    }
    gg_quat_to_dcm(q, C); /* C_b_n; Gamma_b = C^T Gamma_n C (Gao eq. 30 / A4) */
    gg_mat3_transpose(C, Ct);
    gg_mat3_similarity(Ct, gnp->m, gb);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            Gb[i][j] = (double)gb[i][j];
        }
    }
    sym6(Gb, g6);
    return GG_OK;
}

static gg_status_t cfg_ok(const gg_mm_config_t *c)
{
    const double v[] = {c->dt_s, c->update_period_s, c->sigma_meas_s2, c->sigma_db_s2,
                        c->sig0_att_rad, c->sig0_vel_mps, c->sig0_pos_m, c->sig0_bg_rps,
                        c->sig0_ba_mps2, c->arw_rad_rts, c->vrw_mps_rts, c->bg_rw, c->ba_rw,
                        c->lambda, c->gate_nis, c->offdiag_ratio};
    for (size_t k = 0; k < (sizeof(v) / sizeof(v[0])); ++k) {
        if (!GG_ISFINITE(v[k]) || (v[k] < 0.0)) {
            return GG_ERR_CONFIG;
        }
    }
    if ((c->dt_s <= 0.0) || (c->dt_s > GG_LIM_MM_DT_MAX_S) || (c->update_period_s < c->dt_s) ||
        ((c->sigma_meas_s2 + c->sigma_db_s2) <= 0.0) || (c->sig0_att_rad <= 0.0) ||
        (c->sig0_att_rad > 0.5) || (c->sig0_vel_mps <= 0.0) || (c->sig0_pos_m <= 0.0) ||
        (c->sig0_bg_rps <= 0.0) || (c->sig0_ba_mps2 <= 0.0) || (mm_nav_ok(&c->init) == 0) ||
        (c->max_passes < 1) || (c->max_passes > GG_MM_MAX_PASSES) || (c->offdiag_ratio > GG_LIM_MM_OFFDIAG_MAX)) {
        return GG_ERR_CONFIG;
    }
    return GG_OK;
}

/* sigma states = nominal (+) chi_i, from freshly drawn UKF sigma points */
static gg_status_t redraw(gg_mm_t *st, const gg_mm_nav_t *nominal, gg_mm_nav_t sig[GG_MM_NSIG])
{
    int32_t ns = 0;
    gg_status_t s = gg_ukf_sigma_points(&st->ukf, &ns);
    if (s != GG_OK) {
        return s;
    }
    for (int32_t i = 0; i < ns; ++i) {
        s = mm_apply(nominal, st->ukf.chi[i], &sig[i]);
        if (s != GG_OK) {
            return s;
        }
    }
    return GG_OK;
}

gg_status_t gg_mm_init(gg_mm_t *st, const gg_mm_config_t *cfg, const gg_gmap_t *map)
{
    if ((st == NULL) || (cfg == NULL)) {
        return GG_ERR_NULL;
    }
    gg_status_t s = cfg_ok(cfg);
    if (s != GG_OK) {
        return s;
    }
    if ((map != NULL) && ((map->initialized == 0) || ((map->tile.flags & GG_GMAP_ANOMALY) != 0u))) {
        return GG_ERR_CONFIG; /* the filter needs a TOTAL-field tile */
    }
    double zero[GG_UKF_NX_MAX];
    double P0[GG_UKF_NX_MAX][GG_UKF_NX_MAX];
    (void)memset(zero, 0, sizeof zero);
    (void)memset(P0, 0, sizeof P0);
    const double sd[5] = {cfg->sig0_att_rad, cfg->sig0_vel_mps, cfg->sig0_pos_m, cfg->sig0_bg_rps,
                          cfg->sig0_ba_mps2};
    for (int k = 0; k < GG_MM_NX; ++k) {
        P0[k][k] = sd[k / 3] * sd[k / 3];
    }
    gg_ukf_t u;
    const gg_ukf_config_t uc = {GG_MM_NX, cfg->lambda, cfg->gate_nis};
    /* cppcheck-suppress misra-c2012-17.7 */
    s = gg_ukf_init(&u, &uc, zero, (const double(*)[GG_UKF_NX_MAX])P0);
    if (s != GG_OK) {
        return s;
    }
    (void)memset(st, 0, sizeof *st);
    st->ukf = u;
    st->cfg = *cfg;
    st->map = map;
    st->h_hold = cfg->init.h;
    st->vd_hold = cfg->init.v[2];
    s = redraw(st, &cfg->init, st->sig);
    if (s != GG_OK) {
        return s;
    }
    st->initialized = 1;
    return GG_OK;
}

typedef struct {
    const gg_gmap_t *map;
    const gg_mm_nav_t *nominal;
    const gg_mm_meas_t *meas;
    int off_map;
} hctx_t;

/* six components (xx yy zz xy xz yz) of [a x]^2 = a a^T - |a|^2 I */
static void cross2_6(const double a[3], double c6[6])
{
    const double n2 = (a[0] * a[0]) + (a[1] * a[1]) + (a[2] * a[2]);
    double m[3][3];
    for (int j = 0; j < 3; ++j) {
        for (int k = 0; k < 3; ++k) {
            m[j][k] = (a[j] * a[k]) - ((j == k) ? n2 : 0.0);
        }
    }
    sym6(m, c6);
}

/* the gradiometer's [w x]^2 removal with the gyro reading w (mmukf.h,
 * gyro_term): z gets [w x]^2 - [(w - b_g) x]^2 */
static void gyro_term(const gg_mm_meas_t *m, const double bg[3], double z[6])
{
    double u[3];
    double cw[6];
    double cu[6];
    for (int j = 0; j < 3; ++j) {
        u[j] = m->omega_b[j] - bg[j];
    }
    cross2_6(m->omega_b, cw);
    cross2_6(u, cu);
    for (int k = 0; k < 6; ++k) {
        z[k] += cw[k] - cu[k];
    }
}

/* R share of the rate noise n ~ N(0, s^2 I) in the removal: the error
 * [W x][n x] + [n x][W x] = W n^T + n W^T - 2 (W.n) I, linear in n:
 * R += s^2 sum_i S(e_i) S(e_i)^T (full 6 x 6) */
static void gyro_noise_r(const double w[3], double s, double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX])
{
    for (int i = 0; i < 3; ++i) {
        double S[3][3];
        double s6[6];
        for (int j = 0; j < 3; ++j) {
            for (int k = 0; k < 3; ++k) {
                const double ej = (j == i) ? 1.0 : 0.0;
                const double ek = (k == i) ? 1.0 : 0.0;
                S[j][k] = (w[j] * ek) + (ej * w[k]) - ((j == k) ? (2.0 * w[i]) : 0.0);
            }
        }
        sym6(S, s6);
        for (int a = 0; a < 6; ++a) {
            for (int b = 0; b < 6; ++b) {
                R[a][b] += (s * s) * (s6[a] * s6[b]); /* exactly symmetric (ukf.c checks) */
            }
        }
    }
}

static gg_status_t meas_model(void *ctx, const double *x, double *z)
{
    /* MISRA 11.5 deviation: the UKF's model context is a void pointer by design (ukf.h); here it
     * is always the hctx_t built by update_epoch. */
    /* cppcheck-suppress misra-c2012-11.5 */
    hctx_t *c = (hctx_t *)ctx;
    gg_mm_nav_t s;
    gg_status_t st = mm_apply(c->nominal, x, &s);
    if (st != GG_OK) {
        return st;
    }
    st = gg_mm_predict_gradient(c->map, &s, z);
    if (st == GG_ERR_RANGE) {
        c->off_map = 1;
    }
    if ((st == GG_OK) && (c->meas->gyro_term != 0)) {
        gyro_term(c->meas, s.bg, z);
    }
    return st;
}

static void fill_out(const gg_mm_t *st, int32_t updated, double nis, gg_mm_output_t *out)
{
    out->nav = st->sig[0];
    for (int i = 0; i < GG_MM_NX; ++i) {
        out->sigma[i] = gg_sqrt_d(st->ukf.P[i][i]);
        for (int j = 0; j < GG_MM_NX; ++j) {
            out->P[i][j] = st->ukf.P[i][j];
        }
    }
    out->t_s = st->t_s;
    out->updated = updated;
    out->nis = nis;
    out->health = st->health;
    out->n_updates = st->n_updates;
    out->n_gated = st->n_gated;
    out->n_offmap = st->n_offmap;
    out->n_fail = st->n_fail;
}

/* Measurement epoch: recombine the propagated sigma states, update, inject, redraw. */
static void update_epoch(gg_mm_t *st, const gg_mm_meas_t *meas, int32_t *updated, double *nis)
{
    const double T = st->t_since_update_s;
    /* cppcheck-suppress misra-c2012-9.3 */
    const gg_mm_nav_t nominal0 = st->sig[0];
    gg_mm_nav_t nominal = nominal0;
    int ok = 1;
    for (int32_t i = 0; (i < GG_MM_NSIG) && (ok != 0); ++i) {
        if (gg_mm_error(&st->sig[i], &nominal0, st->ukf.chi[i]) != GG_OK) {
            ok = 0;
        }
    }
    double Q[GG_UKF_NX_MAX][GG_UKF_NX_MAX];
    (void)memset(Q, 0, sizeof Q);
    const double q[5] = {st->cfg.arw_rad_rts * st->cfg.arw_rad_rts * T,
                         st->cfg.vrw_mps_rts * st->cfg.vrw_mps_rts * T, 0.0,
                         st->cfg.bg_rw * st->cfg.bg_rw * T, st->cfg.ba_rw * st->cfg.ba_rw * T};
    for (int k = 0; k < GG_MM_NX; ++k) {
        Q[k][k] = q[k / 3];
    }
    double zero[GG_UKF_NX_MAX];
    (void)memset(zero, 0, sizeof zero);
    /* cppcheck-suppress misra-c2012-17.7 */
    if ((ok == 0) || (gg_ukf_predict_finish(&st->ukf, (const double(*)[GG_UKF_NX_MAX])Q) != GG_OK)) {
        st->health |= GG_MM_H_UKF_FAIL;
        st->n_fail++;
    } else {
        /* inject the predicted mean, so the update is linearised about it */
        gg_mm_nav_t injected;
        if (mm_apply(&nominal0, st->ukf.x, &injected) == GG_OK) {
            nominal = injected;
        } else {
            st->health |= GG_MM_H_UKF_FAIL;
            st->n_fail++;
        }
        (void)gg_ukf_set_mean(&st->ukf, zero);
    }
    if ((meas != NULL) && (st->map != NULL) && ((st->health & GG_MM_H_UKF_FAIL) == 0u)) {
        double R[GG_UKF_NZ_MAX][GG_UKF_NZ_MAX];
        (void)memset(R, 0, sizeof R);
        /* R per component: diagonal (xx, yy, zz), off-diagonal (xy, xz, yz) */
        const double ratio = (st->cfg.offdiag_ratio > 0.0) ? st->cfg.offdiag_ratio : 1.0;
        const double sm_off = ratio * st->cfg.sigma_meas_s2;
        const double rdb = st->cfg.sigma_db_s2 * st->cfg.sigma_db_s2;
        const double rk[6] = {(st->cfg.sigma_meas_s2 * st->cfg.sigma_meas_s2) + rdb,
                              (st->cfg.sigma_meas_s2 * st->cfg.sigma_meas_s2) + rdb,
                              (st->cfg.sigma_meas_s2 * st->cfg.sigma_meas_s2) + rdb,
                              (sm_off * sm_off) + rdb, (sm_off * sm_off) + rdb, (sm_off * sm_off) + rdb};
        /* progressive update: pass k uses R / w_k with sum w_k = 1 (for a linear
         * model exactly one update with R: the information adds up); w_k is
         * chosen so that R / w_k equals the largest predicted measurement
         * spread, i.e. each pass at most about halves the variance along the
         * measured directions and the next pass is linearised about the new
         * estimate (sigma points redrawn). max_passes = 1: Gao's single update. */
        double remaining = 1.0;
        int32_t accepted_any = 0;
        /* cppcheck-suppress misra-c2012-15.4 */
        for (int32_t pass = 0; pass < st->cfg.max_passes; ++pass) {
            if (!(remaining > 0.0)) {
                break;
            }
            hctx_t hc = {st->map, &nominal, meas, 0};
            double spread[GG_UKF_NZ_MAX];
            double nis0 = 0.0;
            (void)memset(R, 0, sizeof R);
            for (int k = 0; k < 6; ++k) {
                R[k][k] = rk[k];
            }
            if (meas->gyro_term != 0) {
                double wn[3];
                for (int j = 0; j < 3; ++j) {
                    wn[j] = meas->omega_b[j] - nominal.bg[j];
                }
                gyro_noise_r(wn, meas->sigma_omega_rps, R);
            }
            double w = remaining;
            const gg_status_t s0 = gg_ukf_meas_spread(&st->ukf, 6, meas_model, &hc, spread, meas->gamma_b,
                                                      /* cppcheck-suppress misra-c2012-17.7 */
                                                      (const double(*)[GG_UKF_NZ_MAX])R, &nis0);
            if (s0 != GG_OK) {
                if (hc.off_map != 0) {
                    st->health |= GG_MM_H_OFF_MAP;
                    st->n_offmap++;
                } else {
                    st->health |= GG_MM_H_UKF_FAIL;
                    st->n_fail++;
                }
                break;
            }
            if (pass == 0) {
                *nis = nis0; /* the NIS of a single update with R (consistency statistic) */
            }
            if (pass < (st->cfg.max_passes - 1)) {
                /* the component whose spread exceeds its R the most sets w */
                for (int k = 0; k < 6; ++k) {
                    if ((spread[k] > R[k][k]) && ((R[k][k] / spread[k]) < w)) {
                        w = R[k][k] / spread[k];
                    }
                }
            }
            for (int k = 0; k < 6; ++k) {
                for (int l = 0; l < 6; ++l) {
                    R[k][l] = R[k][l] / w;
                }
            }
            gg_ukf_update_info_t info;
            const gg_status_t s = gg_ukf_update(&st->ukf, 6, meas->gamma_b,
                                                /* cppcheck-suppress misra-c2012-17.7 */
                                                (const double(*)[GG_UKF_NZ_MAX])R, meas_model, &hc, &info);
            if (s != GG_OK) {
                if (hc.off_map != 0) {
                    st->health |= GG_MM_H_OFF_MAP;
                    st->n_offmap++;
                } else {
                    st->health |= GG_MM_H_UKF_FAIL;
                    st->n_fail++;
                }
                break;
            }
            if (info.accepted == 0) {
                st->health |= GG_MM_H_GATED;
                st->n_gated++;
                break;
            }
            accepted_any = 1;
            gg_mm_nav_t injected;
            if (mm_apply(&nominal, st->ukf.x, &injected) != GG_OK) {
                st->health |= GG_MM_H_UKF_FAIL;
                st->n_fail++;
                break;
            }
            nominal = injected;
            (void)gg_ukf_set_mean(&st->ukf, zero);
            remaining -= w;
            if (remaining < 1.0e-12) {
                remaining = 0.0;
            }
        }
        if (accepted_any != 0) {
            st->n_updates++;
            *updated = 1;
        }
    }
    /* reset the mean (already injected), redraw the sigma states */
    (void)gg_ukf_set_mean(&st->ukf, zero);
    gg_mm_nav_t sig[GG_MM_NSIG];
    if (redraw(st, &nominal, sig) == GG_OK) {
        (void)memcpy(st->sig, sig, sizeof sig);
    } else {
        st->health |= GG_MM_H_UKF_FAIL;
        st->n_fail++;
        for (int32_t i = 0; i < GG_MM_NSIG; ++i) {
            st->sig[i] = nominal;
        }
    }
    st->t_since_update_s = 0.0;
}

gg_status_t gg_mm_step(gg_mm_t *st, const gg_mm_imu_t *imu, const gg_mm_meas_t *meas,
                       gg_mm_output_t *out)
{
    if ((st == NULL) || (imu == NULL) || (out == NULL)) {
        return GG_ERR_NULL;
    }
    if (st->initialized == 0) {
        return GG_ERR_NOT_INIT;
    }
    for (int k = 0; k < 3; ++k) {
        if (!GG_ISFINITE(imu->omega_b[k]) || !GG_ISFINITE(imu->f_b[k]) || (imu->omega_b[k] > GG_LIM_MM_W_MAX_RPS) ||
            (imu->omega_b[k] < -GG_LIM_MM_W_MAX_RPS) || (imu->f_b[k] > GG_LIM_MM_F_MAX_MPS2) ||
            (imu->f_b[k] < -GG_LIM_MM_F_MAX_MPS2)) {
            st->health = GG_MM_H_BAD_INPUT;
            return GG_ERR_RANGE;
        }
    }
    if (meas != NULL) {
        for (int k = 0; k < 6; ++k) {
            if (!GG_ISFINITE(meas->gamma_b[k]) || (meas->gamma_b[k] > GG_LIM_MM_GAMMA_MAX_S2) ||
                (meas->gamma_b[k] < -GG_LIM_MM_GAMMA_MAX_S2)) {
                st->health = GG_MM_H_BAD_INPUT;
                return GG_ERR_RANGE;
            }
        }
        if ((meas->gyro_term < 0) || (meas->gyro_term > 1) || !GG_ISFINITE(meas->sigma_omega_rps) ||
            (meas->sigma_omega_rps < 0.0) || (meas->sigma_omega_rps > 1.0)) {
            st->health = GG_MM_H_BAD_INPUT;
            return GG_ERR_RANGE;
        }
        for (int k = 0; k < 3; ++k) {
            if ((meas->gyro_term != 0) && (!GG_ISFINITE(meas->omega_b[k]) || (meas->omega_b[k] > GG_LIM_MM_W_MAX_RPS) ||
                                           (meas->omega_b[k] < -GG_LIM_MM_W_MAX_RPS))) {
                st->health = GG_MM_H_BAD_INPUT;
                return GG_ERR_RANGE;
            }
        }
    }
    gg_mm_nav_t sig[GG_MM_NSIG];
    for (int32_t i = 0; i < GG_MM_NSIG; ++i) {
        sig[i] = st->sig[i];
        const gg_status_t s = gg_mm_mech(&sig[i], imu, st->cfg.dt_s, st->cfg.vertical_hold,
                                         st->h_hold, st->vd_hold);
        if (s != GG_OK) {
            st->health = GG_MM_H_UKF_FAIL;
            return s;
        }
    }
    (void)memcpy(st->sig, sig, sizeof sig);
    st->health = 0u;
    st->t_s += st->cfg.dt_s;
    st->t_since_update_s += st->cfg.dt_s;
    int32_t updated = 0;
    double nis = 0.0;
    if ((meas != NULL) && (st->t_since_update_s >= (st->cfg.update_period_s - (0.5 * st->cfg.dt_s)))) {
        update_epoch(st, meas, &updated, &nis);
        st->last_nis = nis;
    }
    fill_out(st, updated, nis, out);
    return GG_OK;
}
