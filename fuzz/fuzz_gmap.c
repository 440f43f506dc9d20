/* libFuzzer harness: the onboard gravity-gradient map's tile decoder and
 * interpolation (gmap.h: gg_gmap_load, gg_gmap_eval).
 *
 * Byte 0 chooses the path: even - the remaining bytes are the tile file as it
 * is (magic, header and nodes all fuzzed: the decoder must refuse anything
 * malformed); odd - a well-formed 4x4..7x7 tile is assembled from the
 * remaining bytes (magic and the size that goes with nlat, nlon set; header
 * numbers and node values fuzzed), so that decoding gets past the size check
 * and evaluation runs. Then up to 8 evaluations at points inside and around
 * the tile (fractions of its extent from the input), every component mask
 * and with the gradient.
 * Invariants (abort = a finding): no crash or sanitizer report; a refused
 * tile leaves the map state byte for byte as it was; every accepted
 * evaluation returns finite values (a tile of finite nodes must interpolate
 * to finite numbers or be refused). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ggins/gmap.h"
#include "fuzz_bytes.h"

#define FAIL(...)                                                   \
    do {                                                            \
        fprintf(stderr, "FUZZ INVARIANT BROKEN: " __VA_ARGS__);     \
        fprintf(stderr, "\n");                                      \
        abort();                                                    \
    } while (0)

static void put_i32(uint8_t *b, int32_t v) { for (int i = 0; i < 4; ++i) b[i] = (uint8_t)((uint32_t)v >> (8 * i)); }
static void put_f64(uint8_t *b, double v)
{
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    for (int i = 0; i < 8; ++i) b[i] = (uint8_t)(u >> (8 * i));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static gg_gmap_t map, saved;
    static uint8_t buf[GG_GMAP_HEADER_BYTES + 49u * 96u];
    static int first = 1;
    if (first) {
        memset(&map, 0, sizeof map);
        first = 0;
    }
    if (size < 1u) return 0;
    fz_cur_t cur = {data, size, 1};
    const uint8_t *tile = data + 1;
    size_t len = size - 1u;
    if (data[0] & 1u) {
        const int32_t nlat = 4 + (int32_t)(fz_u8(&cur) % 4u), nlon = 4 + (int32_t)(fz_u8(&cur) % 4u);
        len = GG_GMAP_HEADER_BYTES + (size_t)nlat * (size_t)nlon * 96u;
        memcpy(buf, "GGMAP001", 8);
        put_i32(buf + 8, nlat);
        put_i32(buf + 12, nlon);
        put_i32(buf + 16, (int32_t)(fz_u8(&cur) & 1u));
        put_i32(buf + 20, 360);
        put_f64(buf + 24, fz_value(&cur, 0.7));
        put_f64(buf + 32, fz_value(&cur, 0.2));
        put_f64(buf + 40, fz_value(&cur, 1e-4));
        put_f64(buf + 48, fz_value(&cur, 1e-4));
        put_f64(buf + 56, fz_value(&cur, 3000.0));
        put_f64(buf + 64, fz_value(&cur, 500.0));
        put_f64(buf + 72, 0.0);
        put_f64(buf + 80, 0.0);
        for (size_t i = 0; i < (size_t)nlat * (size_t)nlon * 12u; ++i) {
            const double ref = (i % 12u) < 6u ? 1e-6 : 1e-9;
            put_f64(buf + GG_GMAP_HEADER_BYTES + 8u * i, fz_left(&cur) ? fz_value(&cur, ref) : ref);
        }
        tile = buf;
    }
    memcpy(&saved, &map, sizeof map);
    const gg_status_t st = gg_gmap_load(&map, tile, len);
    if (st != GG_OK) {
        if (memcmp(&saved, &map, sizeof map) != 0) FAIL("refused tile (status %d) changed the map", (int)st);
        return 0;
    }
    const gg_gmap_tile_t *t = &map.tile;
    for (int e = 0; e < 8 && fz_left(&cur); ++e) {
        const double u = (double)(int8_t)fz_u8(&cur) / 100.0, w = (double)(int8_t)fz_u8(&cur) / 100.0;
        const double lat = t->lat0_rad + u * t->dlat_rad * (double)(t->nlat - 1);
        const double lon = t->lon0_rad + w * t->dlon_rad * (double)(t->nlon - 1);
        const double h = t->h0_m + (double)(int8_t)fz_u8(&cur) / 100.0 * t->h_range_m * 1.5;
        const uint32_t mask = (uint32_t)fz_u8(&cur) & (GG_GMAP_MASK_ALL | GG_GMAP_H_EXTRAPOLATE);
        gg_gmap_sample_t s;
        const gg_status_t se = gg_gmap_eval(&map, (gg_real_t)lat, (gg_real_t)lon, (gg_real_t)h, mask, 1, &s);
        if (se != GG_OK) continue;
        for (int k = 0; k < GG_GMAP_NCOMP; ++k) {
            if (!isfinite((double)s.gamma[k])) FAIL("evaluation %d accepted with a non-finite component %d", e, k);
            for (int j = 0; j < 3; ++j)
                if (!isfinite((double)s.dgamma[k][j])) FAIL("evaluation %d accepted with a non-finite derivative", e);
        }
        gg_real_t m[3][3];
        if (gg_gmap_to_matrix(s.gamma, m) != GG_OK) FAIL("gg_gmap_to_matrix refused finite components");
    }
    return 0;
}
