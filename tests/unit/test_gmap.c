/* Onboard gradient map (gmap): interpolation against analytic fields.
 *  - a polynomial of degree 3 in lat times degree 3 in lon, linear in h, is
 *    reproduced exactly (value and gradient, to rounding);
 *  - x^4 is NOT: the error is the Lagrange remainder u(u-1)(u-2)(u-3) d^4
 *    exactly (an independent closed form; proves the order is 4, not more);
 *  - the binary tile format round-trips through a hand-written blob;
 *  - bad tiles, bad inputs and points outside the tile are rejected, output
 *    and state untouched. (Against the EGM96 model: tests/gmap/.) */
#include "test_common.h"
#include "ggins/gmap.h"
#include "ggins/ggmath.h"

static gg_gmap_t g_map; /* 240 kB: static */
static gg_gmap_tile_t g_tile;

static const double kLat0 = 0.52, kLon0 = -1.10, kD = 1.0e-3, kH0 = -100.0;

/* the analytic field: x, y in grid units from the tile origin, dh in m */
static long double poly(int c, long double x, long double y, long double dh)
{
    const long double a = 1.0L + 0.1L * c;
    const long double p = a * (1e-9L + 2e-10L * x - 3e-11L * x * x + 4e-12L * x * x * x) *
                              (1.0L + 0.3L * y - 0.02L * y * y + 0.003L * y * y * y) +
                          5e-11L * x * y * y * y - 7e-12L * x * x * x * y * y;
    const long double q = 1e-12L * (1.0L + 0.5L * x * y - 0.01L * x * x * y * y * y + c);
    return p + dh * q;
}

/* analytic derivatives by the same formula differentiated by hand */
static void poly_grad(int c, long double x, long double y, long double dh, long double g[3])
{
    const long double a = 1.0L + 0.1L * c;
    const long double px = 1e-9L + 2e-10L * x - 3e-11L * x * x + 4e-12L * x * x * x;
    const long double dpx = 2e-10L - 6e-11L * x + 12e-12L * x * x;
    const long double py = 1.0L + 0.3L * y - 0.02L * y * y + 0.003L * y * y * y;
    const long double dpy = 0.3L - 0.04L * y + 0.009L * y * y;
    const long double dx = a * dpx * py + 5e-11L * y * y * y - 21e-12L * x * x * y * y +
                           dh * 1e-12L * (0.5L * y - 0.02L * x * y * y * y);
    const long double dy = a * px * dpy + 15e-11L * x * y * y - 14e-12L * x * x * x * y +
                           dh * 1e-12L * (0.5L * x - 0.03L * x * x * y * y);
    g[0] = dx / kD; /* per rad */
    g[1] = dy / kD;
    g[2] = 1e-12L * (1.0L + 0.5L * x * y - 0.01L * x * x * y * y * y + c);
}

static void fill_tile(int nlat, int nlon, int quartic)
{
    memset(&g_tile, 0, sizeof g_tile);
    g_tile.nlat = nlat;
    g_tile.nlon = nlon;
    g_tile.lat0_rad = kLat0;
    g_tile.lon0_rad = kLon0;
    g_tile.dlat_rad = kD;
    g_tile.dlon_rad = kD;
    g_tile.h0_m = kH0;
    g_tile.h_range_m = 500.0;
    g_tile.nmax = 360;
    for (int i = 0; i < nlat; ++i) {
        for (int j = 0; j < nlon; ++j) {
            for (int c = 0; c < GG_GMAP_NCOMP; ++c) {
                const long double x = i, y = j;
                long double v = poly(c, x, y, 0), dv = poly(c, x, y, 1) - poly(c, x, y, 0);
                if (quartic) {
                    v = x * x * x * x * 1e-12L;
                    dv = 0;
                }
                g_tile.node[i * nlon + j][c] = (double)v;
                g_tile.node[i * nlon + j][c + 6] = (double)dv;
            }
        }
    }
}

