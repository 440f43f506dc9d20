/* libFuzzer harness: the cold-atom particle filter's sensor and INS inputs
 * (pf.h: gg_pf_step). The gradient-map UKF's inputs reach it through the 3-D
 * task and are fuzzed there (fuzz_nav3d.c, with its UKF core ukf.h).
 *
 * Byte 0, bits 1-2 choose the filter's model (random-walk, INS or
 * Rao-Blackwellised; bit 0 is not read). Then up to 8 steps, each: 1 op byte
 * (bit 0 the shot ok) and the step's inputs, each a raw double or a small
 * change of the reference value (fz_value). Reference: the filter on a
 * linear Gamma_zz map, 8 particles.
 * Bounds (each input's work small, docs/robustness.md "Bounds"): at most
 * MAX_STEPS steps; 8 particles run the same code as thousands.
 * Invariants (abort = a finding): no crash or sanitizer report; a step the
 * filter refuses leaves its particles, weights and correction as they were;
 * an accepted step gives finite outputs (correction, mean, ESS). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ggins/pf.h"
#include "fuzz_bytes.h"

#define FAIL(...)                                                   \
    do {                                                            \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__);     \
        fprintf(stderr, "\n");                                      \
        abort();                                                    \
    } while (0)

#define MAX_STEPS 8
static gg_pf_t g_pf_ref[3], g_pf;

#define PF_LAT0 0.8
#define PF_LON0 -0.03
#define PF_H0 3000.0
static gg_status_t map_lin(const void *ctx, double lat, double lon, double h, double *g)
{
    (void)ctx;
    (void)h;
    if (!isfinite(lat) || !isfinite(lon) || fabs(lat - PF_LAT0) > 0.01 || fabs(lon - PF_LON0) > 0.01)
        return GG_ERR_RANGE;
    *g = 3.08e-6 + 3.0e-9 * (lon - PF_LON0) * 4.4e6;
    return GG_OK;
}

static void setup(void)
{
    for (int m = 0; m < 3; ++m) {
        gg_pf_config_t c;
        memset(&c, 0, sizeof c);
        c.n = 8;
        c.seed = 1;
        c.k_eff = 4 * 3.14159265358979323846 / 852.347e-9;
        c.T = 0.16;
        c.dz = 1.0;
        c.contrast = 0.5;
        c.c0 = 0.5;
        c.c1 = 0.5;
        c.sigma = 0.01;
        c.sigma0_pos = 100.0;
        c.sigma0_vel = 0.1;
        c.q_pos = 0.1;
        c.q_vel = 0.01;
        c.model = m;
        c.sigma0_acc = 1e-4;
        c.q_acc = 1e-6;
        c.sigma0_jerk = 1e-7;
        c.q_jerk = 1e-9;
        c.sigma0_bias = 1e-4;
        c.q_bias = 1e-7;
        c.reg_bw = (m == 0) ? 0.5 : 0.0;
        c.dt = 1.0;
        c.gain = 1.0;
        c.ess_frac = 0.5;
        c.map.gzz = map_lin;
        c.map.ctx = NULL;
        if (gg_pf_init(&g_pf_ref[m], &c) != GG_OK) FAIL("reference particle filter configuration %d refused", m);
    }
}

static int fin(const double *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

static void run_pf(fz_cur_t *cur, unsigned variant)
{
    memcpy(&g_pf, &g_pf_ref[variant % 3u], sizeof g_pf);
    static double x[GG_PF_MAX][GG_PF_NX], w[GG_PF_MAX];
    const int n = g_pf.cfg.n;
    for (int k = 0; k < MAX_STEPS && fz_left(cur); ++k) {
        const uint8_t op = fz_u8(cur);
        gg_pf_input_t in = {PF_LAT0, PF_LON0, PF_H0, (int)(op & 1u), 0.5, 0.5, 100.0, 50.0};
        const unsigned nchg = (op >> 1) & 7u;
        for (unsigned i = 0; i < nchg; ++i) {
            const unsigned idx = fz_u8(cur) % 8u;
            switch (idx) {
            case 0: in.lat = fz_value(cur, in.lat); break;
            case 1: in.lon = fz_value(cur, in.lon); break;
            case 2: in.h = fz_value(cur, in.h); break;
            case 3: in.s0 = fz_value(cur, in.s0); break;
            case 4: in.s1 = fz_value(cur, in.s1); break;
            case 5: in.vn = fz_value(cur, in.vn); break;
            case 6: in.ve = fz_value(cur, in.ve); break;
            default: in.shot_ok = (int)(int8_t)fz_u8(cur); break;
            }
        }
        memcpy(x, g_pf.x, sizeof(double) * GG_PF_NX * (size_t)n);
        memcpy(w, g_pf.w, sizeof(double) * (size_t)n);
        const double c0 = g_pf.corr[0], c1 = g_pf.corr[1];
        gg_pf_output_t out;
        const gg_status_t st = gg_pf_step(&g_pf, &in, &out);
        if (st != GG_OK) {
            if (memcmp(x, g_pf.x, sizeof(double) * GG_PF_NX * (size_t)n) != 0 ||
                memcmp(w, g_pf.w, sizeof(double) * (size_t)n) != 0 || c0 != g_pf.corr[0] || c1 != g_pf.corr[1])
                FAIL("pf step refused (status %d) but the particles changed", (int)st);
            continue;
        }
        if (!fin(out.corr, 2) || !fin(out.mean, GG_PF_NX) || !isfinite(out.ess) || !isfinite(out.gzz_mean))
            FAIL("pf step %d accepted with a non-finite output (health 0x%x)", k, (unsigned)out.health);
        if (!fin(&g_pf.x[0][0], (size_t)GG_PF_NX * (size_t)n) || !fin(g_pf.w, (size_t)n))
            FAIL("pf step %d accepted but a particle or weight is non-finite", k);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int ready = 0;
    if (!ready) {
        setup();
        ready = 1;
    }
    fz_cur_t cur = {data, size, 0};
    const uint8_t sel = fz_u8(&cur);
    run_pf(&cur, (sel >> 1) & 3u);
    return 0;
}
