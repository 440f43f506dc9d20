/* The simulated computer's map storage (hal_map.h). */
#include "hal_map.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* distance of (lat, lon) from the tile's nearest edge in node spacings;
 * negative outside */
static double edge_margin(const gg_gmap_t *g, double lat, double lon)
{
    const gg_gmap_tile_t *t = &g->tile;
    double dl = lon - t->lon0_rad;
    (void)gg_gmap_lon_offset(g, lon, &dl); /* across +-pi as the tile's interpolation takes it */
    const double i = (lat - t->lat0_rad) / t->dlat_rad;
    const double j = dl / t->dlon_rad;
    double m = i;
    if ((double)(t->nlat - 1) - i < m) m = (double)(t->nlat - 1) - i;
    if (j < m) m = j;
    if ((double)(t->nlon - 1) - j < m) m = (double)(t->nlon - 1) - j;
    return m;
}

/* the kind of a tile (GG_GMAP_KIND_*, gmap.h) */
static uint32_t kind_of(const gg_gmap_t *m)
{
    return (m->tile.flags & GG_GMAP_GZZ_ONLY) != 0u ? GG_GMAP_KIND_GZZ : GG_GMAP_KIND_TENSOR;
}

static gg_status_t tile_at(void *ctx, uint32_t kind, double lat_rad, double lon_rad, double h_m,
                          const gg_gmap_t **tile)
{
    hal_map_store_t *s = (hal_map_store_t *)ctx;
    int best = -1;      /* farthest edge among all covering tiles */
    double best_m = 0.0;
    int band = -1;      /* farthest edge, then nearest h0, among those holding h (the
                         * layers of one grid have equal margins) */
    double band_m = 0.0;
    double band_dh = 0.0;
    s->lookups++;
    if (tile == NULL) return GG_ERR_NULL;
    for (int k = 0; k < s->n_tiles; ++k) {
        if (kind_of(s->tiles[k]) != kind) continue;
        const gg_gmap_tile_t *t = &s->tiles[k]->tile;
        const double m = edge_margin(s->tiles[k], lat_rad, lon_rad);
        if (!(m >= 0.0)) continue;
        if (best < 0 || m > best_m) {
            best = k;
            best_m = m;
        }
        const double dh = fabs(h_m - t->h0_m);
        if (dh <= t->h_range_m &&
            (band < 0 || m > band_m || (!(m < band_m) && dh < band_dh))) {
            band = k;
            band_m = m;
            band_dh = dh;
        }
    }
    if (best < 0) return GG_ERR_RANGE;
    *tile = s->tiles[band >= 0 ? band : best];
    return GG_OK;
}

void hal_map_init(hal_map_store_t *s)
{
    memset(s, 0, sizeof *s);
    s->ops.ctx = s;
    s->ops.tile_at = tile_at;
}

int hal_map_load(hal_map_store_t *s, const char *path, char *err, size_t errlen)
{
    if (s->n_tiles >= HAL_MAP_MAX_TILES) {
        snprintf(err, errlen, "%s: the map storage holds %d tiles at most", path, HAL_MAP_MAX_TILES);
        return -1;
    }
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open", path);
        return -1;
    }
    const size_t cap = GG_GMAP_HEADER_BYTES + sizeof(double) * GG_GMAP_NVAL * GG_GMAP_MAX_NODES + 1u;
    uint8_t *buf = malloc(cap);
    gg_gmap_t *m = malloc(sizeof *m);
    if (!buf || !m) {
        free(buf);
        free(m);
        fclose(f);
        snprintf(err, errlen, "%s: out of memory", path);
        return -1;
    }
    const size_t len = fread(buf, 1, cap, f);
    fclose(f);
    const gg_status_t st = gg_gmap_load(m, buf, len);
    free(buf);
    if (st != GG_OK) {
        free(m);
        snprintf(err, errlen, "%s: not a valid gradient map tile (gg_gmap_load status %d)", path, (int)st);
        return -1;
    }
    s->tiles[s->n_tiles++] = m;
    return 0;
}

void hal_map_free(hal_map_store_t *s)
{
    for (int k = 0; k < s->n_tiles; ++k) free(s->tiles[k]);
    s->n_tiles = 0;
}
