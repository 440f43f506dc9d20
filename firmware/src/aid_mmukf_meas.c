/* Gradient-map aid (aid_mmukf.h): the measurement model (the map's tensor at the
 * INS position, rotated into the body axes) and the epoch's averaging window. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ggins/geo.h"
#include "ggins/gmap.h"
#include "ggins/quat.h"

#include "aid_mmukf_int.h"

/* Empty the epoch's averaging window. */
void aid_mm_window_reset(gg_aid_mm_t *a)
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

gg_status_t aid_mm_meas_model(void *ctx, const double *x, double *z)
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
void aid_mm_window_add(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
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
void aid_mm_window_epoch(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
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

