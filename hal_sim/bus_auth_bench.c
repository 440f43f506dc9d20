/*
 * bus_auth_bench: the cost of authenticating one host-in-the-loop step
 * (bus_auth.h), per message type at its encoded size: MAC (sign) and verify.
 * One step of a lockstep run signs and verifies one frame and one output: the
 * sum is printed. Timing only; run by hand (docs/hil.md).
 */
#define _GNU_SOURCE
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "bus_auth.h"
#include "ggins_nav3d_output_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_sensor_frame_t.h"

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts); /* CPU time: the machine may be shared */
    return 1e9 * (double)ts.tv_sec + (double)ts.tv_nsec;
}

static uint8_t buf[4096];
static volatile int sink;

/* median of 9 repetitions of `reps` calls, ns per call */
static double per_call(int what, size_t n, int reps, const ggins_bus_key_t *k)
{
    double t[9];
    for (int r = 0; r < 9; ++r) {
        const double a = now_ns();
        for (int i = 0; i < reps; ++i) {
            buf[0] = (uint8_t)i;
            if (what == 0) sink += ggins_bus_sign(k, "GGINS_FRAME", buf, n);
            if (what == 1) sink += ggins_bus_verify(k, "GGINS_FRAME", buf, n);
        }
        t[r] = (now_ns() - a) / reps;
    }
    for (int i = 1; i < 9; ++i) /* insertion sort */
        for (int j = i; j > 0 && t[j] < t[j - 1]; --j) {
            const double x = t[j];
            t[j] = t[j - 1];
            t[j - 1] = x;
        }
    return t[4];
}

int main(void)
{
    if (ggins_bus_init() != 0) return 1;
    ggins_bus_key_t k;
    ggins_bus_key_new(&k);
    ggins_sensor_frame_t f;
    ggins_nav_output_t o;
    ggins_nav3d_output_t o3;
    memset(&f, 0, sizeof f);
    memset(&o, 0, sizeof o);
    memset(&o3, 0, sizeof o3);
    const struct {
        const char *name;
        int n;
    } t[] = {{"sensor_frame_t", ggins_sensor_frame_t_encoded_size(&f)},
             {"nav_output_t", ggins_nav_output_t_encoded_size(&o)},
             {"nav3d_output_t", ggins_nav3d_output_t_encoded_size(&o3)}};
    double step2 = 0, step3 = 0;
    printf("%-16s %6s %10s %10s   (CPU ns per call, median of 9 x 20000)\n", "message", "bytes", "sign", "verify");
    for (int i = 0; i < 3; ++i) {
        const double s = per_call(0, (size_t)t[i].n, 20000, &k), v = per_call(1, (size_t)t[i].n, 20000, &k);
        printf("%-16s %6d %10.0f %10.0f\n", t[i].name, t[i].n, s, v);
        if (i != 2) step2 += s + v;
        if (i != 1) step3 += s + v;
    }
    printf("per lockstep step (frame + output, each signed and verified): 2-D %.0f ns, 3-D %.0f ns\n", step2, step3);
    return 0;
}
