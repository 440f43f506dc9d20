/* Shared by the QEMU instruction-count images (m7_qemu_bench.c,
 * m7_qemu_filters.c): leave QEMU through semihosting, and the fault hook
 * m7_startup.c calls on any exception (it ends the run too). */
#include <stdint.h>

#include "m7_startup.h"

void m7_qemu_exit(void)
{
    /* SYS_EXIT (0x18), ADP_Stopped_ApplicationExit */
    register uint32_t r0 __asm__("r0") = 0x18u;
    register uint32_t r1 __asm__("r1") = 0x20026u;
    __asm__ volatile("bkpt 0xab" : : "r"(r0), "r"(r1) : "memory");
}

void m7_fault(void)
{
    m7_qemu_exit();
    for (;;) {
    }
}
