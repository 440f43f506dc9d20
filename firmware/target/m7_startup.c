/* Cortex-M7 start-up shared by the images; see m7_startup.h. */
#include "m7_startup.h"

#include <stdint.h>

const gg_nav2d_config_t g_m7_demo_config = {
    .geometry = {0.5L, 0.5L},
    .dt_us = 10000,
    .dt_tol_us = 100,
    .r0 = {GG_WGS84_A_M, 0.0L, 0.0L},
    .v0 = {0.0L, 0.0L, 300.0L},
    .g0 = {-9.798L, 0.0L, 0.0L},
    .f_max = 100.0,
    .asym_max = 1e-9,
    .gravdr_trapezoid_only = 0,
    .gravity_mode = GG_GRAVITY_GRADIOMETER,
    .model = {.gm = GG_WGS84_GM_M3PS2, .a_m = GG_WGS84_A_M},
    .baro_enable = 1,
    .baro = {{0.005L, 0.01L, 0.015L}, 1.54e-6L, 1000000, 500000, 10000000, -500.0, 20000.0,
             50.0, 5},
    .r_ref_m = GG_WGS84_A_M};

extern uint32_t _sbss, _ebss, _sdata, _edata, _sidata, _estack;
void Reset_Handler(void);
void Default_Handler(void);

void Reset_Handler(void)
{
    uint32_t *src = &_sidata;
    uint32_t *dst = &_sdata;
    while (dst < &_edata) {
        *dst++ = *src++;
    }
    for (dst = &_sbss; dst < &_ebss; ++dst) {
        *dst = 0u;
    }
    /* enable the FPU (CP10, CP11 full access) */
    (*(volatile uint32_t *)0xE000ED88u) |= (0xFu << 20);
    __asm__ volatile("dsb\n\tisb");
    (void)main();
    for (;;) {
    }
}

void Default_Handler(void)
{
    m7_fault();
}

/* vector table as addresses: entry 0 is the initial stack pointer, a data
 * address, so the table is not an array of function pointers */
__attribute__((section(".isr_vector"), used)) static const uintptr_t g_vectors[16] = {
    (uintptr_t)&_estack,         (uintptr_t)Reset_Handler,   (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  (uintptr_t)Default_Handler, (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  0u, 0u, 0u, 0u,              (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  0u, (uintptr_t)Default_Handler, (uintptr_t)Default_Handler};
