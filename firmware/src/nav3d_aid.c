/* The 3-D task's aiding sources (nav3d.h, aid_mmukf.h): the INS solution
 * handed to each aid, the aid's correction fed back into the state. One file
 * per aid source would add its own hand-over here. */
#include "nav3d_int.h"

#include <math.h>
#include <stddef.h>

#include "ggins/quat.h"

/* The task's solution at its current step in the aid's terms. */
static gg_status_t n3_aid_ins(const gg_nav3d_t *nav, int64_t n_adv, int z_valid, gg_aid_ins_t *ins)
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t cb[3][3];
    gg_real_t r_inv[3][3];
    gg_real_t gi[3][3];
    gg_real_t fi[3];
    const gg_real_t s = nav->sin_th;
    const gg_real_t c = nav->cos_th;
    size_t j;
    size_t k;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st != GG_OK) {
        return st;
    }
    ins->n_steps = (int32_t)n_adv;
    ins->dt_s = (double)nav->dt_s;
    ins->omega_ie = (double)nav->omega_ie;
    ins->sin_th = s;
    ins->cos_th = c;
    gg_rot3(s, c, -1, r_i, ins->r_e);
    gg_quat_to_dcm(nav->q_b_i, cb);
    gg_rot3_mat(s, c, -1, r_inv);
    gg_mat3_mul(r_inv, cb, ins->c_b_e);
    gg_mat3_similarity(cb, nav->gamma_b, gi);
    gg_mat3_vec(cb, nav->f_b, fi);
    for (j = 0U; j < 3U; ++j) {
        for (k = 0U; k < 3U; ++k) {
            ins->c_b_i[j][k] = (double)cb[j][k];
        }
    }
    for (j = 0U; j < 3U; ++j) {
        ins->f_i[j] = (double)fi[j];
        for (k = 0U; k < 3U; ++k) {
            ins->gamma_i[j][k] = (double)gi[j][k];
        }
    }
    ins->z_b[0] = (double)nav->gamma_b[0][0];
    ins->z_b[1] = (double)nav->gamma_b[1][1];
    ins->z_b[2] = (double)nav->gamma_b[2][2];
    ins->z_b[3] = (double)nav->gamma_b[0][1];
    ins->z_b[4] = (double)nav->gamma_b[0][2];
    ins->z_b[5] = (double)nav->gamma_b[1][2];
    for (j = 0U; j < 3U; ++j) {
        ins->w_b[j] = (double)nav->w_k[j]; /* the rate difference() removed [w x]^2 with */
    }
    if (nav->cfg.platform == GG_PLATFORM_STRAPDOWN) {
        ins->w_gyro = 1;
    } else {
        ins->w_gyro = 0;
    }
    ins->z_valid = (int32_t)z_valid;
    for (j = 0U; j < 3U; ++j) {
        ins->loop_k[j] = nav->loop_k[j];
        ins->loop_u_i[j] = nav->loop_u_i[j];
    }
    return GG_OK;
}

/* Closed loop: x = true - estimate added to the state. Position and inertial
 * velocity to the mechanization (its stored acceleration moves by
 * Gamma_i dr + dg + psi x f_i), the gravitation (dead reckoning) by
 * Gamma_e dr_e + dg_e so it stays the value at the corrected position, the
 * attitude by q_b_i <- q(psi) (x) q_b_i, the bias estimates by db_w, db_f
 * (subtracted from the next readings on). A correction whose bias estimates
 * would leave their bounds (limits.h, GG_AID_MM_BIAS_SIGMAS) is refused whole:
 * the state stays as it was and the caller flags the aid's failure. */
