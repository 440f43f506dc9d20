// The cold-atom aid's onboard map cut from the route map (coldatom/route_tiles.hpp), checked
// against the route map itself through the firmware's reader and interpolator (gmap.h):
//  - every tile written loads (gg_gmap_load: format, flags, finite values), one every
//    5 km from the start to the end of the route;
//  - node spacing at a tile's centre: the chord between points a node step apart, from their ECEF positions
//    (geodetic -> ECEF, an independent path from the radii the tiles are laid out with),
//    is the 250 m asked, to 1e-6;
//  - the tile centred nearest each point of the route (every 1 km along track, 0 and
//    +-3 km across) covers it, and its bicubic interpolation of Gamma_zz at the route height
//    agrees with the map's own value: the WGS-84 normal part to 1e-6 E (the smooth part,
//    exact up to O(d^4)), normal + terrain to 1 % of the terrain's rms (the terrain field
//    at 3000 m holds little power at the 250 m node spacing: exp(-k d) with d = 2850 m);
//  - a spacing that leaves the corridor is refused with the tile named.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <vector>
#include <unistd.h>

#include "check.hpp"
#include "ggins/coldatom/route_map.hpp"
#include "ggins/coldatom/route_tiles.hpp"
#include "ggins/gravity/wgs84.hpp"

using namespace ggins::coldatom;
namespace fs = std::filesystem;

namespace {

std::vector<gg_gmap_t> load_dir(const fs::path& dir, int n) {
  std::vector<gg_gmap_t> tiles(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", i);
    std::ifstream f(dir / name, std::ios::binary);
    const std::vector<uint8_t> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    CHECK(gg_gmap_load(&tiles[static_cast<size_t>(i)], b.data(), b.size()) == GG_OK, "%s does not load", name);
  }
  return tiles;
}

// Max |interpolated - map| Gamma_zz (s^-2) over the route points; -1 when a point is not covered.
double route_error(const RouteMap& map, const std::vector<gg_gmap_t>& tiles, double spacing) {
  double worst = 0;
  for (double s = 0; s <= map.length(); s += 1000.0)
    for (double c : {-3000.0, 0.0, 3000.0}) {
      double lat, lon, g;
      map.route_point(s, c, &lat, &lon);
      if (!map.gzz(lat, lon, map.params().h, &g)) return -1;
      const auto k = static_cast<size_t>(std::lround(s / spacing));
      gg_gmap_sample_t out;
      if (k >= tiles.size() || gg_gmap_eval(&tiles[k], lat, lon, map.params().h, GG_GMAP_MASK_DD, 0, &out) != GG_OK) {
        std::printf("  point %.1f km, %.0f m across: not in tile %zu\n", s / 1e3, c, k);
        return -1;
      }
      worst = std::fmax(worst, std::fabs(static_cast<double>(out.gamma[GG_GMAP_C_DD]) - g));
    }
  return worst;
}

}  // namespace

int main() {
  const fs::path dir = fs::temp_directory_path() / ("ggins_route_tiles_" + std::to_string(::getpid()));
  const double step = 250.0, spacing = 5000.0;
  for (bool topo : {false, true}) {
    RouteMapParams mp;
    mp.with_egm96 = false;  // no coefficient file needed
    mp.with_topo = topo;
    const RouteMap map(mp, "", "");
    fs::remove_all(dir);
    const int n = write_route_tiles(map, step, spacing, dir.string());
    const int want = static_cast<int>(std::floor((map.length() + 0.5 * spacing) / spacing)) + 1;
    CHECK(n == want, "%d tiles written, %d expected over %.1f km", n, want, map.length() / 1e3);
    const auto tiles = load_dir(dir, n);
    // node spacing from ECEF chords, tile 0 and the last
    double worst_chord = 0;
    for (const gg_gmap_t* t : {&tiles.front(), &tiles.back()}) {
      const gg_gmap_tile_t& g = t->tile;
      // at the tile's centre (half-way between rows n/2 - 1 and n/2: the parallel's radius
      // changes by tan(lat) dlat / 2 ~ 3e-5 from one row to the next)
      const auto p = [&](double i, double j) {
        return ggins::gravity::wgs84::geodetic_to_ecef(g.lat0_rad + i * g.dlat_rad, g.lon0_rad + j * g.dlon_rad, g.h0_m);
      };
      const double c = 0.5 * (g.nlat - 1);
      worst_chord = std::fmax(worst_chord, std::fabs(static_cast<double>((p(c + 0.5, c) - p(c - 0.5, c)).norm()) / step - 1));
      worst_chord = std::fmax(worst_chord, std::fabs(static_cast<double>((p(c, c + 0.5) - p(c, c - 0.5)).norm()) / step - 1));
    }
    CHECK(worst_chord < 1e-6, "node spacing off by %.3g (relative)", worst_chord);
    const double err = route_error(map, tiles, spacing);
    const double bound = topo ? 0.01 * map.topo_gzz_rms() : 1e-15;
    std::printf("%s: %d tiles, node chord within %.2g of %g m, max |interpolated - map| Gamma_zz %.3g E "
                "(bound %.3g E)\n", topo ? "normal + terrain" : "normal", n, worst_chord, step, err * 1e9, bound * 1e9);
    CHECK(err >= 0 && err < bound, "Gamma_zz along the route off by %g s^-2 (bound %g)", err, bound);
  }
  {  // nodes 5 km apart span 245 km, beyond the 60 km corridor: refused, the tile named
    RouteMapParams mp;
    mp.with_egm96 = false;
    mp.with_topo = false;
    const RouteMap map(mp, "", "");
    std::string why;
    try {
      write_route_tiles(map, 5000.0, spacing, (dir / "wide").string());
    } catch (const std::runtime_error& e) {
      why = e.what();
    }
    std::printf("5 km nodes: %s\n", why.c_str());
    CHECK(why.find("route tile 0 at 0.0 km leaves the map's corridor") != std::string::npos, "not refused: '%s'",
          why.c_str());
  }
  fs::remove_all(dir);
  std::printf(g_fail ? "%d checks failed\n" : "all checks passed\n", g_fail);
  return g_fail ? 1 : 0;
}
