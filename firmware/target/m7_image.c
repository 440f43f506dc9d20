/* Minimal bare-metal image for the Cortex-M7 build: a vector table, a reset
 * handler that zeroes .bss, and a main loop that runs the navigation task
 * over a HAL reading frames from a buffer (a board would fill it from its
 * accelerometer drivers) and timing with the DWT cycle counter. It exists
 * so the size report and the "no heap, no stdio" link check see a real
 * program; it is not flown. */
#include <stdint.h>

#include "ggins/hal.h"
#include "ggins/nav2d.h"
#include "m7_startup.h"

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

void m7_fault(void)
{
    for (;;) {
    }
}

int main(void)
{
    const gg_hal_t hal = {&g_io, board_read, board_write, board_cycles, 480000000u, NULL, NULL};
    DEMCR |= (1u << 24);   /* TRCENA */
    DWT_CYCCNT = 0u;
    DWT_CTRL |= 1u;        /* CYCCNTENA */
    if (gg_nav2d_init(&g_nav, &g_m7_demo_config) != GG_OK) {
        for (;;) {
        }
    }
    for (;;) {
        (void)gg_nav2d_task_cycle(&g_nav, &hal);
    }
}
