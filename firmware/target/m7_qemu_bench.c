/* Instruction-count benchmark image for the Cortex-M7 (QEMU mps2-an500):
 * runs STEPS navigation steps on a stationary platform with a 1 Hz
 * barometer, then exits through semihosting. scripts/m7-qemu-count runs it
 * for two step counts under QEMU with one instruction per translation block
 * and counts executed instructions; the difference over the extra steps is
 * the instructions per step of the Thumb-2 build. Built with -DNAV3D it
 * runs the 3-D task (nav3d.h) instead. Not flown. */
#include <stdint.h>

#include "ggins/nav2d.h"
#include "ggins/nav3d.h"
#include "m7_startup.h"

#ifndef STEPS
#define STEPS 100
#endif

static gg_frame_t g_frame;
#ifndef NAV3D
static gg_nav2d_t g_nav;
static gg_nav_output_t g_out;
#endif

#ifndef NAV3D
int main(void)
{
    /* readings of a platform at rest at the equator: f = -G(r + d_i),
     * gradient 2 GM/r^3 radially, -GM/r^3 across */
    const double g0 = 9.798285;
    const double gxx = 3.0725e-6;
    const double gzz = -1.5362e-6;
    int32_t k;
    if (gg_nav2d_init(&g_nav, &g_m7_demo_config) != GG_OK) {
        m7_qemu_exit();
    }
    g_frame.n_acc = 4;
    g_frame.f[0][0] = g0 - (gxx * 0.5);
    g_frame.f[2][0] = g0 + (gxx * 0.5);
    g_frame.f[1][0] = g0;
    g_frame.f[3][0] = g0;
    g_frame.f[1][2] = -(gzz * 0.5);
    g_frame.f[3][2] = gzz * 0.5;
    for (k = 4; k < GG_MAX_ACC; ++k) {
        g_frame.acc_status[k] = GG_SENSOR_ABSENT;
    }
    for (k = 0; k < STEPS; ++k) {
        g_frame.seq = k;
        g_frame.utime = (int64_t)k * 10000;
        g_frame.baro_status = ((k % 100) == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
        g_frame.baro_utime = g_frame.utime;
        g_frame.baro_alt_m = 0.0;
        (void)gg_nav2d_step(&g_nav, &g_frame, NULL, &g_out);
    }
    m7_qemu_exit();
    return 0;
}
#else
/* 3-D: strapdown body at rest on the equator (body x up, readings of the
 * point-mass field), gyros reading a slow constant rotation, 1 Hz barometer;
 * gg_nav3d_step. The readings need not be mutually consistent for counting
 * instructions, only accepted. Built with -DAID the gradient-map UKF aid is
 * on (aid_mmukf.h: 12 error states, an epoch every AID_EPOCH steps, two
 * progressive passes), with one 50 x 50 tile (build_map) as the map storage (with -DPF also
 * the cold-atom aid, aid_pf.h, reading its Gamma_zz from the same tile, its shot at step
 * PF_SHOT): the images for
 * STEPS = AID_EPOCH - 1 ... AID_EPOCH + 6 isolate the propagation-only step
 * and each step of the schedule (epoch, spread, update, spread, update,
 * finish). */
static gg_nav3d_t g_nav3;
static gg_nav3d_output_t g_out3;
#ifdef AID
#ifndef AID_EPOCH
#define AID_EPOCH 20
#endif
static gg_gmap_tile_t g_tile;
static gg_gmap_t g_map;

static gg_status_t board_tile_at(void *ctx, uint32_t kind, double lat_rad, double lon_rad, double h_m,
                                 const gg_gmap_t **tile)
{
    (void)ctx;
    (void)h_m;
    (void)kind; /* one tile of the whole tensor serves both aids (the cycle count only) */
    (void)lat_rad;
    (void)lon_rad;
    *tile = &g_map;
    return GG_OK;
}

/* The tile from the gradient the task measured at its first step (body x
 * up, y east, z north at latitude 0, longitude 0: NN = zz, EE = yy, DD = xx,
 * NE = zy, ND = -zx, ED = -yx), so that the epochs' innovations are those of
 * a consistent measurement, plus a small horizontal variation. */
static int build_map(const double gb[3][3])
{
    int32_t i;
    int32_t j;
    int ok = 0;
    g_tile.nlat = 50;
    g_tile.nlon = 50;
    g_tile.dlat_rad = 1.745e-4;
    g_tile.dlon_rad = 1.745e-4;
    g_tile.lat0_rad = -25.0 * g_tile.dlat_rad;
    g_tile.lon0_rad = -25.0 * g_tile.dlon_rad;
    g_tile.h0_m = 0.0;
    g_tile.h_range_m = 1000.0;
    for (i = 0; i < 50; ++i) {
        for (j = 0; j < 50; ++j) {
            double *n = g_tile.node[(i * 50) + j];
            const double di = (double)(i - 25);
            const double dj = (double)(j - 25);
            n[0] = gb[2][2] + (1.0e-11 * di);
            n[1] = gb[1][1] + (1.0e-11 * dj);
            n[2] = gb[0][0] - (1.0e-11 * (di + dj));
            n[3] = gb[2][1] + (2.0e-13 * di * dj);
            n[4] = -gb[2][0] + (3.0e-12 * di);
            n[5] = -gb[1][0] - (3.0e-12 * dj);
            n[8] = -1.4e-12;
        }
    }
    if (gg_gmap_init(&g_map, &g_tile) == GG_OK) {
        ok = 1;
    }
    return ok;
}
#endif

int main(void)
{
    const double g0 = 9.798285;
    const double gxx = 3.0725e-6;
    const double gyy = -1.5362e-6;
    int32_t k;
    int32_t j;
    gg_nav3d_config_t cfg = {0};
#ifdef AID
    const gg_hal_map_t map = {NULL, board_tile_at};
    const gg_hal_t hal = {NULL, NULL, NULL, NULL, 0U, NULL, &map};
#endif
    cfg.geometry.half_base_m[0] = 0.5L;
    cfg.geometry.half_base_m[1] = 0.5L;
    cfg.geometry.half_base_m[2] = 0.5L;
    cfg.platform = GG_PLATFORM_STRAPDOWN;
    cfg.dt_us = 10000;
    cfg.dt_tol_us = 100;
    cfg.r0_e[0] = GG_WGS84_A_M;
    cfg.g0_e[0] = -9.798L;
    cfg.q0_b_e[0] = 1.0L;
    cfg.f_max = 100.0;
    cfg.asym_max = 1e-6;
    cfg.gravity_mode = GG_GRAVITY_GRADIOMETER;
    cfg.baro_enable = 1;
    cfg.baro = g_m7_demo_config.baro;
#ifdef AID
    cfg.aid_mm.enable = 1;
    cfg.aid_mm.update_steps = AID_EPOCH;
    cfg.aid_mm.max_passes = 2;
    cfg.aid_mm.sigma_meas_s2 = 1.0e-11;
    cfg.aid_mm.sigma_db_s2 = 1.0e-12;
    cfg.aid_mm.offdiag_ratio = 0.7071;
    cfg.aid_mm.sig0_pos_m = 200.0;
    cfg.aid_mm.sig0_vel_mps = 0.1;
    cfg.aid_mm.sig0_att_rad = 1.0e-5;
    cfg.aid_mm.sig0_g_mps2 = 1.0e-7;
    cfg.aid_mm.q_vel_mps_rts = 1.0e-6;
    cfg.aid_mm.q_att_rad_rts = 1.0e-9;
    cfg.aid_mm.q_g_mps2_rts = 1.0e-10;
    cfg.aid_mm.average_steps = AID_EPOCH; /* the worst case: every step in the window, two map nodes */
    cfg.aid_mm.sigma_gyro_rps = 2.9e-6;
    cfg.aid_mm.sigma_gyro_bias_rps = 4.85e-8;
    /* the largest filter: 18 states with the bias states (Gao Table 1 sigmas) */
    cfg.aid_mm.bias_states = 1;
    cfg.aid_mm.sig0_gyro_bias_rps = 4.85e-8;
    cfg.aid_mm.sig0_acc_bias_mps2 = 9.8e-5;
#endif
#ifdef PF
    /* the cold-atom aid (aid_pf.h) with the flights' filter: 500 particles, Rao-Blackwellised,
     * 50 particles a step, 250 end passes a step; a shot at step PF_SHOT (and every 100 after) */
    cfg.aid_pf.enable = 1;
    cfg.aid_pf.chunk = 50;
    cfg.aid_pf.end_chunk = 250;
    cfg.aid_pf.pf.n = 500;
    cfg.aid_pf.pf.seed = 1U;
    cfg.aid_pf.pf.model = GG_PF_MODEL_RBPF;
    cfg.aid_pf.pf.k_eff = 1.4743e7;
    cfg.aid_pf.pf.T = 0.16;
    cfg.aid_pf.pf.dz = 1.0;
    cfg.aid_pf.pf.contrast = 0.5;
    cfg.aid_pf.pf.c0 = 0.5;
    cfg.aid_pf.pf.c1 = 0.5;
    cfg.aid_pf.pf.sigma = 1.68e-3;
    cfg.aid_pf.pf.sigma0_pos = 50.0;
    cfg.aid_pf.pf.sigma0_jerk = 4.9e-7;
    cfg.aid_pf.pf.sigma0_bias = 3.1e-4;
    cfg.aid_pf.pf.q_vel = 1.47e-4;
    cfg.aid_pf.pf.q_acc = 1.96e-5;
    cfg.aid_pf.pf.reg_bw = 1.0;
    cfg.aid_pf.pf.dt = 1.0;
    cfg.aid_pf.pf.gain = 0.05;
    cfg.aid_pf.pf.ess_frac = 1.0; /* every shot resamples and regularises: the end's worst case */
#endif
    if (gg_nav3d_init(&g_nav3, &cfg) != GG_OK) {
        m7_qemu_exit();
    }
    g_frame.n_acc = 6;
    for (j = 0; j < 6; ++j) {
        g_frame.f[j][0] = g0;
    }
    g_frame.f[0][0] = g0 - (gxx * 0.5);
    g_frame.f[3][0] = g0 + (gxx * 0.5);
    g_frame.f[1][1] = -(gyy * 0.5);
    g_frame.f[4][1] = gyy * 0.5;
    g_frame.f[2][2] = -(gyy * 0.5);
    g_frame.f[5][2] = gyy * 0.5;
    g_frame.omega_b[0] = 1.0e-3;
    g_frame.omega_b[2] = 7.0e-5;
    for (k = 0; k < STEPS; ++k) {
        g_frame.seq = k;
        g_frame.utime = (int64_t)k * 10000;
        g_frame.baro_status = ((k % 100) == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
        g_frame.baro_utime = g_frame.utime;
        g_frame.baro_alt_m = 0.0;
#ifdef PF
        g_frame.ca_status = (((k - PF_SHOT) % 100) == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
        g_frame.ca_utime = g_frame.utime;
        g_frame.ca_s[0] = 0.5 - (0.25 * (double)((k / 100) % 3));
        g_frame.ca_s[1] = 0.4 + (0.1 * (double)((k / 100) % 2));
#endif
#ifdef AID
        (void)gg_nav3d_step(&g_nav3, &g_frame, &hal, &g_out3);
        if ((k == 0) && (build_map((const double(*)[3])g_out3.gamma_b) == 0)) {
            m7_qemu_exit();
        }
#else
        (void)gg_nav3d_step(&g_nav3, &g_frame, NULL, &g_out3);
#endif
    }
    m7_qemu_exit();
    return 0;
}
#endif
