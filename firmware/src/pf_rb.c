/* The particle filter's Rao-Blackwellised process model: the psi-angle INS
 * error dynamics discretised per shot (F = exp(A dt), Q by its Taylor series),
 * the shared Kalman prediction and the per-particle part (pf.h). */
#include "pf_int.h"

#include <stddef.h>

#include "ggins/ggmath.h"

pf_radii_t pf_radii(double sl, double h)
{
    pf_radii_t r;
    double rm = 0.0;
    double rn = 0.0;
    gg_geo_radii(sl, &rm, &rn);
    r.rm = rm + h;
    r.rnh = rn + h;
    return r;
}

/* ---- Rao-Blackwellised model (GG_PF_MODEL_RBPF) ---- */

#define PF_RB_TERMS 12 /* Taylor terms of exp(A dt) and of the noise integral */

/* Continuous-time couplings of the RBPF model (see pf.h). */
typedef struct {
    double ws2;  /* Schuler w_s^2 */
    double fcor; /* 2 Omega sinL */
    double wn;   /* w_in = Omega + rho, NED */
    double we;
    double wd;
} pf_rb_coef_t;

/* out = A m for the sparse A of the model (out distinct from m; m only read - not const-qualified
 * because C11 does not convert double (*)[N] to const double (*)[N] implicitly). */
static void pf_rb_amul(const pf_rb_coef_t *k, double m[GG_PF_NX][GG_PF_NX], double out[GG_PF_NX][GG_PF_NX])
{
    int j;
    int i;
    for (j = 0; j < GG_PF_NX; ++j) {
        out[0][j] = m[2][j];
        out[1][j] = m[3][j];
        out[2][j] = (((-k->ws2 * m[0][j]) - (k->fcor * m[3][j])) + m[4][j]) + m[10][j];
        out[3][j] = (((-k->ws2 * m[1][j]) + (k->fcor * m[2][j])) + m[5][j]) + m[11][j];
        out[4][j] = ((k->wd * m[5][j]) + (k->wn * m[6][j])) + m[7][j];
        out[5][j] = ((-k->wd * m[4][j]) + (k->we * m[6][j])) + m[8][j];
        out[6][j] = ((-k->wn * m[4][j]) - (k->we * m[5][j])) + m[9][j];
        for (i = 7; i < GG_PF_NX; ++i) {
            out[i][j] = 0.0;
        }
    }
}

