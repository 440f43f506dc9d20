/* Output of the 3-D task: the state in ECEF, geodetic and NED terms, the
 * attitude as a quaternion and roll, pitch, yaw (nav3d.h). */
#include "nav3d_int.h"

#include <stddef.h>

#include "ggins/geo.h"
#include "ggins/ggmath.h"
#include "ggins/quat.h"

void n3_fill_output(const gg_nav3d_t *nav, const gg_frame_t *fr, gg_status_t status,
                        uint32_t health, gg_nav3d_output_t *out)
{
    const gg_nav3d_output_t empty = {0};
    size_t j;
    size_t k;
    *out = empty;
    out->utime = fr->utime;
    out->seq = fr->seq;
    out->status = (int32_t)status;
    out->health = health;
    if ((nav->started == 0) || (nav->mech.initialized == 0)) {
        gg_real_t lat = 0.0L;
        gg_real_t lon = 0.0L;
        gg_real_t h = 0.0L;
        out->health |= GG_HEALTH_NOT_INIT;
        if (nav->configured != 0) {
            for (j = 0U; j < 3U; ++j) {
                out->r_e[j] = (double)nav->cfg.r0_e[j];
                out->v_e[j] = (double)nav->cfg.v0_e[j];
                out->g_e[j] = (double)nav->cfg.g0_e[j];
            }
            if (gg_geo_ecef_to_geodetic(nav->cfg.r0_e, &lat, &lon, &h) == GG_OK) {
                out->lat_rad = (double)lat;
                out->lon_rad = (double)lon;
                out->h_m = (double)h;
            }
        }
        return;
    }
    {
        const gg_real_t s = nav->sin_th;
        const gg_real_t c = nav->cos_th;
        const gg_real_t w = nav->omega_ie;
        const gg_real_t th = w * ((gg_real_t)nav->n_steps * nav->dt_s);
        gg_real_t rh[3];
        gg_real_t rl[3];
        gg_real_t reh[3];
        gg_real_t rel[3];
        gg_real_t r_e[3];
        gg_real_t v_rel[3];
        gg_real_t v_e[3];
        gg_real_t cen[3][3];
        gg_real_t cb[3][3];
        gg_real_t cbe[3][3];
        gg_real_t cbn[3][3];
        gg_real_t r_inv[3][3];
        gg_real_t lat = 0.0L;
        gg_real_t lon = 0.0L;
        gg_real_t h = 0.0L;
        gg_real_t sh = 0.0L;
        gg_real_t ch = 1.0L;
        gg_real_t a = 0.0L;
        gg_acc_t ra[3];
        gg_acc_t va[3];
        if (gg_mech_get_acc(&nav->mech, ra, va) != GG_OK) {
            out->health |= GG_HEALTH_NOT_INIT;
            return;
        }
        for (j = 0U; j < 3U; ++j) {
            rh[j] = ra[j].hi;
            rl[j] = ra[j].lo;
            v_rel[j] = gg_acc_value(&va[j]);
        }
        gg_rot3(s, c, -1, rh, reh);
        gg_rot3(s, c, -1, rl, rel);
        for (j = 0U; j < 3U; ++j) {
            r_e[j] = reh[j] + rel[j];
            out->r_e[j] = (double)r_e[j];
            out->r_e_lo[j] = (double)(r_e[j] - (gg_real_t)out->r_e[j]);
        }
        /* Earth-relative velocity: v_i - omega x r_i, rotated into ECEF */
        {
            const gg_real_t r0 = rh[0] + rl[0];
            const gg_real_t r1 = rh[1] + rl[1];
            v_rel[0] += w * r1;
            v_rel[1] -= w * r0;
        }
        gg_rot3(s, c, -1, v_rel, v_e);
        if ((gg_geo_local_frame(r_e, &h, cen) != GG_OK) ||
            (gg_geo_ecef_to_geodetic(r_e, &lat, &lon, &h) != GG_OK)) {
            out->health |= GG_HEALTH_NOT_INIT;
        }
        out->lat_rad = (double)lat;
        out->lon_rad = (double)lon;
        out->h_m = (double)h;
        {
            gg_real_t vn[3];
            gg_mat3_vec(cen, v_e, vn);
            for (j = 0U; j < 3U; ++j) {
                out->v_e[j] = (double)v_e[j];
                out->v_n[j] = (double)vn[j];
            }
        }
        if (nav->cfg.gravity_mode == GG_GRAVITY_MODEL) {
            gg_real_t g[3] = {0.0L, 0.0L, 0.0L};
            (void)gg_gmodel_eval(&nav->gmodel, &nav->cfg.model, r_e, g, NULL);
            for (j = 0U; j < 3U; ++j) {
                out->g_e[j] = (double)g[j];
            }
        } else {
            gg_acc_t g[3];
            if (gg_gravdr_get_acc(&nav->gravdr, g) == GG_OK) {
                for (j = 0U; j < 3U; ++j) {
                    const gg_real_t gv = gg_acc_value(&g[j]);
                    out->g_e[j] = (double)gv;
                    out->g_e_lo[j] = (double)(gv - (gg_real_t)out->g_e[j]);
                }
            }
        }
        /* attitude: C_b_e = R3(-theta) C_b_i; q_b_e = q_i_e (x) q_b_i with
         * q_i_e = (cos theta/2, 0, 0, -sin theta/2) */
        gg_quat_to_dcm(nav->q_b_i, cb);
        gg_rot3_mat(s, c, -1, r_inv);
        gg_mat3_mul(r_inv, cb, cbe);
        gg_mat3_mul(cen, cbe, cbn);
        if (gg_sincos(0.5L * th, &sh, &ch) == GG_OK) {
            const gg_real_t qie[4] = {ch, 0.0L, 0.0L, -sh};
            gg_real_t qbe[4];
            gg_quat_mul(qie, nav->q_b_i, qbe);
            for (j = 0U; j < 4U; ++j) {
                out->q_b_e[j] = (double)qbe[j];
            }
        }
        if (gg_atan2(cbn[2][1], cbn[2][2], &a) == GG_OK) {
            out->rpy_rad[0] = (double)a;
        }
        if (gg_atan2(-cbn[2][0], sqrtl((cbn[2][1] * cbn[2][1]) + (cbn[2][2] * cbn[2][2])), &a) ==
            GG_OK) {
            out->rpy_rad[1] = (double)a;
        }
        if (gg_atan2(cbn[1][0], cbn[0][0], &a) == GG_OK) {
            out->rpy_rad[2] = (double)a;
        }
        out->t_s = (double)((gg_real_t)nav->n_steps * nav->dt_s);
    }
    for (j = 0U; j < 3U; ++j) {
        out->f_b[j] = (double)nav->f_b[j];
        out->omega_b[j] = (double)nav->w_k[j];
        out->omega_dot_b[j] = (double)nav->omega_dot_b[j];
        for (k = 0U; k < 3U; ++k) {
            out->gamma_e[j][k] = (double)nav->gamma_e[j][k];
            out->gamma_b[j][k] = (double)nav->gamma_b[j][k];
        }
    }
    for (j = 0U; j < 4U; ++j) {
        out->parity[j] = (double)nav->parity[j];
    }
    out->h_ins_m = (double)nav->h_ins;
    out->baro_innov_m = (double)nav->baro_innov;
    out->g_up_corr = (double)nav->a_c;
}
