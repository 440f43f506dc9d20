/* LCM message <-> firmware struct conversions (see hal_lcm.h). */
#include "hal_lcm.h"

#include <string.h>

void ggins_frame_from_lcm(const ggins_sensor_frame_t *m, gg_frame_t *f)
{
    memset(f, 0, sizeof *f);
    f->utime = m->utime;
    f->seq = m->seq;
    f->n_acc = m->n_acc;
    for (int i = 0; i < GG_MAX_ACC; ++i) {
        for (int j = 0; j < 3; ++j) {
            f->f[i][j] = m->f[i][j];
            f->f_lo[i][j] = m->f_lo[i][j];
        }
        f->acc_status[i] = m->acc_status[i];
    }
    for (int j = 0; j < 3; ++j) f->omega_b[j] = m->omega_b[j];
    f->gyro_status = m->gyro_status;
    f->baro_alt_m = m->baro_alt_m;
    f->baro_utime = m->baro_utime;
    f->baro_status = m->baro_status;
    f->ca_s[0] = m->ca_s[0];
    f->ca_s[1] = m->ca_s[1];
    f->ca_utime = m->ca_utime;
    f->ca_status = m->ca_status;
}

_Static_assert(GG_GMODEL_MAX_DEGREE + 1 == 9, "ggins_nav2d_config_t.model_j holds J_0..J_8");
_Static_assert(GG_GMODEL_MAX_PM == 32, "ggins_nav2d_config_t.model_pm_* hold GG_GMODEL_MAX_PM masses");
_Static_assert(GG_GMODEL_GRID_MAX == 1024, "ggins_nav2d_config_t.grid_dg holds GG_GMODEL_GRID_MAX nodes");

void ggins_config_from_lcm(const ggins_nav2d_config_t *m, gg_nav2d_config_t *c)
{
    memset(c, 0, sizeof *c);
    c->geometry.a_m = (gg_real_t)m->a_m;
    c->geometry.b_m = (gg_real_t)m->b_m;
    c->dt_us = m->dt_us;
    c->dt_tol_us = m->dt_tol_us;
    for (int j = 0; j < 3; ++j) {
        c->r0[j] = (gg_real_t)m->r0_hi[j] + (gg_real_t)m->r0_lo[j];
        c->v0[j] = (gg_real_t)m->v0_hi[j] + (gg_real_t)m->v0_lo[j];
        c->g0[j] = (gg_real_t)m->g0_hi[j] + (gg_real_t)m->g0_lo[j];
    }
    c->f_max = m->f_max;
    c->asym_max = m->asym_max;
    c->gravdr_trapezoid_only = m->gravdr_trapezoid_only;
    c->fdi_parity_f_max = m->fdi_parity_f_max;
    c->fdi_asym_max = m->fdi_asym_max;
    c->acc_frozen_frames = m->acc_frozen_frames;
    c->gravity_mode = m->gravity_mode;
    c->model.gm = (gg_real_t)m->model_gm_hi + (gg_real_t)m->model_gm_lo;
    c->model.a_m = (gg_real_t)m->model_a_m;
    for (int n = 0; n <= GG_GMODEL_MAX_DEGREE; ++n) c->model.j[n] = (gg_real_t)m->model_j[n];
    c->baro_enable = m->baro_enable;
    for (int i = 0; i < 3; ++i) c->baro.poles[i] = (gg_real_t)m->baro_poles[i];
    c->baro.omega_s2 = (gg_real_t)m->baro_omega_s2;
    c->baro.period_us = m->baro_period_us;
    c->baro.max_age_us = m->baro_max_age_us;
    c->baro.coast_us = m->baro_coast_us;
    c->baro.alt_min_m = m->baro_alt_min_m;
    c->baro.alt_max_m = m->baro_alt_max_m;
    c->baro.gate_m = m->baro_gate_m;
    c->baro.max_rejects = m->baro_max_rejects;
    c->r_ref_m = (gg_real_t)m->r_ref_hi + (gg_real_t)m->r_ref_lo;
    /* programmed anomalies: a point-mass count beyond the firmware's array
     * becomes an invalid configuration (n_pm = -1: gg_gmodel_init refuses it) */
    if ((m->model_n_pm < 0) || (m->model_n_pm > GG_GMODEL_MAX_PM)) {
        c->model.n_pm = -1;
    } else {
        c->model.n_pm = m->model_n_pm;
        for (int i = 0; i < m->model_n_pm; ++i) {
            for (int j = 0; j < 3; ++j) c->model.pm_pos[i][j] = (gg_real_t)m->model_pm_pos[i][j];
            c->model.pm_gm[i] = (gg_real_t)m->model_pm_gm[i];
        }
    }
    c->model.grid.n_th = m->grid_n_th;
    c->model.grid.n_rho = m->grid_n_rho;
    c->model.grid.c0 = (gg_real_t)m->grid_c0;
    c->model.grid.s0 = (gg_real_t)m->grid_s0;
    c->model.grid.th0_rad = (gg_real_t)m->grid_th0_rad;
    c->model.grid.dth_rad = (gg_real_t)m->grid_dth_rad;
    c->model.grid.rho0_m = (gg_real_t)m->grid_rho0_m;
    c->model.grid.drho_m = (gg_real_t)m->grid_drho_m;
    /* the node array is copied whole; gg_gmodel_init checks n_th * n_rho against it */
    {
        for (int i = 0; i < GG_GMODEL_GRID_MAX; ++i) {
            c->model.grid.dg[i][0] = m->grid_dg[i][0];
            c->model.grid.dg[i][1] = m->grid_dg[i][1];
        }
    }
}

void ggins_output_to_lcm(const gg_nav_output_t *o, int64_t run_id, ggins_nav_output_t *m)
{
    memset(m, 0, sizeof *m);
    m->utime = o->utime;
    m->seq = o->seq;
    m->run_id = run_id;
    m->status = o->status;
    m->health = (int64_t)o->health;
    for (int j = 0; j < 3; ++j) {
        m->r_i[j] = o->r_i[j];
        m->v_i[j] = o->v_i[j];
        m->g_i[j] = o->g_i[j];
        m->f_i[j] = o->f_i[j];
        for (int k = 0; k < 3; ++k) m->gamma_i[j][k] = o->gamma_i[j][k];
    }
    m->gamma_asym = o->gamma_asym;
    m->h_ins_m = o->h_ins_m;
    m->baro_innov_m = o->baro_innov_m;
    m->g_up_corr = o->g_up_corr;
    m->n_cycles = GG_MOD_COUNT;
    for (int j = 0; j < GG_MOD_COUNT; ++j) m->cycles[j] = (int64_t)o->cycles[j];
    m->republished = 0;
    m->parity_f[0] = o->parity_f[0];
    m->parity_f[1] = o->parity_f[1];
    m->acc_excluded = (int64_t)o->acc_excluded;
    m->acc_rebuilt = (int64_t)o->acc_rebuilt;
    m->resync_count = (int64_t)o->resync_count;
    m->coast_steps = (int64_t)o->coast_steps;
    m->outage_s = o->outage_s;
    m->state_lag_s = o->state_lag_s;
}