/* F and Q of one step (gg_pf_rb_model) from validated inputs: sin, cos of the latitude and the radii. */
static void pf_rb_model_at(const gg_pf_config_t *cfg, double sl, double cl, pf_radii_t r, double vn, double ve,
                           double F[GG_PF_NX][GG_PF_NX], double Q[GG_PF_NX][GG_PF_NX],
                           double tmp[GG_PF_NX][GG_PF_NX])
{
    pf_rb_coef_t k;
    double qc[GG_PF_NX];
    double coef;
    int i;
    int j;
    int t;
    k.ws2 = PF_G0 / gg_sqrt_d(r.rm * r.rnh);
    k.fcor = 2.0 * PF_OMEGA_E * sl;
    k.wn = (PF_OMEGA_E * cl) + (ve / r.rnh);
    k.we = -vn / r.rm;
    k.wd = (-PF_OMEGA_E * sl) - ((ve * sl) / (cl * r.rnh));
    {
        const double dt = cfg->dt;
        qc[0] = (cfg->q_pos * cfg->q_pos) / dt;
        qc[1] = qc[0];
        qc[2] = (cfg->q_vel * cfg->q_vel) / dt;
        qc[3] = qc[2];
        qc[4] = (cfg->q_acc * cfg->q_acc) / dt;
        qc[5] = qc[4];
        qc[6] = qc[4];
        qc[7] = (cfg->q_jerk * cfg->q_jerk) / dt;
        qc[8] = qc[7];
        qc[9] = qc[7];
        qc[10] = (cfg->q_bias * cfg->q_bias) / dt;
        qc[11] = qc[10];
    }
    /* Q = sum_t T_t dt^(t+1) / (t+1)!, T_0 = Qc, T_t = A T_(t-1) + T_(t-1) A^T (the derivatives
     * of e^(As) Qc e^(A^T s) at s = 0); F serves as the buffer of T here */
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j < GG_PF_NX; ++j) {
            F[i][j] = (i == j) ? qc[i] : 0.0;
            Q[i][j] = F[i][j] * cfg->dt;
        }
    }
    coef = cfg->dt;
    for (t = 1; t < PF_RB_TERMS; ++t) {
        pf_rb_amul(&k, F, tmp);
        coef *= cfg->dt / ((double)t + 1.0);
        for (i = 0; i < GG_PF_NX; ++i) {
            for (j = 0; j < GG_PF_NX; ++j) {
                F[i][j] = tmp[i][j] + tmp[j][i];
            }
        }
        for (i = 0; i < GG_PF_NX; ++i) {
            for (j = 0; j < GG_PF_NX; ++j) {
                Q[i][j] += coef * F[i][j];
            }
        }
    }
    /* F = exp(A dt) by Horner: F = I + A dt (I + A dt / 2 (I + ... (I + A dt / K))) */
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j < GG_PF_NX; ++j) {
            F[i][j] = (i == j) ? 1.0 : 0.0;
        }
    }
    for (t = PF_RB_TERMS; t >= 1; --t) {
        const double f = cfg->dt / (double)t;
        pf_rb_amul(&k, F, tmp);
        for (i = 0; i < GG_PF_NX; ++i) {
            for (j = 0; j < GG_PF_NX; ++j) {
                F[i][j] = ((i == j) ? 1.0 : 0.0) + (f * tmp[i][j]);
            }
        }
    }
}

gg_status_t gg_pf_rb_model(const gg_pf_config_t *cfg, double lat, double h, double vn, double ve,
                           double F[GG_PF_NX][GG_PF_NX], double Q[GG_PF_NX][GG_PF_NX],
                           double tmp[GG_PF_NX][GG_PF_NX])
{
    double sl = 0.0;
    double cl = 1.0;
    gg_status_t s;
    if ((cfg == NULL) || (F == NULL) || (Q == NULL) || (tmp == NULL)) {
        return GG_ERR_NULL;
    }
    if (!GG_ISFINITE(lat) || !GG_ISFINITE(h) || !GG_ISFINITE(vn) || !GG_ISFINITE(ve) || !GG_ISFINITE(cfg->dt)) {
        return GG_ERR_NONFINITE;
    }
    if ((lat > GG_LIM_PF_LAT_MAX_RAD) || (lat < -GG_LIM_PF_LAT_MAX_RAD) || (h < GG_LIM_PF_H_MIN_M) ||
        (h > GG_LIM_PF_H_MAX_M) || (vn > GG_LIM_PF_V_MAX_MPS) || (vn < -GG_LIM_PF_V_MAX_MPS) ||
        (ve > GG_LIM_PF_V_MAX_MPS) || (ve < -GG_LIM_PF_V_MAX_MPS) || !(cfg->dt > 0.0)) {
        return GG_ERR_RANGE;
    }
    s = gg_sincos_d(lat, &sl, &cl);
    if (s == GG_OK) {
        pf_rb_model_at(cfg, sl, cl, pf_radii(sl, h), vn, ve, F, Q, tmp);
    }
    return s;
}

/* RBPF prediction, the part shared by all particles (pf.h, model GG_PF_MODEL_RBPF):
 * F, Q of the step, the joint prediction covariance S given r, the Cholesky factor of
 * S_rr and K = S_lr S_rr^-1 (kept in the state for the per-particle part) and the new
 * P (committed). Particles and P untouched on error. */
