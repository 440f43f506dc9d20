// The gradient-map aid's tiles built from a scenario's own field (ggins run3d,
// [aid_ukf] map_from_field; host_tools/apps/run3d/field_map.hpp), against
// independent truth:
//   - every node of every tile against the EGM96 synthesis of ggins gmap (make_egm96_field),
//     bit for bit: the runner builds its tiles from the model itself (FastField::exact, not
//     the truth generator's lattice), and the two builders share the tile cache's entries;
//   - the route covered: every point of it inside a tile by at least half the margin;
//   - central-difference third derivatives against the point mass's closed form;
//   - a route climbing 3000 -> 6000 m: the layers the map storage (hal_sim/hal_map.c) serves
//     at each point of the route, interpolated by the firmware (gg_gmap_eval) at the point's
//     own height, against the exact EGM96 synthesis there; above and below every layer the
//     storage's tile does not hold the height (the aid refuses it).
// Skipped (77) without data/egm96_to360.ascii.txt.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "field_map.hpp"
#include "map_coverage.hpp"
#include "ggins/gmap_gen.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"
#include "hal_map.h"

// cmocka last: its fail() macro would rename the schema's fail()
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
extern "C" {
#include <cmocka.h>
}

namespace fs = std::filesystem;
namespace gm = ggins::gmap;
namespace g = ggins::gravity;

static const std::string kEgm = std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt";

