#include "hal_lcm3d.h"

#include <string.h>

void ggins_config3d_from_lcm(const ggins_nav3d_config_t *m, gg_nav3d_config_t *c)
{
    memset(c, 0, sizeof *c);
    for (int i = 0; i < 3; ++i) {
        c->geometry.half_base_m[i] = (gg_real_t)m->half_base_m[i];
        c->r0_e[i] = (gg_real_t)m->r0_hi[i] + (gg_real_t)m->r0_lo[i];
        c->v0_e[i] = (gg_real_t)m->v0_hi[i] + (gg_real_t)m->v0_lo[i];
        c->g0_e[i] = (gg_real_t)m->g0_hi[i] + (gg_real_t)m->g0_lo[i];
    }
    for (int i = 0; i < 4; ++i) c->q0_b_e[i] = (gg_real_t)m->q0_hi[i] + (gg_real_t)m->q0_lo[i];
    c->platform = m->platform;
    c->dt_us = m->dt_us;
    c->dt_tol_us = m->dt_tol_us;
    c->omega_ie = (gg_real_t)m->omega_ie_hi + (gg_real_t)m->omega_ie_lo;
    c->f_max = m->f_max;
    c->asym_max = m->asym_max;
    c->fdi_parity_f_max = m->fdi_parity_f_max;
    c->acc_frozen_frames = m->acc_frozen_frames;
    c->gravity_mode = m->gravity_mode;
    c->model.gm = (gg_real_t)m->model_gm_hi + (gg_real_t)m->model_gm_lo;
    c->model.a_m = (gg_real_t)m->model_a_m;
    for (int n = 0; n < 9 && n <= GG_GMODEL_MAX_DEGREE; ++n) c->model.j[n] = (gg_real_t)m->model_j[n];
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
    c->aid_mm.enable = m->aid_mm_enable;
    c->aid_mm.update_steps = m->aid_mm_update_steps;
    c->aid_mm.max_passes = m->aid_mm_max_passes;
    c->aid_mm.sigma_meas_s2 = m->aid_mm_sigma_meas_s2;
    c->aid_mm.sigma_db_s2 = m->aid_mm_sigma_db_s2;
    c->aid_mm.offdiag_ratio = m->aid_mm_offdiag_ratio;
    c->aid_mm.sig0_pos_m = m->aid_mm_sig0_pos_m;
    c->aid_mm.sig0_vel_mps = m->aid_mm_sig0_vel_mps;
    c->aid_mm.sig0_att_rad = m->aid_mm_sig0_att_rad;
    c->aid_mm.sig0_g_mps2 = m->aid_mm_sig0_g_mps2;
    c->aid_mm.q_vel_mps_rts = m->aid_mm_q_vel_mps_rts;
    c->aid_mm.q_att_rad_rts = m->aid_mm_q_att_rad_rts;
    c->aid_mm.q_g_mps2_rts = m->aid_mm_q_g_mps2_rts;
    c->aid_mm.lambda = m->aid_mm_lambda;
    c->aid_mm.gate_nis = m->aid_mm_gate_nis;
    c->aid_mm.average_steps = m->aid_mm_average_steps;
    c->aid_mm.sigma_gyro_rps = m->aid_mm_sigma_gyro_rps;
    c->aid_mm.sigma_gyro_bias_rps = m->aid_mm_sigma_gyro_bias_rps;
    c->aid_mm.bias_states = m->aid_mm_bias_states;
    c->aid_mm.sig0_gyro_bias_rps = m->aid_mm_sig0_gyro_bias_rps;
    c->aid_mm.sig0_acc_bias_mps2 = m->aid_mm_sig0_acc_bias_mps2;
    c->aid_mm.q_gyro_bias_rps_rts = m->aid_mm_q_gyro_bias_rps_rts;
    c->aid_mm.q_acc_bias_mps2_rts = m->aid_mm_q_acc_bias_mps2_rts;
    c->aid_mm.sigma_baro_m = m->aid_mm_sigma_baro_m;
    c->aid_pf.enable = m->aid_pf_enable;
    c->aid_pf.chunk = m->aid_pf_chunk;
    c->aid_pf.end_chunk = m->aid_pf_end_chunk;
    c->aid_pf.feedback = m->aid_pf_feedback;
    c->aid_pf.pf.n = m->aid_pf_n;
    c->aid_pf.pf.seed = (uint64_t)m->aid_pf_seed;
    c->aid_pf.pf.model = m->aid_pf_model;
    c->aid_pf.pf.k_eff = m->aid_pf_k_eff;
    c->aid_pf.pf.T = m->aid_pf_T;
    c->aid_pf.pf.dz = m->aid_pf_dz;
    c->aid_pf.pf.contrast = m->aid_pf_contrast;
    c->aid_pf.pf.c0 = m->aid_pf_c0;
    c->aid_pf.pf.c1 = m->aid_pf_c1;
    c->aid_pf.pf.sigma = m->aid_pf_sigma;
    c->aid_pf.pf.sigma0_pos = m->aid_pf_sigma0_pos;
    c->aid_pf.pf.sigma0_vel = m->aid_pf_sigma0_vel;
    c->aid_pf.pf.sigma0_acc = m->aid_pf_sigma0_acc;
    c->aid_pf.pf.sigma0_jerk = m->aid_pf_sigma0_jerk;
    c->aid_pf.pf.sigma0_bias = m->aid_pf_sigma0_bias;
    c->aid_pf.pf.q_pos = m->aid_pf_q_pos;
    c->aid_pf.pf.q_vel = m->aid_pf_q_vel;
    c->aid_pf.pf.q_acc = m->aid_pf_q_acc;
    c->aid_pf.pf.q_jerk = m->aid_pf_q_jerk;
    c->aid_pf.pf.q_bias = m->aid_pf_q_bias;
    c->aid_pf.pf.reg_bw = m->aid_pf_reg_bw;
    c->aid_pf.pf.dt = m->aid_pf_dt;
    c->aid_pf.pf.gain = m->aid_pf_gain;
    c->aid_pf.pf.ess_frac = m->aid_pf_ess_frac;
    c->aid_mm.integ.enable = m->aid_mm_integ_enable;
    c->aid_mm.integ.window = m->aid_mm_integ_window;
    c->aid_mm.integ.z = m->aid_mm_integ_z;
    c->aid_mm.integ.isolate_after = m->aid_mm_integ_isolate;
    c->aid_mm.integ.recover_after = m->aid_mm_integ_recover;
    c->aid_pf.integ.enable = m->aid_pf_integ_enable;
    c->aid_pf.integ.window = m->aid_pf_integ_window;
    c->aid_pf.integ.z = m->aid_pf_integ_z;
    c->aid_pf.integ.isolate_after = m->aid_pf_integ_isolate;
    c->aid_pf.integ.recover_after = m->aid_pf_integ_recover;
    c->aid_pf.info_min = m->aid_pf_info_min;
}

