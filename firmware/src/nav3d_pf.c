/* The 3-D task's cold-atom aid (aid_pf.h): the frame's shot and the task's
 * solution handed to the particle filter, its horizontal position correction
 * fed back into the state (closed loop, nav3d_aid.c's n3_aid_apply). */
#include "nav3d_int.h"

#include <stddef.h>

#include "ggins/geo.h"
#include "ggins/quat.h"

/* The task's solution at its current step: geodetic position, NED velocity and
 * the local frame (rows of C_e_n: north, east, down in ECEF). */
static gg_status_t n3_pf_ins(const gg_nav3d_t *nav, gg_aid_pf_in_t *in, gg_real_t cen[3][3])
{
    gg_real_t r_i[3];
    gg_real_t v_i[3];
    gg_real_t r_e[3];
    gg_real_t v_e[3];
    gg_real_t lat = 0.0L;
    gg_real_t lon = 0.0L;
    gg_real_t h = 0.0L;
    gg_real_t h2 = 0.0L;
    const gg_real_t w = nav->omega_ie;
    gg_status_t st = gg_mech_get(&nav->mech, r_i, v_i);
    if (st == GG_OK) {
        /* Earth-relative velocity: v_i - omega x r_i, rotated into ECEF */
        v_i[0] += w * r_i[1];
        v_i[1] -= w * r_i[0];
        gg_rot3(nav->sin_th, nav->cos_th, -1, r_i, r_e);
        gg_rot3(nav->sin_th, nav->cos_th, -1, v_i, v_e);
        st = gg_geo_ecef_to_geodetic(r_e, &lat, &lon, &h);
    }
    if (st == GG_OK) {
        st = gg_geo_local_frame(r_e, &h2, cen);
    }
    if (st == GG_OK) {
        gg_real_t vn = 0.0L;
        gg_real_t ve = 0.0L;
        for (size_t j = 0U; j < 3U; ++j) {
            vn += cen[0][j] * v_e[j];
            ve += cen[1][j] * v_e[j];
        }
        in->lat_rad = (double)lat;
        in->lon_rad = (double)lon;
        in->h_m = (double)h;
        in->vn_mps = (double)vn;
        in->ve_mps = (double)ve;
    }
    return st;
}

static uint32_t n3_pf_health(uint32_t ah)
{
    uint32_t h = 0U;
    if ((ah & (GG_AID_PF_H_SHOT_INVALID | GG_AID_PF_H_DROPPED)) != 0U) {
        h |= GG_HEALTH_PF_SHOT_INVALID;
    }
    if ((ah & (GG_AID_PF_H_NO_MAP | GG_AID_PF_H_DEGENERATE | GG_AID_PF_H_FAIL)) != 0U) {
        h |= GG_HEALTH_PF_FAIL;
    }
    if ((ah & (GG_AID_PF_H_SUSPECT | GG_AID_PF_H_ISOLATED)) != 0U) {
        h |= GG_HEALTH_AID_INTEGRITY;
    }
    return h;
}

/* The horizontal correction (north, east) as an ECI correction of the state:
 * dr_i = R3(theta) C_n_e (dn, de, 0), dv_i = R3(theta) C_n_e (dvn, dve, 0) +
 * omega x dr_i (the Earth-relative velocity moves by (dvn, dve) only), no
 * attitude, gravitation or bias term (the task moves the gravitation with Gamma dr). */
static gg_status_t n3_pf_apply(gg_nav3d_t *nav, const gg_aid_pf_corr_t *pc, gg_real_t cen[3][3])
{
    gg_aid_corr_t c;
    gg_real_t dr_e[3];
    gg_real_t dr_i[3];
    gg_real_t dv_e[3];
    gg_real_t dv_i[3];
    const gg_real_t dn = (gg_real_t)pc->dn_m;
    const gg_real_t de = (gg_real_t)pc->de_m;
    const gg_real_t dvn = (gg_real_t)pc->dvn_mps;
    const gg_real_t dve = (gg_real_t)pc->dve_mps;
    const gg_real_t w = nav->omega_ie;
    size_t j;
    for (j = 0U; j < 3U; ++j) {
        dr_e[j] = (dn * cen[0][j]) + (de * cen[1][j]);
        dv_e[j] = (dvn * cen[0][j]) + (dve * cen[1][j]);
    }
    gg_rot3(nav->sin_th, nav->cos_th, 1, dr_e, dr_i);
    gg_rot3(nav->sin_th, nav->cos_th, 1, dv_e, dv_i);
    c.valid = 1;
    for (j = 0U; j < 3U; ++j) {
        c.dr_i[j] = (double)dr_i[j];
        c.psi_i[j] = 0.0;
        c.dg_i[j] = 0.0;
        c.db_w[j] = 0.0; /* no bias terms */
        c.db_f[j] = 0.0;
    }
    {
        const gg_real_t dv0 = dv_i[0] - (w * dr_i[1]);
        const gg_real_t dv1 = dv_i[1] + (w * dr_i[0]);
        c.dv_i[0] = (double)dv0;
        c.dv_i[1] = (double)dv1;
    }
    c.dv_i[2] = (double)dv_i[2];
    return n3_aid_apply(nav, &c);
}