static void test_cubic_polynomial_exact(void **state)
{
    (void)state;
    fill_tile(9, 7, 0);
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
    long double worst_v = 0, worst_g = 0;
    /* interior and edge cells, off-grid, several heights */
    for (int k = 0; k < 200; ++k) {
        const long double x = 8.0L * (long double)((k * 37) % 101) / 100.0L;
        const long double y = 6.0L * (long double)((k * 53) % 97) / 96.0L;
        const long double dh = -400.0L + 8.0L * (long double)(k % 101);
        gg_gmap_sample_t s;
        assert_int_equal(gg_gmap_eval(&g_map, kLat0 + x * kD, kLon0 + y * kD, kH0 + dh,
                                      GG_GMAP_MASK_ALL, 1, &s),
                         GG_OK);
        for (int c = 0; c < 6; ++c) {
            const long double want = poly(c, x, y, dh);
            long double gw[3];
            poly_grad(c, x, y, dh, gw);
            const long double ev = fabsl(s.gamma[c] - want);
            if (ev > worst_v) worst_v = ev;
            for (int q = 0; q < 3; ++q) {
                const long double eg = fabsl(s.dgamma[c][q] - gw[q]) / (fabsl(gw[q]) + 1e-12L);
                if (eg > worst_g) worst_g = eg;
            }
        }
    }
    printf("  cubic: worst value error %.3Le s^-2 (values ~1e-8), worst relative gradient error %.3Le\n",
           worst_v, worst_g);
    /* values ~1e-8 stored as double (rel 1.1e-16): rounding ~1e-23 */
    assert_true(worst_v < 1e-21L);
    assert_true(worst_g < 1e-9L);
}

/* A tile across the antimeridian (lon0 = pi - 3 cells, 9 columns: 5 beyond +pi): the cubic is
 * reproduced at longitudes given on the far side as -pi + y', as at the same points given
 * beyond +pi, the gradient too; the storage's offset agrees; points a cell west of the tile and
 * a cell east of its last column are outside; a tile of 2 pi or more, or lon0 beyond pi, is
 * refused. */
static void test_antimeridian(void **state)
{
    (void)state;
    fill_tile(7, 9, 0);
    const double lon0 = (double)GG_PI - 3.0 * kD;
    g_tile.lon0_rad = lon0;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
    long double worst_v = 0, worst_g = 0;
    for (int k = 0; k < 100; ++k) {
        const long double x = 6.0L * (long double)((k * 37) % 101) / 100.0L;
        const long double y = 8.0L * (long double)((k * 53) % 97) / 96.0L;
        long double lon = (long double)lon0 + y * kD; /* beyond +pi for y > 3 */
        if (lon > (long double)GG_PI) lon -= 2.0L * (long double)GG_PI;
        gg_gmap_sample_t s;
        assert_int_equal(gg_gmap_eval(&g_map, kLat0 + x * kD, lon, kH0, GG_GMAP_MASK_ALL, 1, &s), GG_OK);
        double off = 0.0;
        assert_int_equal(gg_gmap_lon_offset(&g_map, (double)lon, &off), GG_OK);
        assert_true(fabsl((long double)off - y * kD) < 1e-12L);
        for (int c = 0; c < 6; ++c) {
            long double gw[3];
            poly_grad(c, x, y, 0, gw);
            const long double ev = fabsl(s.gamma[c] - poly(c, x, y, 0));
            if (ev > worst_v) worst_v = ev;
            for (int q = 0; q < 3; ++q) {
                const long double eg = fabsl(s.dgamma[c][q] - gw[q]) / (fabsl(gw[q]) + 1e-12L);
                if (eg > worst_g) worst_g = eg;
            }
        }
    }
    printf("  antimeridian: worst value error %.3Le s^-2, worst relative gradient error %.3Le\n", worst_v, worst_g);
    /* as the cubic test: the nodes' double rounding (the far-side longitudes round to 4e-16
     * rad = 4e-13 cells, times slopes ~1e-10 per cell) */
    assert_true(worst_v < 1e-21L);
    assert_true(worst_g < 1e-9L);
    gg_gmap_sample_t s;
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, lon0 - kD, kH0, GG_GMAP_MASK_ALL, 0, &s), GG_ERR_RANGE);
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, lon0 + 9.0 * kD - 2.0 * GG_PI, kH0, GG_GMAP_MASK_ALL, 0, &s),
                     GG_ERR_RANGE);
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, 0.0, kH0, GG_GMAP_MASK_ALL, 0, &s), GG_ERR_RANGE);
    g_tile.lon0_rad = (double)GG_PI + kD;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.lon0_rad = -1.0;
    g_tile.dlon_rad = 2.0 * (double)GG_PI / 8.0; /* 9 columns: 2 pi */
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
}

