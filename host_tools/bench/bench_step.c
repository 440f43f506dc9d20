/* Firmware step benchmark (not a test): flies the 2-D north flight with
 * perfect sensors and a 1 Hz barometer through gg_nav2d_step in-process,
 * frames precomputed, and reports the time per module from the HAL cycle
 * counter (host: CLOCK_MONOTONIC in ns). With --no-timing the step runs with
 * no cycle counter at all (for deterministic instruction counts under
 * valgrind --tool=callgrind; scripts/bench does that).
 * With --task nav3d it times gg_nav3d_step instead (strapdown body at rest
 * on the equator turning slowly, 1 Hz barometer; readings accepted, not
 * mutually exact - the timing does not depend on it).
 * Usage: bench_step [--steps N] [--mode gradiometer|model] [--task nav2d|nav3d] [--no-timing] */
#define _POSIX_C_SOURCE 200809L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ggins/nav2d.h"
#include "ggins/nav3d.h"
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

static const char *g_names[GG_MOD_COUNT] = {"diff", "gravdr/model", "mech", "vchan", "total", "aid_mm", "aid_pf"};

static void print_table(uint32_t *cyc[GG_MOD_COUNT], long steps)
{
    printf("  %-13s %9s %9s %9s\n", "module", "median", "p99", "max");
    for (int m = 0; m < GG_MOD_COUNT; ++m) {
        qsort(cyc[m] + 1, (size_t)steps - 1, sizeof(uint32_t), cmp_u32); /* step 0 = start */
        const long n = steps - 1;
        printf("  %-13s %9u %9u %9u\n", g_names[m], cyc[m][1 + n / 2], cyc[m][1 + (n * 99) / 100],
               cyc[m][n]);
    }
}

/* gg_nav3d_step: strapdown, gradiometer mode, baro loop, 1 Hz barometer */
static int bench_nav3d(long steps, int timing, int quiet)
{
    static gg_nav3d_t nav;
    gg_nav3d_config_t cfg;
    gg_frame_t fr;
    gg_nav3d_output_t out;
    uint32_t *cyc[GG_MOD_COUNT];
    long rejected = 0;
    const double g0 = 9.798285, gxx = 3.0725e-6, gyy = -1.5362e-6;
    for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[m] = calloc((size_t)steps, sizeof(uint32_t));
    if (!cyc[GG_MOD_COUNT - 1]) { fprintf(stderr, "bench_step: out of memory\n"); return 1; }
    memset(&cfg, 0, sizeof cfg);
    for (int j = 0; j < 3; ++j) cfg.geometry.half_base_m[j] = 0.5L;
    cfg.platform = GG_PLATFORM_STRAPDOWN;
    cfg.dt_us = 10000;
    cfg.dt_tol_us = 100;
    cfg.r0_e[0] = T_RE;
    cfg.g0_e[0] = -9.798L;
    cfg.q0_b_e[0] = 1.0L;
    cfg.f_max = 100.0;
    cfg.asym_max = 1e-6;
    cfg.gravity_mode = GG_GRAVITY_GRADIOMETER;
    cfg.baro_enable = 1;
    cfg.baro = (gg_vchan_config_t){{0.005L, 0.01L, 0.015L}, T_GM / (T_RE * T_RE * T_RE), 1000000,
                                   500000, 10000000, -1000.0, 30000.0, 100.0, 5};
    if (gg_nav3d_init(&nav, &cfg) != GG_OK) { fprintf(stderr, "bench_step: nav3d init failed\n"); return 1; }
    memset(&fr, 0, sizeof fr);
    fr.n_acc = 6;
    for (int j = 0; j < 6; ++j) fr.f[j][0] = g0;
    fr.f[0][0] = g0 - gxx * 0.5;
    fr.f[3][0] = g0 + gxx * 0.5;
    fr.f[1][1] = -gyy * 0.5;
    fr.f[4][1] = gyy * 0.5;
    fr.f[2][2] = -gyy * 0.5;
    fr.f[5][2] = gyy * 0.5;
    fr.omega_b[0] = 1.0e-3;
    fr.omega_b[2] = 7.0e-5;
    const gg_hal_t hal = {NULL, NULL, NULL, mono_ns, 1000000000u, NULL, NULL};
    for (long k = 0; k < steps; ++k) {
        fr.seq = k;
        fr.utime = k * 10000;
        fr.baro_status = (k % 100 == 0) ? GG_SENSOR_OK : GG_SENSOR_ABSENT;
        fr.baro_utime = fr.utime;
        if (gg_nav3d_step(&nav, &fr, timing ? &hal : NULL, &out) != GG_OK) rejected++;
        for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[m][k] = out.cycles[m];
    }
    if (!quiet) {
        printf("gg_nav3d_step, strapdown, gradiometer mode, %ld steps (%ld rejected), ns per step\n"
               "(diff = differencing + attitude + frame rotations; gravdr = ECEF dead reckoning):\n",
               steps, rejected);
        print_table(cyc, steps);
    }
    for (int m = 0; m < GG_MOD_COUNT; ++m) free(cyc[m]);
    return rejected ? 1 : 0;
}

int main(int argc, char **argv)
{
    long steps = 100000;
    int model = 0, quiet = 0, timing = 1, nav3d = 0;
    for (int i = 1; i < argc; ++i) {
        if (!strcmp(argv[i], "--steps") && i + 1 < argc) {
            steps = atol(argv[++i]);
        } else if (!strcmp(argv[i], "--mode") && i + 1 < argc) {
            ++i;
            if (!strcmp(argv[i], "model")) model = 1;
            else if (strcmp(argv[i], "gradiometer")) { fprintf(stderr, "bench_step: unknown mode %s\n", argv[i]); return 2; }
        } else if (!strcmp(argv[i], "--task") && i + 1 < argc) {
            ++i;
            if (!strcmp(argv[i], "nav3d")) nav3d = 1;
            else if (strcmp(argv[i], "nav2d")) { fprintf(stderr, "bench_step: unknown task %s\n", argv[i]); return 2; }
        } else if (!strcmp(argv[i], "--no-timing")) {
            quiet = 1;
            timing = 0;
        } else {
            fprintf(stderr, "usage: bench_step [--steps N] [--mode gradiometer|model] [--task nav2d|nav3d] [--no-timing]\n"
                            "  times gg_nav2d_step per module on the 300 m/s north flight, 100 Hz,\n"
                            "  perfect sensors, 1 Hz barometer; prints median/p99/max ns per module;\n"
                            "  --task nav3d times gg_nav3d_step (strapdown, baro loop) instead\n");
            return 2;
        }
    }
    if (steps < 2) { fprintf(stderr, "bench_step: --steps must be >= 2\n"); return 2; }
    if (nav3d) return bench_nav3d(steps, timing, quiet);
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
    const gg_hal_t hal = {NULL, NULL, NULL, mono_ns, 1000000000u, NULL, NULL};
    gg_nav_output_t out;
    long rejected = 0;
    for (long k = 0; k < steps; ++k) {
        if (gg_nav2d_step(&nav, &frames[k], timing ? &hal : NULL, &out) != GG_OK) rejected++;
        for (int m = 0; m < GG_MOD_COUNT; ++m) cyc[m][k] = out.cycles[m];
    }
    if (!quiet) {
        printf("gg_nav2d_step, %s mode, %ld steps (%ld rejected), ns per step:\n",
               model ? "gravity-model" : "gradiometer", steps, rejected);
        print_table(cyc, steps);
    }
    free(frames);
    for (int m = 0; m < GG_MOD_COUNT; ++m) free(cyc[m]);
    return rejected ? 1 : 0;
}
