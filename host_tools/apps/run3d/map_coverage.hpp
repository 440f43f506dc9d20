// Does the computer's map storage cover the route? Checked before take-off for each aid
// that reads a map: the planned route (the scenario's trajectory) is sampled every
// kCoverageStepS seconds and at its end, and each sample is asked of the storage exactly as
// the aid asks it in flight (hal_sim/hal_map.c tile_at for the aid's kind: the whole tensor
// for the map UKF, Gamma_DD for the particle filter), then of the tile it serves
// (gg_gmap_eval at the sample's latitude, longitude and height, gmap.h: inside the grid and
// |h - h0| <= h_range_m). A sample either is served, or is outside every tile of the kind
// (area), or is inside a tile whose height band does not hold it (height). Consecutive
// samples of one kind of failure form a stretch, named by time, position and height at both
// ends. The runner refuses a flight with an uncovered stretch unless the aid's
// map_uncovered = "fly": then the aid flies it with no update over the stretch (each
// refused measurement counted, the flight ends degraded).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

extern "C" {
#include "ggins/gmap.h"
#include "hal_map.h"
}
#include "ggins/truth3d/generator3d.hpp"

namespace ggins::run3d {

constexpr double kCoverageStepS = 10.0;  // route sampling of the check, s

struct RoutePoint {
  double t_s, lat_deg, lon_deg, h_m;
};

struct Stretch {
  RoutePoint from{}, to{};
  std::string why;  // "area" | "height"
};

struct Coverage {
  int64_t samples = 0, covered = 0;
  std::vector<Stretch> gaps;
  bool complete() const { return gaps.empty(); }
  double covered_fraction() const { return samples > 0 ? static_cast<double>(covered) / static_cast<double>(samples) : 0; }
  // One line per stretch (the first `max`), for an error message or a log.
  std::string text(size_t max = 8) const {
    std::string s;
    char b[320];
    for (size_t i = 0; i < gaps.size() && i < max; ++i) {
      const Stretch& g = gaps[i];
      std::snprintf(b, sizeof b,
                    "\n  t = %.0f .. %.0f s: from %.4f N %.4f E %.0f m to %.4f N %.4f E %.0f m: %s",
                    g.from.t_s, g.to.t_s, g.from.lat_deg, g.from.lon_deg, g.from.h_m, g.to.lat_deg, g.to.lon_deg,
                    g.to.h_m,
                    g.why == "area" ? "no tile of the aid's kind covers it"
                                    : "the tile there holds no layer at this height");
      s += b;
    }
    if (gaps.size() > max) s += "\n  ... " + std::to_string(gaps.size() - max) + " more stretches";
    return s;
  }
  nlohmann::json json() const {
    nlohmann::json j;
    j["route_samples"] = samples;
    j["sample_step_s"] = kCoverageStepS;
    j["covered_fraction"] = covered_fraction();
    j["uncovered"] = nlohmann::json::array();
    for (const Stretch& g : gaps) {
      auto pt = [](const RoutePoint& p) {
        return nlohmann::json{{"t_s", p.t_s}, {"lat_deg", p.lat_deg}, {"lon_deg", p.lon_deg}, {"h_m", p.h_m}};
      };
      j["uncovered"].push_back({{"from", pt(g.from)}, {"to", pt(g.to)}, {"why", g.why}});
    }
    return j;
  }
};

// The degraded reason of an aid flown over an uncovered route (map_uncovered = "fly").
inline void coverage_reason(const std::string& aid, const Coverage& c, std::vector<std::string>& out) {
  if (c.complete()) return;
  char b[320];
  std::snprintf(b, sizeof b,
                "%s: the map storage leaves %zu stretches of the route uncovered (%.1f %% of its samples, the first "
                "from t = %.0f s); flown with no update there (map_uncovered = \"fly\")",
                aid.c_str(), c.gaps.size(), 100.0 * (1.0 - c.covered_fraction()), c.gaps.front().from.t_s);
  out.push_back(b);
}

// The route's samples: every kCoverageStepS and the end.
inline std::vector<RoutePoint> route_samples(const truth3d::Generator3& gen, double duration_s) {
  const double deg = 180.0 / M_PI;
  std::vector<RoutePoint> pts;
  const int64_t n = static_cast<int64_t>(std::ceil(duration_s / kCoverageStepS));
  for (int64_t i = 0; i <= n; ++i) {
    const double t = std::min(duration_s, kCoverageStepS * static_cast<double>(i));
    const truth3d::State3 s = gen.trajectory().at(static_cast<truth3d::Real>(t));
    pts.push_back({t, static_cast<double>(s.lat) * deg, static_cast<double>(s.lon) * deg, static_cast<double>(s.h)});
  }
  return pts;
}

// The coverage of the route by the tiles `files` (load order, as the storage holds them) for
// tiles of `kind` (GG_GMAP_KIND_TENSOR / GG_GMAP_KIND_GZZ). Throws std::runtime_error naming
// a tile the storage refuses.
inline Coverage route_coverage(const std::vector<RoutePoint>& pts, const std::vector<std::string>& files, uint32_t kind) {
  hal_map_store_t st;
  hal_map_init(&st);
  struct Free {
    hal_map_store_t* s;
    ~Free() { hal_map_free(s); }
  } free_on_exit{&st};
  for (const auto& f : files) {
    char err[512];
    if (hal_map_load(&st, f.c_str(), err, sizeof err) != 0) throw std::runtime_error("map tile " + f + ": " + err);
  }
  const double rad = M_PI / 180.0;
  Coverage c;
  std::string open_why;  // the failure of the stretch being built ("" none)
  for (const RoutePoint& p : pts) {
    std::string why;
    const gg_gmap_t* tile = nullptr;
    if (st.ops.tile_at(st.ops.ctx, kind, p.lat_deg * rad, p.lon_deg * rad, p.h_m, &tile) != GG_OK || tile == nullptr) {
      why = "area";
    } else {
      gg_gmap_sample_t s;
      const gg_status_t e = gg_gmap_eval(tile, static_cast<gg_real_t>(p.lat_deg * rad),
                                         static_cast<gg_real_t>(p.lon_deg * rad), static_cast<gg_real_t>(p.h_m),
                                         GG_GMAP_MASK_DD, 0, &s);
      if (e != GG_OK) why = std::fabs(p.h_m - tile->tile.h0_m) > tile->tile.h_range_m ? "height" : "area";
    }
    ++c.samples;
    if (why.empty()) {
      ++c.covered;
      open_why.clear();
      continue;
    }
    if (why == open_why) {
      c.gaps.back().to = p;
    } else {
      c.gaps.push_back({p, p, why});
      open_why = why;
    }
  }
  return c;
}

}  // namespace ggins::run3d
