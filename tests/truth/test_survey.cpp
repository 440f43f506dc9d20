// Survey grid of the programmed anomalies (truth/survey.hpp) and its
// scenario keys ([navigation.survey]):
//  - parsing: defaults, values, unknown keys and out-of-range values rejected;
//  - geometry: node positions along the flight, recomputed here from the
//    scenario numbers (rho = R + h, angle from the start latitude);
//  - noise-free node values against the disturbance recomputed here at each
//    node position (truth field minus the onboard zonal model), rotated into
//    (t, r) with this test's own unit vectors;
//  - the firmware's interpolation of that grid (gmodel.c, polar grid,
//    bilinear) against the true disturbance on the flight path between nodes:
//    within the bilinear interpolation bound measured from the field's own
//    second differences (independent of gmodel.c);
//  - noise: sample rms of (noisy - true) within a few sigma of the nominal
//    1 mGal / 0.5" x g; seeded (same seed same grid, other seed other grid).
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

#include "ggins/truth/generator.hpp"
#include "ggins/truth/survey.hpp"

using namespace ggins::truth;

#include "check.hpp"

static const char* kBase =
    "[trajectory]\nspeed_mps = 100.0\nheight_m = 3000.0\nlat0_deg = 33.4\n"
    "[gravity]\nmodel = \"rw-anomaly\"\n[gravity.anomaly]\nseed = 3\nhalf_size_m = 60000.0\n"
    "[time]\nduration_s = 200.0\nrate_hz = 10.0\n[navigation]\ngravity = \"model\"\n";

static bool throws_with(const std::string& text, const std::string& what) {
  try {
    parse_scenario(text, "survey-test", "test");
  } catch (const std::runtime_error& e) {
    return std::string(e.what()).find(what) != std::string::npos;
  }
  return false;
}