static void test_tiles_against_egm96(void** state) {
  (void)state;
  ggins::truth3d::Scenario3 sc = ggins::truth3d::load_scenario3("3d-route-45n-map", {GGINS_SCENARIO_DIR});
  sc.sh.path = kEgm;
  const ggins::truth3d::Generator3 gen(sc);
  ggins::truth3d::AidUkf3 a;
  a.map_from_field = true;
  a.map_noise_E = 0.0;
  a.map_spacing_deg = 0.02;
  a.map_margin_deg = 0.1;
  const fs::path dir = fs::temp_directory_path() / ("ggins-field-map-" + std::to_string(::getpid()));
  const ggins::run3d::FieldMap fm = ggins::run3d::build_field_map(gen, sc.duration_s, 360, ggins::run3d::field_tiles(a), dir);
  std::printf("field %s\n", gen.field().name().c_str());
  std::printf("%d tiles, lat %.3f..%.3f lon %.3f..%.3f deg, alt %.1f m, h range %.1f m\n", fm.tiles, fm.lat_min_deg,
              fm.lat_max_deg, fm.lon_min_deg, fm.lon_max_deg, fm.alt_m, fm.h_range_m);
  assert_true(fm.tiles >= 1);
  assert_true(fm.exact);  // from the model, not from its lattice
  const auto exact = gm::make_egm96_field(kEgm, 360, false);
  double worst = 0, worst_dh = 0, scale = 0;
  std::vector<std::unique_ptr<gg_gmap_t>> tiles;
  for (int k = 0; k < fm.tiles; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", k);
    tiles.push_back(gm::read_tile_file((dir / name).string()));
    const gg_gmap_tile_t& t = tiles.back()->tile;
    assert_true(t.nlat * t.nlon <= GG_GMAP_MAX_NODES);
    assert_true(std::fabs(t.h0_m - fm.alt_m) < 1e-9);
    for (int i = 0; i < t.nlat; i += 3)  // every third row and column: the same code at each node
      for (int j = 0; j < t.nlon; j += 3) {
        double ref[GG_GMAP_NVAL];
        gm::node_values(*exact, t.lat0_rad + i * t.dlat_rad, t.lon0_rad + j * t.dlon_rad, t.h0_m, ref);
        const double* v = t.node[i * t.nlon + j];
        for (int c = 0; c < 6; ++c) {
          worst = std::max(worst, std::fabs(v[c] - ref[c]));
          worst_dh = std::max(worst_dh, std::fabs(v[6 + c] - ref[6 + c]));
          scale = std::max(scale, std::fabs(ref[6 + c]));
        }
      }
  }
  std::printf("nodes against exact EGM96-360: max |dGamma| %.3e E, max |d(dGamma/dh)| %.3e E/m (largest %.3e E/m)\n",
              worst * 1e9, worst_dh * 1e9, scale * 1e9);
  // one synthesis, one arithmetic: the same bits (a tile cache entry is either builder's)
  assert_true(worst == 0.0);
  assert_true(worst_dh == 0.0);
  // coverage: every route point (1 s apart) inside some tile by at least half the margin
  const double deg = 180.0 / M_PI, half = 0.5 * a.map_margin_deg;
  for (int s = 0; s <= static_cast<int>(sc.duration_s); ++s) {
    const auto st = gen.trajectory().at(static_cast<ggins::truth3d::Real>(s));
    const double la = static_cast<double>(st.lat) * deg, lo = static_cast<double>(st.lon) * deg;
    bool in = false;
    for (const auto& tp : tiles) {
      const gg_gmap_tile_t& t = tp->tile;
      const double la0 = t.lat0_rad * deg, lo0 = t.lon0_rad * deg;
      const double la1 = la0 + (t.nlat - 1) * t.dlat_rad * deg, lo1 = lo0 + (t.nlon - 1) * t.dlon_rad * deg;
      in = in || (la >= la0 + half && la <= la1 - half && lo >= lo0 + half && lo <= lo1 - half);
    }
    if (!in) std::printf("t = %d s: %.4f, %.4f deg not inside a tile by %.3f deg\n", s, la, lo, half);
    assert_true(in);
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

// A field that hides its third derivatives.
class NoThird final : public g::Field {
 public:
  g::FieldSample eval(const g::Vec3& r) const override { return p_.eval(r); }
  std::string name() const override { return "point mass without third()"; }

 private:
  g::PointMassField p_;
};

static void test_third_by_differences(void** state) {
  (void)state;
  const NoThird f;
  const ggins::run3d::ThirdByDifferences d(f);
  const g::PointMassField exact;
  const g::Vec3 r(4.1e6L, 1.3e6L, 4.7e6L);
  g::Tensor3 td, te;
  assert_true(d.third(r, td));
  assert_true(exact.third(r, te));
  long double worst = 0, big = 0;
  for (int k = 0; k < 3; ++k) {
    worst = std::max(worst, (td[static_cast<size_t>(k)] - te[static_cast<size_t>(k)]).cwiseAbs().maxCoeff());
    big = std::max(big, te[static_cast<size_t>(k)].cwiseAbs().maxCoeff());
  }
  std::printf("central differences vs closed form: %.3Le of %.3Le s^-2/m\n", worst, big);
  assert_true(worst < 1e-8L * big);
}

static void test_layers_climbing(void** state) {
  (void)state;
  const std::string toml = R"(name = "climb-layers"
[trajectory]
type = "route"
lat_deg = 50.0
lon_deg = 8.0
height_m = 3000.0
speed_mps = 200.0
[[trajectory.waypoint]]
lat_deg = 50.0
lon_deg = 9.5
height_m = 6000.0
climb_rate_mps = 10.0
vertical_accel_mps2 = 0.5
[gravity]
model = "egm96"
[time]
duration_s = 500.0
rate_hz = 100.0
)";
  ggins::truth3d::Scenario3 sc = ggins::truth3d::parse_scenario3(toml, "climb-layers", "test_field_map");
  sc.sh.path = kEgm;
  const ggins::truth3d::Generator3 gen(sc);
  ggins::truth3d::AidUkf3 a;
  a.map_from_field = true;
  a.map_noise_E = 0.0;
  a.map_spacing_deg = 0.05;
  a.map_margin_deg = 0.1;
  const fs::path dir = fs::temp_directory_path() / ("ggins-field-layers-" + std::to_string(::getpid()));
  const ggins::run3d::FieldMap fm = ggins::run3d::build_field_map(gen, sc.duration_s, 360, ggins::run3d::field_tiles(a), dir);
  std::printf("climb %.0f .. %.0f m: %d tiles in %d footprints, up to %d layers, widest band %.1f m\n", fm.h_min_m,
              fm.h_max_m, fm.tiles, fm.footprints, fm.layers_max, fm.h_range_m);
  assert_true(fm.h_max_m - fm.h_min_m > 2900.0);
  assert_true(fm.layers_max >= 5);
  static hal_map_store_t store;
  hal_map_init(&store);
  char err[256];
  for (int k = 0; k < fm.tiles; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", k);
    assert_int_equal(hal_map_load(&store, (dir / name).string().c_str(), err, sizeof err), 0);
  }
  const auto exact = gm::make_egm96_field(kEgm, 360, false);
  double worst = 0, worst_dh = 0, change = 0, worst_one = 0;
  const double mid = 0.5 * (fm.h_min_m + fm.h_max_m);  // one layer at mid height, for comparison
  for (int s = 0; s <= static_cast<int>(sc.duration_s); s += 5) {
    const auto st = gen.trajectory().at(static_cast<ggins::truth3d::Real>(s));
    const double la = static_cast<double>(st.lat), lo = static_cast<double>(st.lon), h = static_cast<double>(st.h);
    const gg_gmap_t* t = nullptr;
    assert_int_equal(store.ops.tile_at(store.ops.ctx, GG_GMAP_KIND_TENSOR, la, lo, h, &t), GG_OK);
    const double dh = std::fabs(h - t->tile.h0_m);
    assert_true(dh <= t->tile.h_range_m);
    assert_true(dh <= 0.5 * gm::kLayerMaxM + 1e-6);  // the nearest layer
    worst_dh = std::max(worst_dh, dh);
    gg_gmap_sample_t smp;
    assert_int_equal(gg_gmap_eval(t, la, lo, h, GG_GMAP_MASK_ALL, 0, &smp), GG_OK);
    double ref[GG_GMAP_NVAL], ref0[GG_GMAP_NVAL];
    gm::node_values(*exact, la, lo, h, ref);
    gm::node_values(*exact, la, lo, t->tile.h0_m, ref0);
    double one[GG_GMAP_NVAL];
    gm::node_values(*exact, la, lo, mid, one);
    for (int c = 0; c < 6; ++c) {
      worst_one = std::max(worst_one, std::fabs(one[c] + (h - mid) * one[6 + c] - ref[c]));
      worst = std::max(worst, std::fabs(static_cast<double>(smp.gamma[c]) - ref[c]));
      change = std::max(change, std::fabs(ref[c] - ref0[c]));
    }
  }
  std::printf("served layer at the route's height: |h - h0| <= %.1f m (the field changes by up to %.3f E over it); "
              "interpolation error against exact EGM96-360 %.3e E\n",
              worst_dh, change * 1e9, worst * 1e9);
  std::printf("one layer at %.0f m instead (its first-order term, exact nodes): %.3e E\n", mid, worst_one * 1e9);
  // 0.05 deg horizontally 4.5e-4 E, the height term <= 3.4e-4 E at 300 m (docs/map-matching.md)
  assert_true(worst * 1e9 < 1.0e-3);
  assert_true(worst_one > 10.0 * worst);  // what the layers are for
  // beyond the span: the storage's tile does not hold the height
  const auto st = gen.trajectory().at(250.0L);
  for (const double h : {fm.h_min_m - 1000.0, fm.h_max_m + 1000.0}) {
    const gg_gmap_t* t = nullptr;
    assert_int_equal(store.ops.tile_at(store.ops.ctx, GG_GMAP_KIND_TENSOR, static_cast<double>(st.lat),
                                       static_cast<double>(st.lon), h, &t),
                     GG_OK);
    assert_false(std::fabs(h - t->tile.h0_m) <= t->tile.h_range_m);
  }
  // the route against the storage before take-off (run3d map_coverage.hpp), against the
  // route's own heights and the layers' bands read from the tiles
  std::vector<std::string> all, low;
  double low_top = -1e300;  // the top of the bands of the tiles with h0 below 3600 m
  for (int k = 0; k < fm.tiles; ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "tile_%04d.gmap", k);
    all.push_back((dir / name).string());
    const gg_gmap_tile_t& tk = store.tiles[k]->tile;
    if (tk.h0_m < 3600.0) {
      low.push_back(all.back());
      low_top = std::max(low_top, tk.h0_m + tk.h_range_m);
    }
  }
  const auto pts = ggins::run3d::route_samples(gen, sc.duration_s);
  const ggins::run3d::Coverage full = ggins::run3d::route_coverage(pts, all, GG_GMAP_KIND_TENSOR);
  assert_true(full.complete());
  assert_int_equal(full.covered, static_cast<int64_t>(pts.size()));
  const ggins::run3d::Coverage gzz = ggins::run3d::route_coverage(pts, all, GG_GMAP_KIND_GZZ);
  assert_int_equal(gzz.gaps.size(), 1);
  assert_true(gzz.gaps[0].why == "area" && gzz.covered == 0 && gzz.gaps[0].to.t_s == sc.duration_s);
  const ggins::run3d::Coverage lo_only = ggins::run3d::route_coverage(pts, low, GG_GMAP_KIND_TENSOR);
  double first_above = -1;  // the first sample above the low layers' bands
  for (const auto& q : pts)
    if (q.h_m > low_top) {
      first_above = q.t_s;
      break;
    }
  std::printf("coverage: all tiles %lld of %zu samples; Gamma_zz kind none; the layers below 3600 m (bands up to "
              "%.0f m) leave %zu stretch(es), the first from t = %.0f s (the route passes %.0f m at t = %.0f s):%s\n",
              static_cast<long long>(full.covered), pts.size(), low_top, lo_only.gaps.size(),
              lo_only.gaps.empty() ? -1.0 : lo_only.gaps[0].from.t_s, low_top, first_above, lo_only.text(2).c_str());
  assert_true(first_above > 0);
  assert_true(!lo_only.gaps.empty() && lo_only.gaps[0].why == "height");
  assert_true(lo_only.gaps[0].from.t_s == first_above);
  assert_true(lo_only.gaps.back().to.t_s == sc.duration_s);  // climbing to the end
  hal_map_free(&store);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

int main() {
  if (!fs::exists(kEgm)) {
    std::printf("no %s: skipped\n", kEgm.c_str());
    return 77;
  }
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_third_by_differences),
      cmocka_unit_test(test_tiles_against_egm96),
      cmocka_unit_test(test_layers_climbing),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
