/* Minimal bare-metal image for the Cortex-M7 build: a vector table, a reset
 * handler that zeroes .bss, and a main loop that runs the navigation task
 * over a HAL reading frames from a buffer (a board would fill it from its
 * accelerometer drivers) and timing with the DWT cycle counter. It exists
 * so the size report and the "no heap, no stdio" link check see a real
 * program; it is not flown. */
#include <stdint.h>

#include "ggins/hal.h"
#include "ggins/nav2d.h"

#define DWT_CTRL (*(volatile uint32_t *)0xE0001000u)
#define DWT_CYCCNT (*(volatile uint32_t *)0xE0001004u)
#define DEMCR (*(volatile uint32_t *)0xE000EDFCu)

typedef struct {
    gg_frame_t frame;    /* written by the sensor interrupt on a board */
    volatile int ready;
    gg_nav_output_t out; /* read by the telemetry link on a board */
} board_io_t;

static gg_status_t board_read(void *ctx, gg_frame_t *frame)
{
    board_io_t *io = (board_io_t *)ctx;
    if (io->ready == 0) {
        return GG_ERR_NO_DATA;
    }
    *frame = io->frame;
    io->ready = 0;
    return GG_OK;
}

static gg_status_t board_write(void *ctx, const gg_nav_output_t *out)
{
    board_io_t *io = (board_io_t *)ctx;
    io->out = *out;
    return GG_OK;
}

static uint32_t board_cycles(void *ctx)
{
    (void)ctx;
    return DWT_CYCCNT;
}

static board_io_t g_io;
static gg_nav2d_t g_nav;

int main(void);
int main(void)
{
    static const gg_nav2d_config_t cfg = {
        .geometry = {0.5L, 0.5L},
        .dt_us = 10000,
        .dt_tol_us = 100,
        .r0 = {6378137.0L, 0.0L, 0.0L},
        .v0 = {0.0L, 0.0L, 300.0L},
        .g0 = {-9.798L, 0.0L, 0.0L},
        .f_max = 100.0,
        .asym_max = 1e-9,
        .gravdr_trapezoid_only = 0,
        .gravity_mode = GG_GRAVITY_GRADIOMETER,
        .model = {3.986004418e14L, 6378137.0L, {0.0L}},
        .baro_enable = 1,
        .baro = {{0.005L, 0.01L, 0.015L}, 1.54e-6L, 1000000, 500000, 10000000, -500.0,
                 20000.0, 50.0, 5},
        .r_ref_m = 6378137.0L};
    const gg_hal_t hal = {&g_io, board_read, board_write, board_cycles, 480000000u};
    DEMCR |= (1u << 24);   /* TRCENA */
    DWT_CYCCNT = 0u;
    DWT_CTRL |= 1u;        /* CYCCNTENA */
    if (gg_nav2d_init(&g_nav, &cfg) != GG_OK) {
        for (;;) {
        }
    }
    for (;;) {
        (void)gg_nav2d_task_cycle(&g_nav, &hal);
    }
}

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
    (void)main();
    for (;;) {
    }
}

void Default_Handler(void)
{
    for (;;) {
    }
}

/* vector table as addresses: entry 0 is the initial stack pointer, a data
 * address, so the table is not an array of function pointers */
__attribute__((section(".isr_vector"), used)) static const uintptr_t g_vectors[16] = {
    (uintptr_t)&_estack,         (uintptr_t)Reset_Handler,   (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  (uintptr_t)Default_Handler, (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  0u, 0u, 0u, 0u,              (uintptr_t)Default_Handler,
    (uintptr_t)Default_Handler,  0u, (uintptr_t)Default_Handler, (uintptr_t)Default_Handler};