gg_status_t pf_rb_common(gg_pf_t *st, const gg_pf_input_t *in, double sl, double cl, pf_radii_t r)
{
    double (*F)[GG_PF_NX] = st->rb_F;
    double (*S)[GG_PF_NX] = st->rb_Q;
    double (*G)[GG_PF_NX] = st->rb_T;
    double pn[GG_PF_NL][GG_PF_NL];
    double kg[GG_PF_NL][2];
    double det;
    int i;
    int j;
    int q;
    int ok = 1;
    pf_rb_model_at(&st->cfg, sl, cl, r, in->vn, in->ve, F, S, G);
    /* G = F_(.,l) P; S = G F_(.,l)^T + Q: the joint prediction covariance given r */
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j < GG_PF_NL; ++j) {
            double a = 0.0;
            for (q = 0; q < GG_PF_NL; ++q) {
                a += F[i][2 + q] * st->P[q][j];
            }
            G[i][j] = a;
        }
    }
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j < GG_PF_NX; ++j) {
            double a = 0.0;
            for (q = 0; q < GG_PF_NL; ++q) {
                a += G[i][q] * F[j][2 + q];
            }
            S[i][j] += a;
        }
    }
    for (i = 0; i < GG_PF_NX; ++i) { /* exactly symmetric */
        for (j = 0; j < i; ++j) {
            const double a = 0.5 * (S[i][j] + S[j][i]);
            S[i][j] = a;
            S[j][i] = a;
        }
    }
    det = (S[0][0] * S[1][1]) - (S[0][1] * S[0][1]);
    if (!(S[0][0] > 0.0) || !(det > 0.0) || !GG_ISFINITE(det)) {
        return GG_ERR_CONFIG; /* cannot happen with q_vel > 0 and a finite P */
    }
    for (i = 0; i < GG_PF_NL; ++i) { /* K = S_lr S_rr^-1 */
        kg[i][0] = ((S[2 + i][0] * S[1][1]) - (S[2 + i][1] * S[1][0])) / det;
        kg[i][1] = ((S[2 + i][1] * S[0][0]) - (S[2 + i][0] * S[0][1])) / det;
    }
    for (i = 0; i < GG_PF_NL; ++i) { /* P = S_ll - K S_lr^T */
        for (j = 0; j <= i; ++j) {
            const double a = S[2 + i][2 + j] - ((kg[i][0] * S[2 + j][0]) + (kg[i][1] * S[2 + j][1]));
            pn[i][j] = a;
            pn[j][i] = a;
            if (!GG_ISFINITE(a)) {
                ok = 0;
            }
        }
    }
    if (ok == 0) {
        return GG_ERR_CONFIG;
    }
    for (i = 0; i < GG_PF_NL; ++i) {
        st->rb_K[i][0] = kg[i][0];
        st->rb_K[i][1] = kg[i][1];
        for (j = 0; j < GG_PF_NL; ++j) {
            st->P[i][j] = pn[i][j];
        }
    }
    st->rb_L[0] = gg_sqrt_d(S[0][0]);
    st->rb_L[1] = S[1][0] / st->rb_L[0];
    st->rb_L[2] = gg_sqrt_d(det / S[0][0]);
    /* the free-inertial covariance, P_fi <- F P_fi F^T + Q (pf.h): F and Q of the step again
     * (S and G are spent), G = F P_fi, then P_fi = G F^T + Q in place (it reads G, F, Q only) */
    pf_rb_model_at(&st->cfg, sl, cl, r, in->vn, in->ve, F, S, G);
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j < GG_PF_NX; ++j) {
            double a = 0.0;
            for (q = 0; q < GG_PF_NX; ++q) {
                a += F[i][q] * st->P_fi[q][j];
            }
            G[i][j] = a;
        }
    }
    for (i = 0; i < GG_PF_NX; ++i) {
        for (j = 0; j <= i; ++j) {
            double a = 0.5 * (S[i][j] + S[j][i]);
            for (q = 0; q < GG_PF_NX; ++q) {
                a += G[i][q] * F[j][q];
            }
            st->P_fi[i][j] = a;
        }
    }
    for (i = 0; i < GG_PF_NX; ++i) { /* exactly symmetric */
        for (j = i + 1; j < GG_PF_NX; ++j) {
            st->P_fi[i][j] = st->P_fi[j][i];
        }
    }
    return GG_OK;
}