void ggins_output3d_to_lcm(const gg_nav3d_output_t *o, int64_t run_id, ggins_nav3d_output_t *m)
{
    memset(m, 0, sizeof *m);
    m->utime = o->utime;
    m->seq = o->seq;
    m->run_id = run_id;
    m->status = o->status;
    m->health = (int64_t)o->health;
    for (int i = 0; i < 3; ++i) {
        m->r_e[i] = o->r_e[i];
        m->r_e_lo[i] = o->r_e_lo[i];
        m->v_e[i] = o->v_e[i];
        m->v_n[i] = o->v_n[i];
        m->g_e[i] = o->g_e[i];
        m->g_e_lo[i] = o->g_e_lo[i];
        m->f_b[i] = o->f_b[i];
        m->rpy_rad[i] = o->rpy_rad[i];
        m->omega_b[i] = o->omega_b[i];
        m->omega_dot_b[i] = o->omega_dot_b[i];
        for (int j = 0; j < 3; ++j) {
            m->gamma_e[i][j] = o->gamma_e[i][j];
            m->gamma_b[i][j] = o->gamma_b[i][j];
        }
    }
    for (int i = 0; i < 4; ++i) {
        m->q_b_e[i] = o->q_b_e[i];
        m->parity[i] = o->parity[i];
    }
    m->lat_rad = o->lat_rad;
    m->lon_rad = o->lon_rad;
    m->h_m = o->h_m;
    m->h_ins_m = o->h_ins_m;
    m->baro_innov_m = o->baro_innov_m;
    m->g_up_corr = o->g_up_corr;
    m->t_s = o->t_s;
    m->n_cycles = GG_MOD_COUNT;
    for (int i = 0; i < GG_MOD_COUNT && i < 8; ++i) m->cycles[i] = (int64_t)o->cycles[i];
    m->republished = 0;
    m->resync_count = (int64_t)o->resync_count;
    m->coast_steps = (int64_t)o->coast_steps;
    m->acc_rebuilt = (int64_t)o->acc_rebuilt;
    m->acc_excluded = (int64_t)o->acc_excluded;
    m->outage_s = o->outage_s;
    m->state_lag_s = o->state_lag_s;
    m->mm_phase = o->mm_phase;
    m->mm_corrected = (int8_t)o->mm_corrected;
    m->mm_epochs = (int64_t)o->mm_epochs;
    m->mm_updates = (int64_t)o->mm_updates;
    m->mm_rejected = (int64_t)o->mm_rejected;
    m->mm_no_map = (int64_t)o->mm_no_map;
    m->mm_nis = o->mm_nis;
    for (int i = 0; i < 18; ++i) m->mm_sigma[i] = o->mm_sigma[i];
    for (int i = 0; i < 6; ++i) m->mm_bias[i] = o->mm_bias[i];
    for (int i = 0; i < 3; ++i) m->mm_corr_m[i] = o->mm_corr_m[i];
    for (int i = 0; i < 6; ++i) m->mm_innov[i] = o->mm_innov[i];
    for (int i = 0; i < 18; ++i) m->mm_pcov[i] = o->mm_pcov[i];
    m->mm_n_avg = o->mm_n_avg;
    m->pf_phase = o->pf_phase;
    m->pf_corrected = (int8_t)o->pf_corrected;
    m->pf_shots = (int64_t)o->pf_shots;
    m->pf_updates = (int64_t)o->pf_updates;
    m->pf_failed = (int64_t)o->pf_failed;
    m->pf_invalid = (int64_t)o->pf_invalid;
    m->pf_dropped = (int64_t)o->pf_dropped;
    m->pf_no_map = (int64_t)o->pf_no_map;
    m->pf_map_miss = (int64_t)o->pf_map_miss;
    m->pf_degenerate = (int64_t)o->pf_degenerate;
    m->pf_resampled = (int64_t)o->pf_resampled;
    m->pf_ess = o->pf_ess;
    for (int i = 0; i < 2; ++i) m->pf_spread_m[i] = o->pf_spread_m[i];
    for (int i = 0; i < 2; ++i) m->pf_corr_m[i] = o->pf_corr_m[i];
    for (int i = 0; i < 2; ++i) m->pf_mean_m[i] = o->pf_mean_m[i];
    m->pf_gzz_s2 = o->pf_gzz_s2;
    m->mm_integ = o->mm_integ;
    m->mm_integ_ratio = o->mm_integ_ratio;
    m->mm_isolated = (int64_t)o->mm_isolated;
    m->pf_nis = o->pf_nis;
    m->pf_integ = o->pf_integ;
    m->pf_integ_ratio = o->pf_integ_ratio;
    m->pf_isolated = (int64_t)o->pf_isolated;
    m->pf_uninformative = (int64_t)o->pf_uninformative;
    m->pf_info = o->pf_info;
    for (int i = 0; i < 2; ++i) m->pf_spread_fi_m[i] = o->pf_spread_fi_m[i];
}
