/* Gradient-map aid (aid_mmukf.h): the error dynamics of one navigation step,
 * accumulated over an epoch, and the UKF's process model x_out = Phi x_in. */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "ggins/geo.h"
#include "ggins/gmap.h"
#include "ggins/quat.h"

#include "aid_mmukf_int.h"

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

/* The barometric loop's correction at this step (aid_mmukf.h): x <- x + b (c^T x + n_b),
 * c^T x = u^T dr, on the accumulated transition and noise. */
static void loop_correction(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
{
    double b[NXM];
    double cphi[NXM];
    double cq[NXM];
    double cqc;
    const double *u = ins->loop_u_i;
    const double w = ins->omega_ie;
    const double sb2 = a->cfg.sigma_baro_m * a->cfg.sigma_baro_m;
    const int32_t n = a->nx;
    int32_t j;
    int32_t k;
    for (j = 0; j < NXM; ++j) {
        b[j] = 0.0;
        cphi[j] = 0.0;
        cq[j] = 0.0;
    }
    for (j = 0; j < 3; ++j) {
        b[j] = ins->loop_k[0] * u[j];
        b[3 + j] = ins->loop_k[1] * u[j];
        if (a->nb == GG_AID_MM_NX_DR) {
            b[9 + j] = -ins->loop_k[2] * u[j]; /* a_c enters the acceleration as a_c u */
        }
    }
    /* the position correction is Earth-relative: v_i moves by w_ie x dr as well */
    b[3] -= w * b[1];
    b[4] += w * b[0];
    for (k = 0; k < n; ++k) {
        cphi[k] = (u[0] * a->phi[0][k]) + (u[1] * a->phi[1][k]) + (u[2] * a->phi[2][k]);
        cq[k] = (u[0] * a->q[0][k]) + (u[1] * a->q[1][k]) + (u[2] * a->q[2][k]);
    }
    cqc = (u[0] * cq[0]) + (u[1] * cq[1]) + (u[2] * cq[2]);
    for (j = 0; j < n; ++j) {
        for (k = 0; k < n; ++k) {
            a->phi[j][k] += b[j] * cphi[k];
            a->q[j][k] += (b[j] * cq[k]) + (cq[j] * b[k]) + (b[j] * b[k] * (cqc + sb2));
        }
    }
}

gg_status_t aid_mm_propagate(gg_aid_mm_t *a, const gg_aid_ins_t *ins)
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
    if ((ins->loop_k[0] != 0.0) || (ins->loop_k[1] != 0.0) || (ins->loop_k[2] != 0.0)) {
        loop_correction(a, ins);
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
gg_status_t aid_mm_predict_accumulated(gg_aid_mm_t *a)
{
    /* cppcheck-suppress misra-c2012-17.7 */
    const gg_status_t st = gg_ukf_predict(&a->ukf, fx_phi, a, (const double(*)[NXM])a->q);
    if (st == GG_OK) {
        mat_identity(a->nx, a->phi);
        mat_zero(a->q);
    }
    return st;
}
