/* Firmware step benchmark (not a test): flies the 2-D north flight with
 * perfect sensors and a 1 Hz barometer through gg_nav2d_step in-process,
 * frames precomputed, and reports the time per module from the HAL cycle
 * counter (host: CLOCK_MONOTONIC in ns). With --no-timing the step runs with
 * no cycle counter at all (for deterministic instruction counts under
 * valgrind --tool=callgrind; scripts/bench does that).
 * Usage: bench_step [--steps N] [--mode gradiometer|model] [--no-timing] */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ggins/nav2d.h"
#include "truth2d.h"

static uint32_t mono_ns(void *ctx)
{
    struct timespec ts;
    (void)ctx;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (uint32_t)((uint64_t)ts.tv_sec * 1000000000u + (uint64_t)ts.tv_nsec);
}

static int cmp_u32(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    long steps = 100000;
    int model = 0, quiet = 0, timing = 1;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--steps") && i + 1 < argc) {
            steps = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--mode") && i + 1 < argc) {
            ++i;
            if (!strcmp(argv[i], "model")) model = 1;
            else if (strcmp(argv[i], "gradiometer")) { fprintf(stderr, "bench_step: unknown mode %s\n", argv[i]); return 2; }
        } else if (!strcmp(argv[i], "--no-timing")) {
            quiet = 1;
            timing = 0;
        } else {
            fprintf(stderr, "usage: bench_step [--steps N] [--mode gradiometer|model] [--no-timing]\n"
                            "  times gg_nav2d_step per module on the 300 m/s north flight, 100 Hz,\n"
                            "  perfect sensors, 1 Hz barometer; prints median/p99/max ns per module\n");
            return 2;
        }
    }
    if (steps < 2) { fprintf(stderr, "bench_step: --steps must be >= 2\n"); return 2; }
    const t_flight_t fl = {300.0L, 0.0L, 0.0L};
    gg_frame_t *frames = calloc((size_t)steps, sizeof *frames);
    uint32_t *cyc[GG_MOD_COUNT];
    for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[m] = calloc((size_t)steps, sizeof(uint32_t));
    if (!frames || !cyc[GG_MOD_COUNT - 1]) { fprintf(stderr, "bench_step: out of memory\n"); return 1; }
    for (long k = 0; k < steps; ++k) t_make_frame(&fl, k, 10000, 0, NULL, 100, &frames[k]);
    gg_nav2d_config_t cfg;
    memset(&cfg, 0, sizeof cfg);
    {
        long double r[3], v[3], a[3], g[3];
        t_flight(&fl, 0.0L, r, v, a);
        t_point_mass_g(r, g);
        for (int j = 0; j < 3; ++j) { cfg.r0[j] = r[j]; cfg.v0[j] = v[j]; cfg.g0[j] = g[j]; }
    }
    cfg.geometry.a_m = cfg.geometry.b_m = 0.5L;
    cfg.dt_us = 10000;
    cfg.dt_tol_us = 100;
    cfg.f_max = 100.0;
    cfg.asym_max = 1e-9;
    cfg.gravity_mode = model ? GG_GRAVITY_MODEL : GG_GRAVITY_GRADIOMETER;
    cfg.model.gm = T_GM;
    cfg.model.a_m = T_RE;
    cfg.model.j[2] = 1.08262982131e-3L;
    cfg.model.j[4] = -2.37091120053e-6L;
    cfg.model.j[6] = 6.08346498882e-9L;
    cfg.model.j[8] = -1.42681087920e-11L;
    cfg.baro_enable = 1;
    cfg.baro = (gg_vchan_config_t){{0.005L, 0.01L, 0.015L}, T_GM / (T_RE * T_RE * T_RE), 1000000,
                                   500000, 10000000, -1000.0, 30000.0, 100.0, 5};
    cfg.r_ref_m = T_RE;
    gg_nav2d_t nav;
    if (gg_nav2d_init(&nav, &cfg) != GG_OK) { fprintf(stderr, "bench_step: init failed\n"); return 1; }
    const gg_hal_t hal = {NULL, NULL, NULL, mono_ns, 1000000000u, NULL};
    gg_nav_output_t out;
    long rejected = 0;
    for (long k = 0; k < steps; ++k) {
        if (gg_nav2d_step(&nav, &frames[k], timing ? &hal : NULL, &out) != GG_OK) rejected++;
        for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[m][k] = out.cycles[m];
    }
    if (!quiet) {
        static const char *names[GG_MOD_COUNT] = {"diff", "gravdr/model", "mech", "vchan", "total"};
        printf("gg_nav2d_step, %s mode, %ld steps (%ld rejected), ns per step:\n",
               model ? "gravity-model" : "gradiometer", steps, rejected);
        printf("  %-13s %9s %9s %9s\n", "module", "median", "p99", "max");
        for (int m = 0; m < GG_MOD_COUNT; ++m) {
            qsort(cyc[m] + 1, (size_t)steps - 1, sizeof(uint32_t), cmp_u32); /* step 0 = start */
            const long n = steps - 1;
            printf("  %-13s %9u %9u %9u\n", names[m], cyc[m][1 + n / 2], cyc[m][1 + (n * 99) / 100],
                   cyc[m][n]);
        }
    }
    free(frames);
    for (int m = 0; m < GG_MOD_COUNT; ++m) free(cyc[m]);
    return rejected ? 1 : 0;
}