int main() {
  // parsing
  {
    const Scenario s0 = parse_scenario(kBase, "survey-test", "test");
    CHECK(!s0.navigation.survey.enable, "no [navigation.survey]: grid off");
    const Scenario s1 = parse_scenario(std::string(kBase) + "[navigation.survey]\n", "survey-test", "test");
    const SurveyParams& p = s1.navigation.survey;
    CHECK(p.enable && p.spacing_m == 2000 && p.n_rho == 2 && p.drho_m == 1000 && p.noise_gravity_mgal == 1.0 &&
              p.noise_deflection_arcsec == 0.5 && p.margin_m == 20000 && p.seed == 1,
          "empty [navigation.survey]: enabled with the documented defaults");
    CHECK(throws_with(std::string(kBase) + "[navigation.survey]\nspacing = 3.0\n", "navigation.survey.spacing"),
          "unknown key named");
    CHECK(throws_with(std::string(kBase) + "[navigation.survey]\nn_rho = 1\n", "navigation.survey"), "n_rho = 1 rejected");
    CHECK(throws_with(std::string(kBase) + "[navigation.survey]\nnoise_gravity_mgal = -1.0\n", "navigation.survey"),
          "negative noise rejected");
  }
  const std::string text = std::string(kBase) +
                           "[navigation.survey]\nseed = 5\nspacing_m = 1000.0\nmargin_m = 3000.0\nn_rho = 3\n"
                           "drho_m = 500.0\n";
  const Scenario sc = parse_scenario(text, "survey-test", "test");
  const Generator gen(sc);
  const SurveyGrid s = make_survey_grid(gen);
  const double rho = 6378137.0 + 3000.0, lat0 = 33.4 * M_PI / 180.0;
  // geometry: 20 km flight + 2 x 3 km margins at 1 km -> 27 nodes; 3 levels 500 m apart around rho
  CHECK(s.n_th == 27 && s.n_rho == 3, "nodes %d x %d (27 x 3)", s.n_th, s.n_rho);
  CHECK(std::fabs(s.dth_rad * rho - 1000.0) < 1e-6 && std::fabs(s.th0_rad * rho + 3000.0) < 1e-6 &&
            std::fabs(s.rho0_m - (rho - 500.0)) < 1e-6 && s.drho_m == 500.0 &&
            std::fabs(s.c0 - std::cos(lat0)) < 1e-15 && std::fabs(s.s0 - std::sin(lat0)) < 1e-15,
        "grid geometry from the scenario numbers");
  // noise-free values against the disturbance at the node positions
  double worst = 0, rms_true = 0;
  for (int k = 0; k < s.n_rho; ++k)
    for (int i = 0; i < s.n_th; ++i) {
      const double th = lat0 - 3000.0 / rho + i * 1000.0 / rho, rk = rho - 500.0 + 500.0 * k;
      const Vec3 r(rk * std::cos(th), 0, rk * std::sin(th));
      const Vec3 d = gen.field().eval(r).g - gen.model_g(r);
      const double dt = static_cast<double>(-d(0) * std::sin(th) + d(2) * std::cos(th));
      const double dr = static_cast<double>(d(0) * std::cos(th) + d(2) * std::sin(th));
      const auto& v = s.dg_true[static_cast<size_t>(k * s.n_th + i)];
      worst = std::max({worst, std::fabs(v[0] - dt), std::fabs(v[1] - dr)});
      rms_true += dt * dt + dr * dr;
    }
  rms_true = std::sqrt(rms_true / (2.0 * s.n_th * s.n_rho));
  CHECK(worst < 1e-12 && rms_true > 1e-5, "noise-free nodes = field - zonal model at the nodes: worst %.2e m/s^2 "
        "(rms disturbance %.2e)", worst, rms_true);
  // the firmware's interpolation between nodes (noise-free grid)
  {
    static gg_gmodel_config_t cfg;
    std::memset(&cfg, 0, sizeof cfg);
    const NavModelParams m = sc.nav_model();
    cfg.gm = m.gm_m3ps2;
    cfg.a_m = m.a_m;
    for (int n = 0; n <= GG_GMODEL_MAX_DEGREE; ++n) cfg.j[n] = m.j[static_cast<size_t>(n)];
    SurveyGrid clean = s;
    clean.dg = clean.dg_true;
    fill_gmodel_grid(clean, cfg.grid);
    gg_gmodel_t st;
    CHECK(gg_gmodel_init(&st, &cfg) == GG_OK, "firmware accepts the grid");
    double err = 0, bound = 0;
    for (int i = 0; i + 1 < s.n_th; ++i) {
      const double th = lat0 - 3000.0 / rho + (i + 0.5) * 1000.0 / rho;  // cell centres on the flight radius
      const Vec3 r(rho * std::cos(th), 0, rho * std::sin(th));
      gg_real_t rr[3] = {r(0), r(1), r(2)}, g[3];
      uint32_t fl = 1;
      if (gg_gmodel_eval(&st, &cfg, rr, g, &fl) != GG_OK || fl != 0) { err = 1; break; }
      const Vec3 gt = gen.field().eval(r).g;
      err = std::max({err, static_cast<double>(std::fabs(g[0] - gt(0))), static_cast<double>(std::fabs(g[2] - gt(2)))});
      // bilinear error at a cell centre on the middle level ~ |second difference| / 8 along track
      const auto& a = s.dg_true[static_cast<size_t>(s.n_th + i)];
      const auto& b = s.dg_true[static_cast<size_t>(s.n_th + i + 1)];
      const int j = i + 2 < s.n_th ? i + 2 : i - 1;
      const auto& c = s.dg_true[static_cast<size_t>(s.n_th + j)];
      for (int q = 0; q < 2; ++q) bound = std::max(bound, std::fabs(a[q] - 2 * b[q] + c[q]) / 8.0);
    }
    CHECK(err < 3.0 * bound + 1e-9 && err < 0.2 * rms_true,
          "firmware grid vs truth at cell centres: %.2e m/s^2 (3 x second-difference bound %.2e; rms disturbance %.2e)",
          err, 3.0 * bound, rms_true);
  }
  // noise statistics and seeding
  {
    double st = 0, sr = 0;
    const size_t n = s.dg.size();
    for (size_t i = 0; i < n; ++i) {
      st += std::pow(s.dg[i][0] - s.dg_true[i][0], 2);
      sr += std::pow(s.dg[i][1] - s.dg_true[i][1], 2);
    }
    const double g = static_cast<double>(gen.truth(0).g.norm());
    const double nt = 0.5 * 4.84813681109536e-6 * g, nr = 1e-5;
    const double rt = std::sqrt(st / n) / nt, rr = std::sqrt(sr / n) / nr;
    // 81 samples: the rms ratio has sd ~ 1/sqrt(2 * 81) = 0.079; 4 sd
    CHECK(std::fabs(rt - 1) < 0.32 && std::fabs(rr - 1) < 0.32,
          "noise rms / nominal: tangential %.3f, radial %.3f (81 nodes)", rt, rr);
    const SurveyGrid again = make_survey_grid(gen);
    Scenario sc2 = sc;
    sc2.navigation.survey.seed = 6;
    const Generator gen2(sc2);
    const SurveyGrid other = make_survey_grid(gen2);
    CHECK(again.dg == s.dg && other.dg != s.dg && other.dg_true == s.dg_true, "seeded: reproducible, seed changes noise only");
  }
  // too many nodes: refused with a message
  {
    Scenario big = sc;
    big.navigation.survey.spacing_m = 10.0;
    bool threw = false;
    try {
      make_survey_grid(Generator(big));
    } catch (const std::invalid_argument& e) {
      threw = std::string(e.what()).find("GG_GMODEL_GRID_MAX") != std::string::npos;
    }
    CHECK(threw, "grid beyond GG_GMODEL_GRID_MAX refused");
  }
  std::printf("%s\n", g_fail ? "FAILED" : "all passed");
  return g_fail ? 1 : 0;
}
