/* The simulated computer's map storage (hal_sim/hal_map.c) serves each aid the
 * tiles of its kind: of the tiles covering a point, only those of the kind
 * asked for (the whole tensor for the map UKF, Gamma_DD alone for the cold-atom
 * aid: GG_GMAP_GZZ_ONLY, gmap.h) are candidates, and of those the one whose
 * nearest edge is farthest from the point is given; where several height
 * layers cover it, those whose band holds the height come first, the nearest
 * h0 among equal margins. The tiles are written in
 * the gmap file format by hand (gmap.h: header and nodes) and loaded as
 * hal_sim loads them. */
#include "test_common.h"

#include "ggins/gmap.h"
#include "hal_map.h"

#define N 10 /* nodes a side */
static const double kD = 1.0e-3; /* spacing, rad */

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

/* a tile of N x N nodes with its south-west node at (lat0, lon0): the tensor
 * (every component value) or Gamma_DD alone (tag in DD) */
static void write_tile_h(const char *path, double lat0, double lon0, uint32_t flags, double tag, double h0,
                         double h_range)
{
    static uint8_t b[88 + 96 * N * N];
    memset(b, 0, sizeof b);
    memcpy(b, "GGMAP001", 8);
    put_u32(b + 8, N);
    put_u32(b + 12, N);
    put_u32(b + 16, flags);
    put_f64(b + 24, lat0);
    put_f64(b + 32, lon0);
    put_f64(b + 40, kD);
    put_f64(b + 48, kD);
    put_f64(b + 56, h0);
    put_f64(b + 64, h_range);
    for (int i = 0; i < N * N; ++i)
        for (int k = 0; k < GG_GMAP_NCOMP; ++k)
            if ((flags & GG_GMAP_GZZ_ONLY) == 0u || k == GG_GMAP_C_DD) put_f64(b + 88 + 8 * (12 * i + k), tag);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, sizeof b, f), sizeof b);
    assert_int_equal(fclose(f), 0);
}

static void write_tile(const char *path, double lat0, double lon0, uint32_t flags, double tag)
{
    write_tile_h(path, lat0, lon0, flags, tag, 0.0, 500.0);
}

static double tag_at_h(hal_map_store_t *s, uint32_t kind, double lat, double lon, double h, gg_status_t want)
{
    const gg_gmap_t *t = NULL;
    assert_int_equal(s->ops.tile_at(s->ops.ctx, kind, lat, lon, h, &t), want);
    if (want != GG_OK) return 0.0;
    assert_non_null(t);
    return t->tile.node[0][GG_GMAP_C_DD];
}

static double tag_at(hal_map_store_t *s, uint32_t kind, double lat, double lon, gg_status_t want)
{
    return tag_at_h(s, kind, lat, lon, 0.0, want);
}