/* f = x^4 (grid units): the cubic Lagrange interpolant through nodes s..s+3
 * misses by exactly (x-s)(x-s-1)(x-s-2)(x-s-3) (the fourth derivative is 24). */
static void test_quartic_remainder(void **state)
{
    (void)state;
    fill_tile(8, 8, 1);
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
    const long double xs[] = {0.25L, 1.5L, 3.7L, 6.9L, 2.0L};
    const int s0[] = {0, 0, 2, 4, 1}; /* stencil starts: edge cells shift inward */
    for (int k = 0; k < 5; ++k) {
        gg_gmap_sample_t s;
        assert_int_equal(gg_gmap_eval(&g_map, kLat0 + xs[k] * kD, kLon0 + 3.3 * kD, kH0,
                                      GG_GMAP_MASK_DD, 0, &s),
                         GG_OK);
        const long double u = xs[k] - s0[k];
        const long double want = 1e-12L * (xs[k] * xs[k] * xs[k] * xs[k] -
                                           u * (u - 1) * (u - 2) * (u - 3));
        assert_near(s.gamma[GG_GMAP_C_DD], want, 1e-21L);
        assert_true(s.gamma[GG_GMAP_C_NN] == 0.0L); /* not in the mask */
        if (k == 2) { /* interior point: the interpolation error is really there */
            assert_true(fabsl(s.gamma[GG_GMAP_C_DD] - 1e-12L * powl(xs[k], 4)) > 1e-14L);
        }
    }
}

