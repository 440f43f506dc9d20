/* Shared by the Cortex-M7 images (m7_image.c, m7_qemu_bench.c): the demo
 * navigation configuration, and the start-up code (m7_startup.c: vector
 * table, reset handler that copies .data, zeroes .bss, enables the FPU and
 * calls main). Each image provides m7_fault(), called on any exception. */
#ifndef GGINS_M7_STARTUP_H
#define GGINS_M7_STARTUP_H

#include "ggins/nav2d.h"

/** The 2-D configuration the images fly: 0.5 m half-baselines, 100 Hz,
 *  gradiometer gravity, barometric loop on. */
extern const gg_nav2d_config_t g_m7_demo_config;

int main(void);

/** Called by the default exception handler; must not return. */
void m7_fault(void);

/** QEMU images only (m7_qemu_exit.c): end the run through semihosting. */
void m7_qemu_exit(void);

#endif