void n3_pf_step(gg_nav3d_t *nav, const gg_frame_t *fr, int used, const gg_hal_t *hal, uint32_t *health,
                int32_t *corrected)
{
    gg_aid_pf_in_t in;
    gg_aid_pf_corr_t corr;
    gg_real_t cen[3][3];
    const gg_hal_map_t *map = NULL;
    uint32_t extra = 0U;
    gg_status_t st;
    *corrected = 0;
    if (hal != NULL) {
        map = hal->map;
    }
    in.shot_present = 0;
    in.shot_ok = 0;
    in.s[0] = 0.0;
    in.s[1] = 0.0;
    if (used != 0) {
        in.stale = 0;
    } else {
        in.stale = 1;
    }
    if (fr->ca_status != GG_SENSOR_ABSENT) {
        if ((fr->ca_utime < 0) || (fr->ca_utime > GG_TIME_MAX) ||
            ((fr->ca_status != GG_SENSOR_OK) && (fr->ca_status != GG_SENSOR_BAD))) {
            extra |= GG_HEALTH_PF_SHOT_INVALID; /* no shot this step: its time or status is no shot's */
        } else if ((nav->pf_have_shot == 0) || (fr->ca_utime != nav->pf_last_utime)) {
            in.shot_present = 1;
            if (fr->ca_status == GG_SENSOR_OK) {
                in.shot_ok = 1;
            } else {
                in.shot_ok = 0;
            }
            in.s[0] = fr->ca_s[0];
            in.s[1] = fr->ca_s[1];
            nav->pf_have_shot = 1;
            nav->pf_last_utime = fr->ca_utime;
        } else {
            /* the same shot repeated in a later frame */
        }
    }
    st = n3_pf_ins(nav, &in, cen);
    if (st == GG_OK) {
        st = gg_aid_pf_step(&nav->aid_pf, &in, map, &corr);
    }
    if ((st == GG_OK) && (corr.valid != 0)) {
        int32_t applied = 0;
        if (n3_pf_apply(nav, &corr, cen) == GG_OK) {
            applied = 1;
            *corrected = 1;
        }
        st = gg_aid_pf_applied(&nav->aid_pf, &corr, applied);
        if (applied == 0) {
            extra |= GG_HEALTH_PF_FAIL;
        }
    }
    if (st != GG_OK) {
        extra |= GG_HEALTH_PF_FAIL;
    }
    *health |= extra | n3_pf_health(nav->aid_pf.health);
}

void n3_pf_output(const gg_nav3d_t *nav, gg_nav3d_output_t *out)
{
    const gg_aid_pf_t *a = &nav->aid_pf;
    if (a->initialized == 0) {
        return;
    }
    out->pf_phase = a->phase;
    out->pf_shots = a->n_shots;
    out->pf_updates = a->n_updates;
    out->pf_failed = a->n_failed;
    out->pf_invalid = a->n_invalid;
    out->pf_dropped = a->n_dropped;
    out->pf_no_map = a->n_no_map;
    out->pf_map_miss = a->n_map_miss;
    out->pf_degenerate = a->n_degenerate;
    out->pf_resampled = a->n_resampled;
    out->pf_ess = a->last.ess;
    out->pf_spread_m[0] = a->last.spread[0];
    out->pf_spread_m[1] = a->last.spread[1];
    out->pf_corr_m[0] = a->last.corr[0];
    out->pf_corr_m[1] = a->last.corr[1];
    out->pf_gzz_s2 = a->last.gzz_mean;
    out->pf_nis = a->last.nis;
    out->pf_integ = a->integ.state;
    out->pf_integ_ratio = a->integ.ratio;
    out->pf_isolated = a->n_isolated;
    out->pf_uninformative = a->n_uninformative;
    out->pf_info = a->last.info;
    out->pf_spread_fi_m[0] = a->last.spread_fi[0];
    out->pf_spread_fi_m[1] = a->last.spread_fi[1];
    out->pf_mean_m[0] = a->last.mean[0] - a->last.corr[0];
    out->pf_mean_m[1] = a->last.mean[1] - a->last.corr[1];
}