static void test_rejects(void **state)
{
    (void)state;
    fill_tile(6, 6, 0);
    memset(&g_map, 0, sizeof g_map);
    gg_gmap_sample_t s, s0;
    memset(&s, 0x5a, sizeof s);
    s0 = s;
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, kLon0, kH0, GG_GMAP_MASK_ALL, 0, &s), GG_ERR_NOT_INIT);
    assert_int_equal(gg_gmap_eval(NULL, kLat0, kLon0, kH0, GG_GMAP_MASK_ALL, 0, &s), GG_ERR_NULL);
    /* bad tiles: state untouched */
    g_tile.nlat = 3;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.nlat = 51;
    g_tile.nlon = 50;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG); /* 2550 > 2500 nodes */
    g_tile.nlat = 6;
    g_tile.nlon = 6;
    g_tile.dlat_rad = 0;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.dlat_rad = kD;
    g_tile.lat0_rad = 1.56;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG); /* beyond 89 deg */
    g_tile.lat0_rad = kLat0;
    g_tile.flags = 4u; /* no such flag */
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.flags = GG_GMAP_GZZ_ONLY; /* says Gamma_DD alone, carries all six */
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.flags = GG_GMAP_ANOMALY;
    g_tile.node[20][7] = NAN;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_NONFINITE);
    assert_int_equal(g_map.initialized, 0);
    /* finite but implausible (fuzzing: 6e228 s^-2 on a 1e-130 rad grid gave
     * Inf derivatives): refused */
    g_tile.node[20][7] = 6e228;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_NONFINITE);
    g_tile.node[20][7] = 0.0;
    g_tile.dlat_rad = 1e-130;
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    g_tile.dlat_rad = kD;
    assert_int_equal(g_map.initialized, 0);
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
    /* outside the tile, beyond the height range, NaN input: out untouched */
    const long double bad[][3] = {{kLat0 - 1e-8L * kD, kLon0, kH0},
                                  {kLat0 + 5.0001L * kD, kLon0, kH0},
                                  {kLat0, kLon0 + 5.0001L * kD, kH0},
                                  {kLat0, kLon0 - 1e-8L * kD, kH0},
                                  {kLat0, kLon0, kH0 + 500.001L},
                                  {kLat0, kLon0, kH0 - 500.001L}};
    for (int k = 0; k < 6; ++k) {
        assert_int_equal(gg_gmap_eval(&g_map, bad[k][0], bad[k][1], bad[k][2], GG_GMAP_MASK_ALL, 1, &s),
                         GG_ERR_RANGE);
    }
    assert_int_equal(gg_gmap_eval(&g_map, NAN, kLon0, kH0, GG_GMAP_MASK_ALL, 1, &s), GG_ERR_NONFINITE);
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, kLon0, INFINITY, GG_GMAP_MASK_ALL, 1, &s), GG_ERR_NONFINITE);
    assert_memory_equal(&s, &s0, sizeof s);
    /* beyond the band with GG_GMAP_H_EXTRAPOLATE: the linear height term continued */
    assert_int_equal(gg_gmap_eval(&g_map, kLat0 + 5 * kD, kLon0 + 5 * kD, kH0 + 2500,
                                  GG_GMAP_MASK_ALL | GG_GMAP_H_EXTRAPOLATE, 0, &s), GG_OK);
    assert_near(s.gamma[2], g_tile.node[35][2] + 2500.0 * g_tile.node[35][8], 1e-19L);
    assert_int_equal(gg_gmap_eval(&g_map, kLat0, kLon0, kH0 + 2e5, GG_GMAP_MASK_ALL | GG_GMAP_H_EXTRAPOLATE, 0, &s),
                     GG_ERR_RANGE);
    /* the corners themselves are inside */
    assert_int_equal(gg_gmap_eval(&g_map, kLat0 + 5 * kD, kLon0 + 5 * kD, kH0 + 500, GG_GMAP_MASK_ALL, 1, &s), GG_OK);
    assert_near(s.gamma[1], g_tile.node[35][1] + 500.0 * g_tile.node[35][7], 1e-20L); /* coordinate rounding ~5e-14 cell */
    gg_real_t m[3][3];
    assert_int_equal(gg_gmap_to_matrix(s.gamma, m), GG_OK);
    assert_true(m[0][1] == s.gamma[GG_GMAP_C_NE] && m[1][0] == s.gamma[GG_GMAP_C_NE]);
    assert_true(m[0][2] == s.gamma[GG_GMAP_C_ND] && m[2][1] == s.gamma[GG_GMAP_C_ED]);
}

static void put_u32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; ++k) p[k] = (uint8_t)(v >> (8 * k));
}
static void put_f64(uint8_t *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    for (int k = 0; k < 8; ++k) p[k] = (uint8_t)(u >> (8 * k));
}

static uint8_t g_blob[88 + 96 * 30];

