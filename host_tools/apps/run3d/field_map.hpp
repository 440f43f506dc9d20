// The onboard map of an aid built from the scenario's own gravity field (map_from_field):
// for the map UKF ([aid_ukf]) tiles of the whole tensor, for the particle filter ([aid_pf]
// with [coldatom] gzz_map = "field") of Gamma_DD alone. The runner writes gmap tiles
// (ggins/gmap_gen.hpp: the tensor Gamma rotated into each node's NED frame and its height
// derivative, plus database noise) over the route before the flight, into a directory that
// becomes one source of the computer's map storage (map_storage.hpp: recorded with its
// digest, so a replay loads the same tiles).
//
// Coverage: the route is sampled every 10 s (and at its end: map_coverage.hpp route_samples); the box of its latitudes
// and longitudes, widened by map_margin_deg, is cut into tiles of at most
// GG_GMAP_MAX_NODES nodes (n x n, n = floor(sqrt(max))) at map_spacing_deg that overlap
// their neighbours by map_margin_deg; a tile no route sample comes within the margin of
// is left out. The aid takes, at each epoch's start, the tile whose edge is farthest
// from the position (hal_sim/hal_map.c), so within the overlap an epoch's sigma points
// stay inside one tile.
//
// Height: a route whose height span is at most gmap::kLayerMaxM (600 m) gets one layer, at
// its mid height, accepting |h - alt| up to half the span + 300 m. A route that climbs or
// descends more gets height layers per footprint (gmap::height_layers): the heights of the
// route samples within the footprint (and its margin) span [h_lo, h_hi]; layers of equal
// thickness t <= 600 m (one where the route is level there), each accepting
// |h - h0| <= t/2 + 300 m (the 300 m: an epoch's climb after its tile was chosen). The storage serves the layer whose h0 is nearest (hal.h), so
// |h - h0| <= t/2 at an epoch's start. The first-order height term errs by ~(h - h0)^2/2
// d2Gamma/dh2: measured 3.8e-3 E at 1000 m from h0 (docs/map-matching.md), so <= 3.4e-4 E at
// 300 m and <= 1.4e-3 E at 600 m, beside the map's 1e-3 E database noise. A position above
// or below every layer is refused by the aid (no map at that height).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ggins/gmap_gen.hpp"
#include "ggins/gravity/lattice.hpp"
#include "ggins/tile_cache.hpp"
#include "ggins/truth3d/aids3d.hpp"
#include "ggins/truth3d/coldatom3d.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "map_coverage.hpp"

namespace ggins::run3d {

// The scenario's field with third derivatives for the tiles' height derivatives: the
// field's own where it has them, else central differences of its gradient 1 m either side
// along each axis (truncation ~ (1 m)^2 d^5V, below 1e-20 s^-2/m at the Earth; rounding of
// long-double gradients ~ 1e-22 s^-2 / 2 m).
class ThirdByDifferences final : public gravity::Field {
 public:
  explicit ThirdByDifferences(const gravity::Field& f) : f_(f) {}
  gravity::FieldSample eval(const gravity::Vec3& r_e) const override { return f_.eval(r_e); }
  std::string name() const override { return f_.name(); }
  bool third(const gravity::Vec3& r_e, gravity::Tensor3& t) const override {
    if (f_.third(r_e, t)) return true;
    const gravity::Real h = 1.0L;
    for (int k = 0; k < 3; ++k) {
      gravity::Vec3 e = gravity::Vec3::Zero();
      e(k) = h;
      t[static_cast<size_t>(k)] = (f_.eval(r_e + e).gamma - f_.eval(r_e - e).gamma) / (2.0L * h);
    }
    return true;
  }

