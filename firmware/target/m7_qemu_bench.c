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
 * instructions, only accepted. */
static gg_nav3d_t g_nav3;
static gg_nav3d_output_t g_out3;

int main(void)
{
    const double g0 = 9.798285;
    const double gxx = 3.0725e-6;
    const double gyy = -1.5362e-6;
    int32_t k;
    int32_t j;
    gg_nav3d_config_t cfg = {0};
    cfg.geometry.half_base_m[0] = 0.5L;
    cfg.geometry.half_base_m[1] = 0.5L;
    cfg.geometry.half_base_m[2] = 0.5L;
    cfg.platform = GG_PLATFORM_STRAPDOWN;
    cfg.dt_us = 10000;
    cfg.dt_tol_us = 100;
    cfg.r0_e[0] = 6378137.0L;
    cfg.g0_e[0] = -9.798L;
    cfg.q0_b_e[0] = 1.0L;
    cfg.f_max = 100.0;
    cfg.asym_max = 1e-6;
    cfg.gravity_mode = GG_GRAVITY_GRADIOMETER;
    cfg.baro_enable = 1;
    cfg.baro = g_m7_demo_config.baro;
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
        (void)gg_nav3d_step(&g_nav3, &g_frame, NULL, &g_out3);
    }
    m7_qemu_exit();
    return 0;
}
#endif