static gg_status_t n3_bias_bounded(const gg_nav3d_t *nav, const gg_aid_corr_t *corr)
{
    const gg_aid_mm_config_t *c = &nav->cfg.aid_mm;
    double bw = GG_LIM_AID_MM_BIAS_W_EST_MAX_RPS;
    double bf = GG_LIM_AID_MM_BIAS_F_EST_MAX_MPS2;
    gg_status_t st = GG_OK;
    size_t j;
    if (c->bias_states != 0) {
        const double sw = GG_AID_MM_BIAS_SIGMAS * c->sig0_gyro_bias_rps;
        const double sf = GG_AID_MM_BIAS_SIGMAS * c->sig0_acc_bias_mps2;
        bw = (sw < bw) ? sw : bw;
        bf = (sf < bf) ? sf : bf;
    } else {
        bw = 0.0; /* no bias states: no estimate */
        bf = 0.0;
    }
    for (j = 0U; j < 3U; ++j) {
        const double nw = nav->bias_w[j] + corr->db_w[j];
        const double nf = nav->bias_f[j] + corr->db_f[j];
        if (!(nw <= bw) || !(nw >= -bw) || !(nf <= bf) || !(nf >= -bf)) {
            st = GG_ERR_RANGE;
        }
    }
    return st;
}

gg_status_t n3_aid_apply(gg_nav3d_t *nav, const gg_aid_corr_t *corr)
{
    gg_real_t dr[3];
    gg_real_t dv[3];
    gg_real_t psi[3];
    gg_real_t dg[3];
    gg_real_t gi[3][3];
    gg_real_t fi[3];
    gg_real_t gdr[3];
    gg_real_t da[3];
    gg_real_t dq[4];
    gg_real_t q[4];
    gg_status_t st;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        dr[j] = (gg_real_t)corr->dr_i[j];
        dv[j] = (gg_real_t)corr->dv_i[j];
        psi[j] = (gg_real_t)corr->psi_i[j];
        dg[j] = (gg_real_t)corr->dg_i[j];
        if (!GG_ISFINITE(dr[j]) || !GG_ISFINITE(dv[j]) || !GG_ISFINITE(psi[j]) ||
            !GG_ISFINITE(dg[j]) || !GG_ISFINITE(corr->db_w[j]) || !GG_ISFINITE(corr->db_f[j])) {
            return GG_ERR_NONFINITE;
        }
    }
    st = n3_bias_bounded(nav, corr);
    if (st != GG_OK) {
        return st;
    }
    {
        const gg_nav3d_t *cn = nav;
        gg_real_t cb[3][3];
        gg_quat_to_dcm(cn->q_b_i, cb);
        gg_mat3_similarity(cb, cn->gamma_b, gi);
        gg_mat3_vec(cb, cn->f_b, fi);
    }
    gg_mat3_vec(gi, dr, gdr);
    for (j = 0U; j < 3U; ++j) {
        gdr[j] += dg[j];
    }
    da[0] = gdr[0] + ((psi[1] * fi[2]) - (psi[2] * fi[1]));
    da[1] = gdr[1] + ((psi[2] * fi[0]) - (psi[0] * fi[2]));
    da[2] = gdr[2] + ((psi[0] * fi[1]) - (psi[1] * fi[0]));
    st = gg_quat_from_rotvec(psi, dq);
    if (st == GG_OK) {
        gg_quat_mul(dq, nav->q_b_i, q);
        st = gg_quat_normalize(q);
    }
    if (st == GG_OK) {
        st = gg_mech_correct(&nav->mech, dr, dv, da);
    }
    if ((st == GG_OK) && (nav->cfg.gravity_mode == GG_GRAVITY_GRADIOMETER)) {
        gg_real_t dg_e[3];
        gg_rot3(nav->sin_th, nav->cos_th, -1, gdr, dg_e);
        st = gg_gravdr_correct(&nav->gravdr, dg_e);
    }
    if (st == GG_OK) {
        for (j = 0U; j < 4U; ++j) {
            nav->q_b_i[j] = q[j];
        }
        for (j = 0U; j < 3U; ++j) {
            nav->bias_w[j] += corr->db_w[j];
            nav->bias_f[j] += corr->db_f[j];
        }
    }
    return st;
}