 private:
  const gravity::Field& f_;
};

struct FieldMap {
  std::filesystem::path dir;  // the tiles, *.gmap in load order
  int tiles = 0;
  double lat_min_deg = 0, lat_max_deg = 0, lon_min_deg = 0, lon_max_deg = 0;
  double alt_m = 0, h_range_m = 0;  // one layer: its height and band; layers: the route's mid height, widest band
  double h_min_m = 0, h_max_m = 0;  // the route's height span
  int footprints = 0;               // horizontal tiles
  int layers_max = 1;               // most layers of one footprint
  int built = 0, cache_hits = 0;    // tiles computed, tiles taken from the cache
  bool exact = false;               // from the model itself (MapField), not its lattice
  bool cached = false;              // through the tile cache
};

// What an aid's map_from_field asks for: the map UKF's tiles hold the whole tensor, the
// particle filter's Gamma_DD alone (gmap::keep_gzz_only); the cut and the layers are the same.
struct FieldTiles {
  std::string key;  // the scenario table, for messages ("aid_ukf", "aid_pf")
  double spacing_deg = 0.05, margin_deg = 0.1, noise_E = 0.001;
  uint64_t seed = 1;
  bool gzz_only = false;
};
inline FieldTiles field_tiles(const truth3d::AidUkf3& a) {
  return {"aid_ukf", a.map_spacing_deg, a.map_margin_deg, a.map_noise_E, a.map_seed, false};
}
inline FieldTiles field_tiles(const truth3d::AidPf3& a) {
  return {"aid_pf", a.map_spacing_deg, a.map_margin_deg, a.map_noise_E, a.map_seed, true};
}

// How the tiles are built: threads per tile (rows of nodes in parallel), the cache folder
// (gmap/tile_cache.hpp; empty: no cache) and the identity of the field for its keys (empty:
// not cached, e.g. a field that names no model file), and a progress callback (tiles done,
// tiles in all).
struct MapBuild {
  int threads = 2;
  std::filesystem::path cache_dir;
  std::string field_id;
  std::function<void(int, int)> progress;
};

// The field the tiles are computed from: the scenario's model itself where the truth
// generator samples it on a lattice (gravity::FastField::exact: normal + the disturbance's
// spherical harmonics, whose circles of latitude share the Legendre sums along a row of
// nodes and give the height derivative by dual numbers), else the generator's field with
// third derivatives by differences (ThirdByDifferences, node by node).
struct MapField {
  std::shared_ptr<const gravity::Field> exact;
  std::unique_ptr<ThirdByDifferences> diff;
  const gravity::Field& field() const { return exact ? *exact : static_cast<const gravity::Field&>(*diff); }
  bool is_exact() const { return exact != nullptr; }
};
inline MapField map_field(const gravity::Field& f) {
  MapField m;
  if (const auto* ff = dynamic_cast<const gravity::FastField*>(&f)) m.exact = ff->exact();
  if (!m.exact) m.diff = std::make_unique<ThirdByDifferences>(f);
  return m;
}

inline FieldMap build_field_map(const truth3d::Generator3& gen, double duration_s, int nmax, const FieldTiles& a,
                                const std::filesystem::path& dir, const MapBuild& mb = {}) {
  namespace fs = std::filesystem;
  std::vector<std::array<double, 3>> pts;  // lat, lon (deg), h (m) of the route samples
  double h_min = 1e300, h_max = -1e300;
  for (const RoutePoint& p : route_samples(gen, duration_s)) {
    // longitudes continuous along the route (across the antimeridian: beyond +-180)
    double lon = p.lon_deg;
    if (!pts.empty()) lon = pts.back()[1] + std::remainder(lon - pts.back()[1], 360.0);
    pts.push_back({p.lat_deg, lon, p.h_m});
    h_min = std::min(h_min, p.h_m);
    h_max = std::max(h_max, p.h_m);
  }
  FieldMap fm;
  fm.dir = dir;
  fm.lat_min_deg = fm.lat_max_deg = pts[0][0];
  fm.lon_min_deg = fm.lon_max_deg = pts[0][1];
  for (const auto& p : pts) {
    fm.lat_min_deg = std::min(fm.lat_min_deg, p[0]);
    fm.lat_max_deg = std::max(fm.lat_max_deg, p[0]);
    fm.lon_min_deg = std::min(fm.lon_min_deg, p[1]);
    fm.lon_max_deg = std::max(fm.lon_max_deg, p[1]);
  }
  if (fm.lon_max_deg - fm.lon_min_deg > 300.0)
    throw std::runtime_error(a.key + ".map_from_field: the route spans " + std::to_string(fm.lon_max_deg - fm.lon_min_deg) +
                             " deg of longitude (around a pole?); give map tiles instead");
  const double m = a.margin_deg, d = a.spacing_deg;
  fm.lat_min_deg -= m;
  fm.lat_max_deg += m;
  fm.lon_min_deg -= m;
  fm.lon_max_deg += m;
  if (fm.lat_min_deg < -89.0 || fm.lat_max_deg > 89.0)
    throw std::runtime_error(a.key + ".map_from_field: the route with its margin reaches beyond 89 deg of latitude");
  fm.alt_m = 0.5 * (h_min + h_max);
  fm.h_range_m = 0.5 * (h_max - h_min) + 300.0;
  fm.h_min_m = h_min;
  fm.h_max_m = h_max;
  const bool layered = h_max - h_min > gmap::kLayerMaxM;
  if (layered) fm.h_range_m = 0;
  const int side = static_cast<int>(std::floor(std::sqrt(static_cast<double>(GG_GMAP_MAX_NODES))));
  const double span = (side - 1) * d, stride = span - m;
  if (!(stride > d)) throw std::runtime_error(a.key + ".map_margin_deg is too wide for tiles of " + std::to_string(side) +
                                              " x " + std::to_string(side) + " nodes at map_spacing_deg");
  const MapField mf = map_field(gen.field());
  // cached only where the key names the model (cached_tile: an empty folder builds every tile)
  const std::string field_id = mf.is_exact() ? mb.field_id : std::string();
  const fs::path cache_dir = field_id.empty() ? fs::path() : mb.cache_dir;
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create " + dir.string() + ": " + ec.message());
  std::vector<gmap::TileSpec> plan;  // the tiles in load order
  for (double la = fm.lat_min_deg; la < fm.lat_max_deg - 1e-12; la += stride) {
    for (double lo = fm.lon_min_deg; lo < fm.lon_max_deg - 1e-12; lo += stride) {
      const double la1 = std::min(la + span, fm.lat_max_deg), lo1 = std::min(lo + span, fm.lon_max_deg);
      bool near = false;  // a route sample within the margin of this tile
      double f_lo = 1e300, f_hi = -1e300;  // its heights there
      for (const auto& p : pts)
        if (p[0] >= la - m && p[0] <= la1 + m && p[1] >= lo - m && p[1] <= lo1 + m) {
          near = true;
          f_lo = std::min(f_lo, p[2]);
          f_hi = std::max(f_hi, p[2]);
        }
      if (!near) continue;
      ++fm.footprints;
      // the layers of this footprint: (h0, band)
      std::vector<gmap::Layer> layers{{fm.alt_m, fm.h_range_m}};
      if (layered) {
        layers = gmap::height_layers(f_lo, f_hi);
        fm.layers_max = std::max(fm.layers_max, static_cast<int>(layers.size()));
        for (const auto& L : layers) fm.h_range_m = std::max(fm.h_range_m, L.h_range_m);
      }
      for (const auto& L : layers) {
        gmap::TileSpec spec;
        spec.lat_min_deg = la;
        spec.lat_max_deg = std::max(la1, la + 3 * d);  // at least 4 nodes a side (gmap_gen)
        spec.lon_min_deg = lo;
        spec.lon_max_deg = std::max(lo1, lo + 3 * d);
        spec.spacing_deg = d;
        spec.alt_m = L.h0_m;
        spec.h_range_m = L.h_range_m;
        spec.nmax = nmax;
        spec.noise_e = a.noise_E;
        spec.seed = a.seed * 1000003ull + static_cast<uint64_t>(plan.size());
        spec.threads = mb.threads;
        plan.push_back(spec);
      }
    }
  }
  const int n_tiles = static_cast<int>(plan.size());
  for (const gmap::TileSpec& spec : plan) {
    if (mb.progress) mb.progress(fm.tiles, n_tiles);
    bool hit = false;
    const auto make = [&] {
      const auto tile = gmap::make_tile(mf.field(), spec);
      if (a.gzz_only) gmap::keep_gzz_only(*tile);
      return gmap::encode(*tile);
    };
    const std::vector<std::uint8_t> bytes =
        gmap::cached_tile(cache_dir, gmap::tile_key(field_id, spec, a.gzz_only), make, &hit);
    (hit ? fm.cache_hits : fm.built) += 1;
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", fm.tiles);
    std::ofstream f(dir / name, std::ios::binary);
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw std::runtime_error("cannot write " + (dir / name).string());
    ++fm.tiles;
  }
  if (mb.progress) mb.progress(fm.tiles, n_tiles);
  fm.exact = mf.is_exact();
  fm.cached = !cache_dir.empty();
  if (fm.tiles == 0) throw std::runtime_error(a.key + ".map_from_field: no tile along the route");
  return fm;
}

}  // namespace ggins::run3d
