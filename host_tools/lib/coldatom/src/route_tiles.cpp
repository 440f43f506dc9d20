#include "ggins/coldatom/route_tiles.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <vector>

#include "ggins/gmap_gen.hpp"
#include "ggins/gravity/wgs84.hpp"

namespace ggins::coldatom {

bool build_tile(const RouteMap& map, double lat_c, double lon_c, double h, double step, gg_gmap_tile_t* tile) {
  const int n = kRouteTileNodes;
  gravity::Real rm, rn;
  gravity::wgs84::radii(lat_c, rm, rn);
  const double RM = static_cast<double>(rm), RN = static_cast<double>(rn);
  std::memset(tile, 0, sizeof *tile);
  tile->nlat = n;
  tile->nlon = n;
  tile->dlat_rad = step / (RM + h);
  tile->dlon_rad = step / ((RN + h) * std::cos(lat_c));
  tile->lat0_rad = lat_c - 0.5 * (n - 1) * tile->dlat_rad;
  tile->lon0_rad = lon_c - 0.5 * (n - 1) * tile->dlon_rad;
  tile->h0_m = h;
  tile->h_range_m = 1000.0;
  tile->flags = GG_GMAP_GZZ_ONLY;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double g = 0;
      if (!map.gzz(tile->lat0_rad + i * tile->dlat_rad, tile->lon0_rad + j * tile->dlon_rad, h, &g)) return false;
      tile->node[i * n + j][GG_GMAP_C_DD] = g;
      tile->node[i * n + j][GG_GMAP_NCOMP + GG_GMAP_C_DD] = -3.0 * g / (6371000.0 + h);
    }
  return true;
}

int write_route_tiles(const RouteMap& map, double step_m, double spacing_m, const std::string& dir) {
  if (!(step_m > 0) || !(spacing_m > 0)) throw std::runtime_error("route tiles: step and spacing must be > 0");
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create " + dir + ": " + ec.message());
  auto tile = std::make_unique<gg_gmap_tile_t>();  // 240 kB
  int n = 0;
  for (double s = 0; s <= map.length() + 0.5 * spacing_m; s += spacing_m, ++n) {
    double lat, lon;
    map.route_point(std::min(s, map.length()), 0, &lat, &lon);
    if (!build_tile(map, lat, lon, map.params().h, step_m, tile.get())) {
      char why[128];
      std::snprintf(why, sizeof why, "route tile %d at %.1f km leaves the map's corridor (step %.0f m)", n, s / 1e3,
                    step_m);
      throw std::runtime_error(why);
    }
    const std::vector<std::uint8_t> b = gmap::encode(*tile);
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", n);
    const fs::path p = fs::path(dir) / name;
    std::ofstream f(p, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    if (!f) throw std::runtime_error("cannot write " + p.string());
  }
  return n;
}

}  // namespace ggins::coldatom
