/* Instruction-count benchmark images for the Cortex-M7 (QEMU mps2-an500) of
 * the filters. Built with -DPF_BENCH: STEPS shots of the cold-atom particle
 * filter (pf.h; 500 particles, INS error model, regularised
 * resampling, candidates from a gmap tile: the settings of
 * host_tools/apps/coldatom/pf_bench.cpp). Otherwise the map-matching filter
 * (mmukf.h): STEPS filter steps at 10 Hz
 * on a level platform at rest over a synthetic 50 x 50 gradient tile, then
 * exit through semihosting. MM_UPDATE = 0: propagation only (31 sigma
 * states through the NED mechanization); MM_UPDATE = 1: a one-pass
 * measurement update at every step (the measurement is the map's own
 * prediction at the initial state, so the filter stays converged and the
 * pass count fixed). scripts/m7-qemu-count counts two step counts; the
 * difference over the extra steps is the per-step figure. Not flown. */
#include <stdint.h>
#include <string.h>

#include "ggins/mmukf.h"
#include "ggins/ggmath.h"
#include "ggins/pf.h"
#include "m7_startup.h"

#ifndef STEPS
#define STEPS 20
#endif
#ifndef MM_UPDATE
#define MM_UPDATE 0
#endif

static gg_gmap_tile_t g_tile;
static gg_gmap_t g_map;
#ifdef PF_BENCH
#ifndef PF_BENCH_N
#define PF_BENCH_N GG_PF_MAX
#endif
static gg_pf_t g_pf;
#else
static gg_mm_t g_mm;
static gg_mm_output_t g_out;
#endif

#ifdef PF_BENCH
int main(void)
{
    gg_pf_config_t c;
    gg_pf_output_t o;
    int32_t i;
    int32_t j;
    int32_t k;
    /* Gamma_DD varying smoothly over the tile (quadratic, no libm), d/dh as
     * the normal field's */
    g_tile.nlat = 50;
    g_tile.nlon = 50;
    g_tile.lat0_rad = 0.8;
    g_tile.lon0_rad = -0.03;
    g_tile.dlat_rad = 4.0e-5;
    g_tile.dlon_rad = 6.0e-5;
    g_tile.h0_m = 3000.0;
    g_tile.h_range_m = 1000.0;
    for (i = 0; i < 50; ++i) {
        for (j = 0; j < 50; ++j) {
            const double u = ((double)i - 25.0) / 25.0;
            const double v = ((double)j - 25.0) / 25.0;
            g_tile.node[(i * 50) + j][GG_GMAP_C_DD] = 3.08e-6 + (2.0e-8 * ((u * u) - (0.5 * u * v)));
            g_tile.node[(i * 50) + j][GG_GMAP_NCOMP + GG_GMAP_C_DD] = -1.45e-12;
        }
    }
    if (gg_gmap_init(&g_map, &g_tile) != GG_OK) {
        m7_qemu_exit();
    }
    (void)memset(&c, 0, sizeof c);
    c.n = PF_BENCH_N;
    c.seed = 1U;
    c.k_eff = 1.4743e7;
    c.T = 0.16;
    c.dz = 1.0;
    c.contrast = 0.5;
    c.c0 = 0.5;
    c.c1 = 0.5;
    c.sigma = 0.003;
    c.sigma0_pos = 300.0;
    c.sigma0_vel = 0.05;
    c.dt = 1.0;
    c.gain = 0.05;
    c.ess_frac = 0.5;
    c.model = GG_PF_MODEL_RBPF; /* the flights' filter (flight.cpp, Table I) */
    c.sigma0_vel = 0.0;
    c.q_pos = 0.0;
    c.q_vel = 1.47e-4;
    c.q_acc = 1.96e-5;
    c.sigma0_jerk = 4.9e-7;
    c.sigma0_bias = 3.1e-4;
    c.reg_bw = 1.0;
    if ((gg_pf_map_from_gmap(&g_map, &c.map) != GG_OK) || (gg_pf_init(&g_pf, &c) != GG_OK)) {
        m7_qemu_exit();
    }
    for (k = 0; k < STEPS; ++k) {
        /* a pair on the ellipse of ~3080 E with the shared phase turning 0.7 rad per shot */
        double s0 = 0.0;
        double c0 = 1.0;
        double s1 = 0.0;
        double c1 = 1.0;
        gg_pf_input_t in;
        (void)gg_sincos_d(0.7 * (double)k, &s0, &c0);
        (void)gg_sincos_d((0.7 * (double)k) + 1.16, &s1, &c1);
        in.lat = 0.8 + (25.0 * 4.0e-5);
        in.lon = -0.03 + (25.0 * 6.0e-5);
        in.h = 3000.0;
        in.shot_ok = 1;
        in.s0 = 0.5 - (0.25 * c0);
        in.s1 = 0.5 - (0.25 * c1);
        in.vn = -97.0;
        in.ve = 26.0;
        (void)gg_pf_step(&g_pf, &in, &o);
    }
    m7_qemu_exit();
    return 0;
}
#else
int main(void)
{
    gg_mm_config_t c;
    gg_mm_meas_t z;
    (void)memset(&z, 0, sizeof z);
    const gg_mm_imu_t imu = {{7.0e-5, 0.0, -3.0e-5}, {0.0, 0.0, -9.79}};
    int32_t i;
    int32_t k;
    /* smooth synthetic tile (same values as host_tools/apps/mapnav/bench_mapnav.c) */
    g_tile.nlat = 50;
    g_tile.nlon = 50;
    g_tile.lat0_rad = 0.5;
    g_tile.lon0_rad = 2.4;
    g_tile.dlat_rad = 8.7e-4;
    g_tile.dlon_rad = 8.7e-4;
    g_tile.h0_m = -100.0;
    g_tile.h_range_m = 300.0;
    for (i = 0; i < 2500; ++i) {
        for (k = 0; k < 12; ++k) {
            g_tile.node[i][k] = (1.0e-9 * (double)(((i * 7) + (k * 3)) % 11)) + ((k == 2) ? 3.0e-6 : 0.0);
        }
    }
    if (gg_gmap_init(&g_map, &g_tile) != GG_OK) {
        m7_qemu_exit();
    }
    (void)memset(&c, 0, sizeof c);
    c.dt_s = 0.1;
    c.update_period_s = 0.1;
    c.sigma_meas_s2 = 1.0e-11;
    c.sigma_db_s2 = 1.0e-12;
    c.sig0_att_rad = 8.7e-3;
    c.sig0_vel_mps = 1.0;
    c.sig0_pos_m = 10.0;
    c.sig0_bg_rps = 4.8e-8;
    c.sig0_ba_mps2 = 1.0e-4;
    c.arw_rad_rts = 3.0e-7;
    c.vrw_mps_rts = 1.0e-5;
    c.bg_rw = 1.0e-12;
    c.ba_rw = 1.0e-9;
    c.max_passes = 1;
    c.init.q[0] = 1.0;
    c.init.lat = 0.52;
    c.init.lon = 2.42;
    c.init.h = -100.0;
    if (gg_mm_init(&g_mm, &c, &g_map) != GG_OK) {
        m7_qemu_exit();
    }
    if (gg_mm_predict_gradient(&g_map, &c.init, z.gamma_b) != GG_OK) {
        m7_qemu_exit();
    }
    for (k = 0; k < STEPS; ++k) {
        (void)gg_mm_step(&g_mm, &imu, (MM_UPDATE != 0) ? &z : NULL, &g_out);
    }
    m7_qemu_exit();
    return 0;
}
#endif
