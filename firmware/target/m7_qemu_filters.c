/* Instruction-count benchmark image for the Cortex-M7 (QEMU mps2-an500) of
 * the cold-atom particle filter on its own (pf.h; PF_BENCH_N particles,
 * the Rao-Blackwellised model, regularised resampling, candidates from a gmap
 * tile): STEPS shots, then exit through semihosting. scripts/m7-qemu-count
 * counts two step counts; the difference over the extra shots is the
 * per-shot figure. The filter inside the 3-D task is counted by
 * m7_qemu_bench.c. Not flown. */
#include <stdint.h>
#include <string.h>

#include "ggins/ggmath.h"
#include "ggins/gmap.h"
#include "ggins/pf.h"
#include "m7_startup.h"

#ifndef STEPS
#define STEPS 20
#endif

static gg_gmap_tile_t g_tile;
static gg_gmap_t g_map;
#ifndef PF_BENCH_N
#define PF_BENCH_N GG_PF_MAX
#endif
static gg_pf_t g_pf;

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