static void test_load_blob(void **state)
{
    (void)state;
    fill_tile(5, 6, 0);
    memset(g_blob, 0, sizeof g_blob);
    memcpy(g_blob, "GGMAP001", 8);
    put_u32(g_blob + 8, 5);
    put_u32(g_blob + 12, 6);
    put_u32(g_blob + 16, 1);
    put_u32(g_blob + 20, 360);
    put_f64(g_blob + 24, kLat0);
    put_f64(g_blob + 32, kLon0);
    put_f64(g_blob + 40, kD);
    put_f64(g_blob + 48, kD);
    put_f64(g_blob + 56, kH0);
    put_f64(g_blob + 64, 500.0);
    put_f64(g_blob + 72, 1e-12);
    put_u32(g_blob + 80, 42);
    for (int i = 0; i < 30; ++i)
        for (int k = 0; k < 12; ++k) put_f64(g_blob + 88 + 8 * (12 * i + k), g_tile.node[i][k]);
    memset(&g_map, 0, sizeof g_map);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob - 1), GG_ERR_CONFIG);
    assert_int_equal(g_map.initialized, 0);
    g_blob[3] = 'X';
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_ERR_CONFIG);
    g_blob[3] = 'A';
    put_f64(g_blob + 88 + 8 * 100, NAN);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_ERR_NONFINITE);
    assert_int_equal(g_map.initialized, 0);
    put_f64(g_blob + 88 + 8 * 100, g_tile.node[100 / 12][100 % 12]);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_OK);
    assert_int_equal(g_map.tile.nlat, 5);
    assert_int_equal(g_map.tile.nlon, 6);
    assert_int_equal(g_map.tile.flags, GG_GMAP_ANOMALY);
    assert_true(g_map.tile.seed == 42u && g_map.tile.noise_s2 == 1e-12 && g_map.tile.h_range_m == 500.0);
    assert_memory_equal(g_map.tile.node, g_tile.node, 30 * sizeof g_tile.node[0]);
    gg_gmap_sample_t s;
    assert_int_equal(gg_gmap_eval(&g_map, kLat0 + 2.2 * kD, kLon0 + 3.1 * kD, kH0 + 10, GG_GMAP_MASK_ALL, 0, &s), GG_OK);
    assert_near(s.gamma[4], poly(4, 2.2L, 3.1L, 10), 1e-20L);
    /* a Gamma_DD-only tile: with every other value zero it loads; one non-zero
     * value of another component (NE of node 7) or of its height derivative
     * (d/dh ED of node 12): refused, state untouched */
    put_u32(g_blob + 16, GG_GMAP_GZZ_ONLY);
    for (int i = 0; i < 30; ++i)
        for (int k = 0; k < 12; ++k)
            put_f64(g_blob + 88 + 8 * (12 * i + k), (k == GG_GMAP_C_DD || k == 6 + GG_GMAP_C_DD) ? g_tile.node[i][k] : 0.0);
    memset(&g_map, 0, sizeof g_map);
    put_f64(g_blob + 88 + 8 * (12 * 7 + GG_GMAP_C_NE), 1e-12);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_ERR_CONFIG);
    put_f64(g_blob + 88 + 8 * (12 * 7 + GG_GMAP_C_NE), 0.0);
    put_f64(g_blob + 88 + 8 * (12 * 12 + 6 + GG_GMAP_C_ED), -1e-15);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_ERR_CONFIG);
    assert_int_equal(g_map.initialized, 0);
    put_f64(g_blob + 88 + 8 * (12 * 12 + 6 + GG_GMAP_C_ED), 0.0);
    assert_int_equal(gg_gmap_load(&g_map, g_blob, sizeof g_blob), GG_OK);
    assert_int_equal(g_map.tile.flags, GG_GMAP_GZZ_ONLY);
    assert_int_equal(gg_gmap_eval(&g_map, kLat0 + 2.2 * kD, kLon0 + 3.1 * kD, kH0 + 10, GG_GMAP_MASK_DD, 0, &s), GG_OK);
    assert_near(s.gamma[GG_GMAP_C_DD], poly(GG_GMAP_C_DD, 2.2L, 3.1L, 10), 1e-20L);
    /* and through gg_gmap_init the same */
    memcpy(&g_tile, &g_map.tile, sizeof g_tile);
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_OK);
    g_tile.node[3][GG_GMAP_C_NN] = 1e-9;
    memset(&g_map, 0, sizeof g_map);
    assert_int_equal(gg_gmap_init(&g_map, &g_tile), GG_ERR_CONFIG);
    assert_int_equal(g_map.initialized, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cubic_polynomial_exact),
        cmocka_unit_test(test_quartic_remainder),
        cmocka_unit_test(test_rejects),
        cmocka_unit_test(test_antimeridian),
        cmocka_unit_test(test_load_blob),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
