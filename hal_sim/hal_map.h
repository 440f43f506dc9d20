/*
 * hal_map: the onboard map storage of the simulated navigation computer
 * (gg_hal_map_t, firmware/include/ggins/hal.h). hal_sim loads the gradient
 * map tiles given with --map FILE (the gmap binary format of gmap.h, written
 * by `ggins gmap`) at start-up, as a vehicle's computer holds its tiles in
 * flash; each aid of the 3-D task asks for the tile of its kind (the whole
 * tensor for the map UKF, Gamma_DD alone for the cold-atom aid: the flag
 * GG_GMAP_GZZ_ONLY, gmap.h) covering its estimated position at each of its
 * measurements and height, and is served only tiles of that kind. Of several
 * such tiles covering a point, those whose height band holds the height come
 * first (height layers of one area); of those the one whose nearest edge is
 * farthest from it (in node spacings) is given, so the aid's sigma points or
 * particles stay inside, and among equal margins the nearest layer (hal.h).
 */
#ifndef GGINS_HAL_MAP_H
#define GGINS_HAL_MAP_H

#ifdef __cplusplus
extern "C" {
#endif
#include "ggins/gmap.h"
#include "ggins/hal.h"

/** Tiles the storage holds. */
#define HAL_MAP_MAX_TILES 256

typedef struct {
    gg_gmap_t *tiles[HAL_MAP_MAX_TILES]; /* heap (the host side of the HAL) */
    int n_tiles;
    unsigned long lookups;               /* tile_at calls (diagnostics) */
    gg_hal_map_t ops;                    /* what the firmware sees */
} hal_map_store_t;

/** Empty storage; its ops are ready to hand to the firmware (hal.map). */
void hal_map_init(hal_map_store_t *s);

/** Load one tile file. 0 on success, -1 (message in err, errlen bytes) on a
 *  file that cannot be read, a tile gg_gmap_load refuses, or a full storage. */
int hal_map_load(hal_map_store_t *s, const char *path, char *err, size_t errlen);

/** Release the tiles. */
void hal_map_free(hal_map_store_t *s);

#ifdef __cplusplus
}
#endif

#endif /* GGINS_HAL_MAP_H */