static void test_kind_selects(void **state)
{
    (void)state;
    static hal_map_store_t s;
    char err[256];
    /* T1, T2: tensor tiles at the origin and 4 cells north-east of it;
     * Z: a Gamma_DD tile 2 cells north-east, loaded first */
    write_tile("test_hal_map_z.gmap", 2 * kD, 2 * kD, GG_GMAP_GZZ_ONLY, 3e-9);
    write_tile("test_hal_map_t1.gmap", 0.0, 0.0, 0u, 1e-9);
    write_tile("test_hal_map_t2.gmap", 4 * kD, 4 * kD, 0u, 2e-9);
    hal_map_init(&s);
    assert_int_equal(hal_map_load(&s, "test_hal_map_z.gmap", err, sizeof err), 0);
    assert_int_equal(hal_map_load(&s, "test_hal_map_t1.gmap", err, sizeof err), 0);
    assert_int_equal(hal_map_load(&s, "test_hal_map_t2.gmap", err, sizeof err), 0);
    /* at 6 cells: margins T1 3, Z 4, T2 2: the
     * tensor asked for gets T1 although Z's edge is farther; Gamma_DD gets Z */
    assert_true(tag_at(&s, GG_GMAP_KIND_TENSOR, 6 * kD, 6 * kD, GG_OK) == 1e-9);
    assert_true(tag_at(&s, GG_GMAP_KIND_GZZ, 6 * kD, 6 * kD, GG_OK) == 3e-9);
    /* at 8 cells: T1 margin 1, T2 4, Z 3: the tensor is T2 (the farther edge of its kind) */
    assert_true(tag_at(&s, GG_GMAP_KIND_TENSOR, 8 * kD, 8 * kD, GG_OK) == 2e-9);
    assert_true(tag_at(&s, GG_GMAP_KIND_GZZ, 8 * kD, 8 * kD, GG_OK) == 3e-9);
    /* at 1 cell only T1 covers the point: no Gamma_DD tile there */
    assert_true(tag_at(&s, GG_GMAP_KIND_TENSOR, 1 * kD, 1 * kD, GG_OK) == 1e-9);
    (void)tag_at(&s, GG_GMAP_KIND_GZZ, 1 * kD, 1 * kD, GG_ERR_RANGE);
    /* no tile at all; an unknown kind matches none */
    (void)tag_at(&s, GG_GMAP_KIND_TENSOR, -1 * kD, 1 * kD, GG_ERR_RANGE);
    (void)tag_at(&s, 7u, 6 * kD, 6 * kD, GG_ERR_RANGE);
    hal_map_free(&s);
    /* a storage of Gamma_DD tiles alone serves no tensor */
    hal_map_init(&s);
    assert_int_equal(hal_map_load(&s, "test_hal_map_z.gmap", err, sizeof err), 0);
    (void)tag_at(&s, GG_GMAP_KIND_TENSOR, 6 * kD, 6 * kD, GG_ERR_RANGE);
    hal_map_free(&s);
    remove("test_hal_map_z.gmap");
    remove("test_hal_map_t1.gmap");
    remove("test_hal_map_t2.gmap");
}

/* Height layers: L1, L2, L3 share one grid at h0 = 1000, 1600, 2200 m (bands
 * +-400 m); F, a tile at 5000 m shifted 2 cells north-east, has the farther
 * edge at the test point and is loaded first. */
static void test_height_layers(void **state)
{
    (void)state;
    static hal_map_store_t s;
    char err[256];
    const char *names[4] = {"test_hal_map_f.gmap", "test_hal_map_l1.gmap", "test_hal_map_l2.gmap",
                            "test_hal_map_l3.gmap"};
    write_tile_h(names[0], 2 * kD, 2 * kD, 0u, 5e-9, 5000.0, 400.0);
    write_tile_h(names[1], 0.0, 0.0, 0u, 1e-9, 1000.0, 400.0);
    write_tile_h(names[2], 0.0, 0.0, 0u, 2e-9, 1600.0, 400.0);
    write_tile_h(names[3], 0.0, 0.0, 0u, 3e-9, 2200.0, 400.0);
    hal_map_init(&s);
    for (int k = 0; k < 4; ++k) assert_int_equal(hal_map_load(&s, names[k], err, sizeof err), 0);
    /* at (6, 6) cells: margins F 4, L* 3 */
    const double p = 6 * kD;
    /* one layer holds h: it wins over F's farther edge */
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 1100.0, GG_OK) == 1e-9);
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 2500.0, GG_OK) == 3e-9);
    /* two layers hold h (equal margins): the nearer h0 */
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 1350.0, GG_OK) == 2e-9);
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 1250.0, GG_OK) == 1e-9);
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 1950.0, GG_OK) == 3e-9);
    /* F holds h */
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 4800.0, GG_OK) == 5e-9);
    /* no tile holds h: the farthest edge (F), whose band the aid then finds wrong */
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, p, p, 3500.0, GG_OK) == 5e-9);
    /* at (1, 1) only the layers cover the point: out of every band, the first of equal margins */
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, 1 * kD, 1 * kD, 9000.0, GG_OK) == 1e-9);
    assert_true(tag_at_h(&s, GG_GMAP_KIND_TENSOR, 1 * kD, 1 * kD, 2000.0, GG_OK) == 3e-9);
    (void)tag_at_h(&s, GG_GMAP_KIND_TENSOR, -1 * kD, 1 * kD, 1000.0, GG_ERR_RANGE);
    hal_map_free(&s);
    for (int k = 0; k < 4; ++k) remove(names[k]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kind_selects),
        cmocka_unit_test(test_height_layers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
