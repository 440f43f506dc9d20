/* Instruction-count benchmark image for the Cortex-M7 (QEMU mps2-an500):
 * runs STEPS navigation steps on a stationary platform with a 1 Hz
 * barometer, then exits through semihosting. scripts/m7-qemu-count runs it
 * for two step counts under QEMU with one instruction per translation block
 * and counts executed instructions; the difference over the extra steps is
 * the instructions per step of the Thumb-2 build. Not flown. */
#include <stdint.h>

#include "ggins/nav2d.h"
#include "m7_startup.h"

#ifndef STEPS
#define STEPS 100
#endif

static gg_nav2d_t g_nav;
static gg_frame_t g_frame;
static gg_nav_output_t g_out;

static void semihost_exit(void)
{
    /* SYS_EXIT (0x18), ADP_Stopped_ApplicationExit */
    register uint32_t r0 __asm__("r0") = 0x18u;
    register uint32_t r1 __asm__("r1") = 0x20026u;
    __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}

void m7_fault(void)
{
    semihost_exit();
    for (;;) {
    }
}

int main(void)
{
    /* readings of a platform at rest at the equator: f = -G(r + d_i),
     * gradient 2 GM/r^3 radially, -GM/r^3 across */
    const double g0 = 9.798285;
    const double gxx = 3.0725e-6;
    const double gzz = -1.5362e-6;
    int32_t k;
    if (gg_nav2d_init(&g_nav, &g_m7_demo_config) != GG_OK) {
        semihost_exit();
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
    semihost_exit();
    return 0;
}

