/* libFuzzer harness: the map-matching filters' measurement and sensor inputs
 * (mmukf.h: gg_mm_step with its UKF core ukf.h; pf.h: gg_pf_step).
 *
 * Byte 0, bit 0 chooses the filter, bits 1-2 its variant (mmukf: gyro term
 * in the gradient measurement, vertical hold; pf: random-walk, INS or
 * Rao-Blackwellised model). Then up to 8 steps, each: 1 op byte (mmukf: bit
 * 0 a gradient measurement offered; pf: bit 0 the shot ok) and the step's
 * inputs, each a raw double or a small change of the reference value
 * (fz_value). References: the filter at rest on a synthetic linear gradient
 * map (mmukf: a 9 x 9 tile around (0.5, -1.0) rad at -100 m, level, facing
 * north; pf: a linear Gamma_zz map, 8 particles).
 * Bounds (each input's work small, docs/robustness.md "Bounds"): at most
 * MAX_STEPS steps; the gated variant makes 2 update passes (the multi-pass
 * code, as with more); 8 particles run the same code as thousands.
 * Invariants (abort = a finding): no crash or sanitizer report; a step the
 * filter refuses leaves its nominal state (mmukf) / its particles, weights
 * and correction (pf) as they were; an accepted step gives finite outputs
 * (state, sigmas, covariance; correction, mean, ESS). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ggins/gmap.h"
#include "ggins/mmukf.h"
#include "ggins/pf.h"
#include "fuzz_bytes.h"

#define FAIL(...)                                                   \
    do {                                                            \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__);     \
        fprintf(stderr, "\n");                                      \
        abort();                                                    \
    } while (0)

#define MAX_STEPS 8
static const double kW = 7.292115e-5;
static gg_gmap_t g_map;
static gg_mm_t g_mm_ref[4], g_mm;
static gg_pf_t g_pf_ref[3], g_pf;

static void field(double lat, double lon, double g6[6])
{
    const double dn = (lat - 0.5) * 6.36e6, de = (lon + 1.0) * 5.6e6;
    g6[0] = -1.54e-6 + 1e-12 * dn + 0.5e-12 * de;
    g6[1] = -1.54e-6 - 0.7e-12 * dn + 1e-12 * de;
    g6[2] = -(g6[0] + g6[1]);
    g6[3] = 1e-9 + 0.8e-12 * de;
    g6[4] = 2e-9 - 0.6e-12 * dn;
    g6[5] = -1e-9 + 0.9e-12 * dn - 0.4e-12 * de;
    for (int k = 6; k < 12; ++k) g6[k] = 0.0;
}

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
    static gg_gmap_tile_t t;
    memset(&t, 0, sizeof t);
    t.nlat = t.nlon = 9;
    t.lat0_rad = 0.5 - 4e-4;
    t.lon0_rad = -1.0 - 4e-4;
    t.dlat_rad = t.dlon_rad = 1e-4;
    t.h0_m = -100;
    t.h_range_m = 300;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) field(t.lat0_rad + i * 1e-4, t.lon0_rad + j * 1e-4, t.node[i * 9 + j]);
    if (gg_gmap_init(&g_map, &t) != GG_OK) FAIL("reference tile refused");
    for (int v = 0; v < 4; ++v) {
        gg_mm_config_t c;
        memset(&c, 0, sizeof c);
        c.dt_s = 0.1;
        c.update_period_s = 0.1;
        c.sigma_meas_s2 = 1e-11;
        c.sigma_db_s2 = 1e-12;
        c.sig0_att_rad = 1e-3;
        c.sig0_vel_mps = 0.1;
        c.sig0_pos_m = 100;
        c.sig0_bg_rps = 1e-9;
        c.sig0_ba_mps2 = 1e-5;
        c.arw_rad_rts = 1e-7;
        c.vrw_mps_rts = 1e-5;
        c.gate_nis = (v & 1) ? 30.0 : 0.0;
        c.max_passes = (v & 1) ? 2 : 1;
        c.vertical_hold = (v >> 1) & 1;
        c.init.q[0] = 1;
        c.init.lat = 0.5 + 50.0 / 6.36e6;
        c.init.lon = -1.0 + 50.0 / 5.6e6;
        c.init.h = -100;
        if (gg_mm_init(&g_mm_ref[v], &c, &g_map) != GG_OK) FAIL("reference mmukf configuration refused");
    }
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

static void run_mm(fz_cur_t *cur, unsigned variant)
{
    memcpy(&g_mm, &g_mm_ref[variant & 3u], sizeof g_mm);
    double g = 9.8;
    (void)gg_mm_normal_gravity(0.5, -100, &g);
    double g6[12];
    field(0.5, -1.0, g6);
    for (int k = 0; k < MAX_STEPS && fz_left(cur); ++k) {
        const uint8_t op = fz_u8(cur);
        gg_mm_imu_t imu = {{kW * cos(0.5), 0.0, -kW * sin(0.5)}, {0.0, 0.0, -g}};
        gg_mm_meas_t z;
        memset(&z, 0, sizeof z);
        memcpy(z.gamma_b, g6, sizeof z.gamma_b);
        z.gyro_term = (variant >> 2) & 1;
        const unsigned nchg = (op >> 1) & 15u;
        for (unsigned i = 0; i < nchg; ++i) {
            const unsigned idx = fz_u8(cur) % 16u;
            if (idx < 3u) imu.omega_b[idx] = fz_value(cur, imu.omega_b[idx]);
            else if (idx < 6u) imu.f_b[idx - 3u] = fz_value(cur, imu.f_b[idx - 3u]);
            else if (idx < 12u) z.gamma_b[idx - 6u] = fz_value(cur, z.gamma_b[idx - 6u]);
            else if (idx < 15u) z.omega_b[idx - 12u] = fz_value(cur, imu.omega_b[idx - 12u]);
            else z.sigma_omega_rps = fz_value(cur, 1e-6);
        }
        const gg_mm_nav_t before = g_mm.sig[0];
        gg_mm_output_t out;
        const gg_status_t st = gg_mm_step(&g_mm, &imu, (op & 1u) ? &z : NULL, &out);
        if (st != GG_OK) {
            if (memcmp(&before, &g_mm.sig[0], sizeof before) != 0)
                FAIL("mmukf step refused (status %d) but its nominal state changed", (int)st);
            continue;
        }
        if (!fin(out.nav.q, 4) || !fin(out.nav.v, 3) || !isfinite(out.nav.lat) || !isfinite(out.nav.lon) ||
            !isfinite(out.nav.h) || !fin(out.nav.bg, 3) || !fin(out.nav.ba, 3) || !fin(out.sigma, GG_MM_NX) ||
            !fin(&out.P[0][0], (size_t)GG_MM_NX * GG_MM_NX) || !isfinite(out.nis))
            FAIL("mmukf step %d accepted with a non-finite output (health 0x%x)", k, (unsigned)out.health);
    }
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
    if (sel & 1u) run_pf(&cur, (sel >> 1) & 3u);
    else run_mm(&cur, (sel >> 1) & 7u);
    return 0;
}