static uint32_t n3_aid_health(uint32_t ah)
{
    uint32_t h = 0U;
    if ((ah & GG_AID_MM_H_NO_MAP) != 0U) {
        h |= GG_HEALTH_MM_NO_MAP;
    }
    if ((ah & GG_AID_MM_H_GATED) != 0U) {
        h |= GG_HEALTH_MM_GATED;
    }
    if ((ah & GG_AID_MM_H_FAIL) != 0U) {
        h |= GG_HEALTH_MM_FAIL;
    }
    if ((ah & GG_AID_MM_H_BAD_MEAS) != 0U) {
        h |= GG_HEALTH_MM_BAD_MEAS;
    }
    if ((ah & (GG_AID_MM_H_SUSPECT | GG_AID_MM_H_ISOLATED)) != 0U) {
        h |= GG_HEALTH_AID_INTEGRITY;
    }
    return h;
}

void n3_aid_step(gg_nav3d_t *nav, int64_t n_adv, int z_valid, const gg_hal_t *hal,
                 uint32_t *health, int32_t *corrected)
{
    gg_aid_ins_t ins;
    gg_aid_corr_t corr;
    const gg_hal_map_t *map = NULL;
    gg_status_t st;
    *corrected = 0;
    if ((nav->aid_mm.initialized == 0) || (n_adv < 1)) {
        return;
    }
    if (hal != NULL) {
        map = hal->map;
    }
    corr.valid = 0;
    st = n3_aid_ins(nav, n_adv, z_valid, &ins);
    if (st == GG_OK) {
        st = gg_aid_mm_step(&nav->aid_mm, &ins, map, &corr);
    }
    {
        size_t j;
        for (j = 0U; j < 3U; ++j) {
            nav->loop_k[j] = 0.0; /* handed over once */
        }
    }
    *health |= n3_aid_health(nav->aid_mm.health);
    if ((st == GG_OK) && (corr.valid != 0)) {
        st = n3_aid_apply(nav, &corr);
        if (st == GG_OK) {
            size_t j;
            *corrected = 1;
            for (j = 0U; j < 3U; ++j) {
                nav->aid_corr_m[j] = corr.dr_i[j];
            }
        }
    }
    if (st != GG_OK) {
        *health |= GG_HEALTH_MM_FAIL;
    }
}

void n3_aid_start(const gg_nav3d_t *nav, gg_aid_mm_t *aid, uint32_t *health)
{
    gg_aid_ins_t ins;
    gg_status_t st = n3_aid_ins(nav, 1, 0, &ins);
    if (st == GG_OK) {
        /* cppcheck-suppress misra-c2012-17.7 */
        st = gg_aid_mm_start(aid, (const double(*)[3])ins.gamma_i);
    }
    if (st != GG_OK) {
        *health |= GG_HEALTH_MM_FAIL;
    }
}

void n3_aid_output(const gg_nav3d_t *nav, gg_nav3d_output_t *out)
{
    const gg_aid_mm_t *a = &nav->aid_mm;
    int32_t j;
    if (a->initialized == 0) {
        return;
    }
    out->mm_phase = a->phase;
    out->mm_epochs = a->n_epochs;
    out->mm_updates = a->n_updates;
    out->mm_rejected = a->n_rejected;
    out->mm_no_map = a->n_no_map;
    out->mm_nis = a->last_nis;
    out->mm_integ = a->integ.state;
    out->mm_integ_ratio = a->integ.ratio;
    out->mm_isolated = a->n_isolated;
    for (j = 0; (j < a->nx) && (j < 18); ++j) {
        const double p = a->ukf.P[j][j];
        out->mm_sigma[j] = sqrt(p);
    }
    for (j = 0; j < 3; ++j) {
        out->mm_bias[j] = nav->bias_w[j];
        out->mm_bias[3 + j] = nav->bias_f[j];
    }
    for (j = 0; j < 3; ++j) {
        out->mm_corr_m[j] = nav->aid_corr_m[j];
    }
    for (j = 0; j < 6; ++j) {
        out->mm_innov[j] = a->last_innov[j];
    }
    {
        static const int32_t rj[6] = {0, 1, 2, 0, 0, 1};
        static const int32_t rk[6] = {0, 1, 2, 1, 2, 2};
        int32_t b;
        for (b = 0; b < 3; ++b) {
            for (j = 0; j < 6; ++j) {
                out->mm_pcov[(6 * b) + j] = a->ukf.P[(3 * b) + rj[j]][(3 * b) + rk[j]];
            }
        }
    }
    out->mm_n_avg = a->last_n_avg;
}
