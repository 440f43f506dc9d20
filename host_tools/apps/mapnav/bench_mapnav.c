#define _POSIX_C_SOURCE 199309L
/* Step times of the map-matching pieces on the host (CLOCK_MONOTONIC, median of
 * repeated calls): gmap interpolation (all six components, with gradient, Gamma_DD
 * only), one NED mechanization step, one filter step without and with the
 * measurement update (31 sigma states). Synthetic tile and data; timing only.
 * usage: bench_mapnav [reps=20000]   (callgrind: valgrind --tool=callgrind bench_mapnav 2000) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ggins/mmukf.h"

static gg_gmap_t g_map;
static gg_mm_t g_mm;

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    return v[n / 2];
}

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 20000;
    static gg_gmap_tile_t t;
    t.nlat = t.nlon = 50;
    t.lat0_rad = 0.5;
    t.lon0_rad = 2.4;
    t.dlat_rad = t.dlon_rad = 8.7e-4;
    t.h0_m = -100;
    t.h_range_m = 300;
    for (int i = 0; i < 2500; ++i)
        for (int k = 0; k < 12; ++k) t.node[i][k] = 1e-9 * ((i * 7 + k * 3) % 11) + (k == 2 ? 3e-6 : 0);
    if (gg_gmap_init(&g_map, &t) != GG_OK) return 1;
    double *v = malloc(sizeof(double) * (size_t)reps);
    gg_gmap_sample_t s;
    volatile double sink = 0;
    const char *names[3] = {"gmap_eval all 6, no gradient", "gmap_eval all 6 + gradient", "gmap_eval Gamma_DD only"};
    const uint32_t masks[3] = {GG_GMAP_MASK_ALL, GG_GMAP_MASK_ALL, GG_GMAP_MASK_DD};
    for (int m = 0; m < 3; ++m) {
        for (int r = 0; r < reps; ++r) {
            const double lat = 0.51 + 1e-6 * (r % 1000), lon = 2.41 + 2e-6 * (r % 777);
            const double t0 = now_ns();
            gg_gmap_eval(&g_map, lat, lon, -90.0, masks[m], m == 1, &s);
            v[r] = now_ns() - t0;
            sink += (double)s.gamma[2];
        }
        printf("%-34s %8.0f ns\n", names[m], median(v, reps));
    }
    gg_mm_config_t c;
    memset(&c, 0, sizeof c);
    c.dt_s = 0.1;
    c.update_period_s = 0.1; /* every step an update: times the update path */
    c.sigma_meas_s2 = 1e-11;
    c.sigma_db_s2 = 1e-12;
    c.sig0_att_rad = 8.7e-3;
    c.sig0_vel_mps = 1;
    c.sig0_pos_m = 10;
    c.sig0_bg_rps = 4.8e-8;
    c.sig0_ba_mps2 = 1e-4;
    c.arw_rad_rts = 3e-7;
    c.vrw_mps_rts = 1e-5;
    c.bg_rw = 1e-12;
    c.ba_rw = 1e-9;
    c.max_passes = 1; /* one pass: the per-update cost (the progressive passes repeat it) */
    c.init.q[0] = 1;
    c.init.lat = 0.52;
    c.init.lon = 2.42;
    c.init.h = -100;
    gg_mm_imu_t imu = {{7e-5, 0, -3e-5}, {0, 0, -9.79}};
    gg_mm_nav_t x = c.init;
    for (int r = 0; r < reps; ++r) {
        const double t0 = now_ns();
        gg_mm_mech(&x, &imu, 0.1, 1, -100, 0);
        v[r] = now_ns() - t0;
    }
    printf("%-34s %8.0f ns\n", "gg_mm_mech (one state)", median(v, reps));
    if (gg_mm_init(&g_mm, &c, &g_map) != GG_OK) return 2;
    gg_mm_output_t out;
    gg_mm_meas_t z;
    memset(&z, 0, sizeof z);
    gg_mm_predict_gradient(&g_map, &c.init, z.gamma_b);
    const int n2 = reps / 10 > 10 ? reps / 10 : 10;
    for (int r = 0; r < n2; ++r) {
        const double t0 = now_ns();
        gg_mm_step(&g_mm, &imu, NULL, &out);
        v[r] = now_ns() - t0;
    }
    printf("%-34s %8.0f ns\n", "gg_mm_step, no update (31 states)", median(v, n2));
    for (int r = 0; r < n2; ++r) {
        const double t0 = now_ns();
        gg_mm_step(&g_mm, &imu, &z, &out);
        v[r] = now_ns() - t0;
    }
    printf("%-34s %8.0f ns  (%u updates)\n", "gg_mm_step with update", median(v, n2), out.n_updates);
    free(v);
    return sink == 12345.0;
}
