// The cold-atom aid's onboard map cut from a route map (route_map.hpp): gmap tiles of
// Gamma_zz alone (flag GG_GMAP_GZZ_ONLY, gmap.h), n x n nodes on a lat/lon grid at the
// route's height, one tile centred on the route every `spacing_m` along track (from the
// start to the end, both included).
//
//   node value:         Gamma_zz(lat, lon, h)                 (the map's own, s^-2, NED)
//   height derivative:  -3 Gamma_zz / (R + h), R = 6,371,000 m (free-air falloff of a
//                                                               gradient ~ 1/r^3)
//
// Node spacing: `step_m` along the meridian and the parallel at the tile's centre
// (the WGS-84 radii, gravity/wgs84.hpp), so a tile spans (n - 1) step_m each way.
#pragma once

#include <string>

#include "ggins/coldatom/route_map.hpp"

extern "C" {
#include "ggins/gmap.h"
}

namespace ggins::coldatom {

constexpr int kRouteTileNodes = 50;  // nodes a side (2,500 <= GG_GMAP_MAX_NODES)

// Fill a tile around (lat_c, lon_c) (rad) at height h (m), nodes step m apart; false when a
// node is off the map's corridor.
bool build_tile(const RouteMap& map, double lat_c, double lon_c, double h, double step, gg_gmap_tile_t* tile);

// Write tile_0000.gmap, tile_0001.gmap, ... (gmap.h's binary format) along the route into
// dir (created; files of the same names replaced) at the map's height; returns the number
// written. Throws std::runtime_error when a tile leaves the map's corridor or a file cannot
// be written, naming the tile and its distance along the route.
int write_route_tiles(const RouteMap& map, double step_m, double spacing_m, const std::string& dir);

}  // namespace ggins::coldatom
