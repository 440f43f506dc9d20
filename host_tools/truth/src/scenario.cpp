#include "ggins/truth/scenario.hpp"
#include "ggins/truth/fdi_thresholds.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/gravity/normal.hpp"
#include "ggins/truth/scenario_toml.hpp"
#include "sensor_faults_parse.hpp"

namespace ggins::truth {

// Generated at configure time from scenarios/*.toml (builtin_scenarios.cpp).
struct BuiltinScenario {
  const char* name;
  const char* text;
};
extern const BuiltinScenario kBuiltinScenarios[];
extern const int kBuiltinScenarioCount;

namespace {

using scenario_toml::check_keys;
using scenario_toml::fail;
using scenario_toml::get_bool;
using scenario_toml::get_int;
using scenario_toml::get_num;
using scenario_toml::get_str;

const toml::table* sub(const toml::table& root, const char* name, const std::string& source) {
  const toml::node* n = root.get(name);
  if (!n) return nullptr;
  if (!n->is_table()) fail(source, std::string("'") + name + "' must be a table ([" + name + "])");
  return n->as_table();
}

void get_per_axis(const toml::table& t, const std::string& where, const char* key,
                  std::array<std::array<double, 3>, kMaxAcc>& out, const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return;
  const toml::array* rows = n->as_array();
  const std::string k = where + "." + key;
  if (!rows || rows->size() > static_cast<size_t>(kMaxAcc))
    fail(source, k + " must be an array of up to 6 [x, y, z] arrays (one per accelerometer)");
  for (size_t i = 0; i < rows->size(); ++i) {
    const toml::array* row = (*rows)[i].as_array();
    if (!row || row->size() != 3) fail(source, k + "[" + std::to_string(i) + "] must be [x, y, z]");
    for (size_t j = 0; j < 3; ++j) {
      auto d = (*row)[j].value<double>();
      if (!d || !std::isfinite(*d)) fail(source, k + " entries must be finite numbers");
      out[i][j] = *d;
    }
  }
}

uint64_t get_seed(const toml::table& t, const std::string& where, const std::string& source) {
  const int64_t s = get_int(t, where, "seed", 1, source);
  if (s < 0) fail(source, where + ".seed must be >= 0");
  return static_cast<uint64_t>(s);
}

void check_prob(double p, const std::string& key, const std::string& source) {
  if (!(p >= 0.0 && p < 1.0)) fail(source, key + " must be in [0, 1)");
}

// An array of finite numbers with n_min..n_max entries.
std::vector<double> get_num_array(const toml::table& t, const std::string& where, const char* key, size_t n_min,
                                  size_t n_max, const std::string& source) {
  std::vector<double> v;
  const toml::node* n = t.get(key);
  if (!n) return v;
  const toml::array* a = n->as_array();
  const std::string k = where + "." + key;
  if (!a || a->size() < n_min || a->size() > n_max)
    fail(source, k + " must be an array of " + std::to_string(n_min) + ".." + std::to_string(n_max) + " numbers");
  for (const auto& e : *a) {
    auto d = e.value<double>();
    if (!d || !std::isfinite(*d)) fail(source, k + " entries must be finite numbers");
    v.push_back(*d);
  }
  return v;
}

}  // namespace

int64_t Scenario::dt_us() const { return static_cast<int64_t>(std::llround(1e6 / rate_hz)); }

int64_t Scenario::baro_every() const {
  return std::max<int64_t>(1, static_cast<int64_t>(std::llround(rate_hz / baro.rate_hz)));
}

NavModelParams Scenario::nav_model() const {
  if (navigation.model.set) return navigation.model;
  NavModelParams m;
  m.set = true;
  if (gravity.model == "point-mass") {
    m.gm_m3ps2 = gravity.gm_m3ps2;
    m.a_m = trajectory.radius_m;
  } else {  // the WGS-84 normal field's zonal series: GM, a, J2, J4, J6, J8
    const gravity::NormalField n;
    m.gm_m3ps2 = static_cast<double>(n.params().gm);
    m.a_m = static_cast<double>(n.params().a);
    for (int k = 1; 2 * k <= 8; ++k) m.j[static_cast<size_t>(2 * k)] = static_cast<double>(n.j2n(k));
  }
  return m;
}

int64_t Scenario::n_steps() const {
  return static_cast<int64_t>(std::llround(duration_s * 1e6 / static_cast<double>(dt_us()))) + 1;
}

Scenario parse_scenario(const std::string& text, const std::string& fallback_name, const std::string& source) {
  toml::table root;
  try {
    root = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << e.description() << " (line " << e.source().begin.line << ", column " << e.source().begin.column << ")";
    fail(source, os.str());
  }
  Scenario s;
  s.source = source;
  s.text = text;
  check_keys(root, "",
             {"name", "description", "trajectory", "gravity", "platform", "time", "accel", "firmware",
              "transport", "output", "sensor_faults", "navigation", "baro"},
             source);
  s.name = get_str(root, "", "name", fallback_name, source);
  s.description = get_str(root, "", "description", "", source);
  if (s.name.empty() || s.name.size() > 63) fail(source, "name must have 1..63 characters");

  if (const auto* t = sub(root, "trajectory", source)) {
    check_keys(*t, "trajectory", {"type", "speed_mps", "height_m", "lat0_deg", "radius_m"}, source);
    auto& p = s.trajectory;
    p.type = get_str(*t, "trajectory", "type", p.type, source);
    p.speed_mps = get_num(*t, "trajectory", "speed_mps", p.speed_mps, source);
    p.height_m = get_num(*t, "trajectory", "height_m", p.height_m, source);
    p.lat0_deg = get_num(*t, "trajectory", "lat0_deg", p.lat0_deg, source);
    p.radius_m = get_num(*t, "trajectory", "radius_m", p.radius_m, source);
  }
  if (s.trajectory.type != "north-flight")
    fail(source, "trajectory.type '" + s.trajectory.type + "' unknown (known: north-flight)");
  if (!(s.trajectory.radius_m + s.trajectory.height_m > 1.0))
    fail(source, "trajectory.radius_m + height_m must be > 1 m");
  if (std::fabs(s.trajectory.lat0_deg) > 90.0) fail(source, "trajectory.lat0_deg must be within [-90, 90]");

  if (const auto* t = sub(root, "gravity", source)) {
    check_keys(*t, "gravity", {"model", "gm_m3ps2", "anomaly"}, source);
    s.gravity.model = get_str(*t, "gravity", "model", s.gravity.model, source);
    s.gravity.gm_m3ps2 = get_num(*t, "gravity", "gm_m3ps2", s.gravity.gm_m3ps2, source);
    if (const toml::node* an = t->get("anomaly")) {
      if (!an->is_table()) fail(source, "'gravity.anomaly' must be a table ([gravity.anomaly])");
      const toml::table& a = *an->as_table();
      const std::string w = "gravity.anomaly";
      check_keys(a, w,
                 {"seed", "lat_deg", "lon_deg", "half_size_m", "ref_height_m", "rms_arcsec", "corr_length_m",
                  "ewald_sigma_m", "lattice_spacing_m", "lattice_points"},
                 source);
      auto& p = s.gravity.anomaly;
      p.seed = get_seed(a, w, source);
      p.lat_deg = get_num(a, w, "lat_deg", p.lat_deg, source);
      p.lon_deg = get_num(a, w, "lon_deg", p.lon_deg, source);
      p.half_size_m = get_num(a, w, "half_size_m", p.half_size_m, source);
      p.ref_height_m = get_num(a, w, "ref_height_m", p.ref_height_m, source);
      p.rms_arcsec = get_num(a, w, "rms_arcsec", p.rms_arcsec, source);
      p.corr_length_m = get_num(a, w, "corr_length_m", p.corr_length_m, source);
      p.ewald_sigma_m = get_num(a, w, "ewald_sigma_m", p.ewald_sigma_m, source);
      p.lattice_spacing_m = get_num(a, w, "lattice_spacing_m", p.lattice_spacing_m, source);
      p.lattice_points = get_int(a, w, "lattice_points", p.lattice_points, source);
      if (std::fabs(p.lat_deg) > 90.0) fail(source, w + ".lat_deg must be within [-90, 90]");
      if (!(p.half_size_m > 0) || !(p.rms_arcsec >= 0) || !(p.corr_length_m > 0) || !(p.ewald_sigma_m > 0) ||
          !(p.lattice_spacing_m > 0))
        fail(source, w + ": half_size_m, corr_length_m, ewald_sigma_m, lattice_spacing_m must be > 0, rms_arcsec >= 0");
      if (p.lattice_points < 2 || p.lattice_points > 16 || p.lattice_points % 2 != 0)
        fail(source, w + ".lattice_points must be even, 2..16");
    }
  }
  if (s.gravity.model != "point-mass" && s.gravity.model != "wgs84-normal" && s.gravity.model != "rw-anomaly")
    fail(source, "gravity.model '" + s.gravity.model + "' unknown (known: point-mass, wgs84-normal, rw-anomaly)");
  if (!(s.gravity.gm_m3ps2 > 0)) fail(source, "gravity.gm_m3ps2 must be > 0");

  if (const auto* t = sub(root, "platform", source)) {
    check_keys(*t, "platform", {"a_m", "b_m"}, source);
    s.a_m = get_num(*t, "platform", "a_m", s.a_m, source);
    s.b_m = get_num(*t, "platform", "b_m", s.b_m, source);
  }
  if (!(s.a_m > 0) || !(s.b_m > 0)) fail(source, "platform.a_m and platform.b_m must be > 0");

  if (const auto* t = sub(root, "time", source)) {
    check_keys(*t, "time", {"duration_s", "rate_hz"}, source);
    s.duration_s = get_num(*t, "time", "duration_s", s.duration_s, source);
    s.rate_hz = get_num(*t, "time", "rate_hz", s.rate_hz, source);
  }
  if (!(s.rate_hz > 0) || s.rate_hz > 1e6) fail(source, "time.rate_hz must be in (0, 1e6]");
  {
    const double dt = 1e6 / s.rate_hz;
    if (std::fabs(dt - std::round(dt)) > 1e-9 * dt)
      fail(source, "time.rate_hz must make 1e6/rate_hz an integer number of microseconds");
  }
  if (!(s.duration_s > 0) || s.duration_s > 1e7) fail(source, "time.duration_s must be in (0, 1e7]");

  if (const auto* t = sub(root, "accel", source)) {
    check_keys(*t, "accel",
               {"seed", "bias_sigma_mps2", "noise_sigma_mps2", "scale_sigma", "bias_mps2", "scale"}, source);
    auto& a = s.accel;
    a.seed = get_seed(*t, "accel", source);
    a.bias_sigma_mps2 = get_num(*t, "accel", "bias_sigma_mps2", 0.0, source);
    a.noise_sigma_mps2 = get_num(*t, "accel", "noise_sigma_mps2", 0.0, source);
    a.scale_sigma = get_num(*t, "accel", "scale_sigma", 0.0, source);
    if (a.bias_sigma_mps2 < 0 || a.noise_sigma_mps2 < 0 || a.scale_sigma < 0)
      fail(source, "accel sigmas must be >= 0");
    get_per_axis(*t, "accel", "bias_mps2", a.bias_mps2, source);
    get_per_axis(*t, "accel", "scale", a.scale, source);
  }
  if (const auto* t = sub(root, "firmware", source)) {
    check_keys(*t, "firmware",
               {"f_max_mps2", "asym_max_ps2", "dt_tol_us", "gravdr_trapezoid_only", "fdi_parity_f_max_mps2",
                "fdi_asym_max_ps2"},
               source);
    auto& f = s.firmware;
    f.f_max_mps2 = get_num(*t, "firmware", "f_max_mps2", f.f_max_mps2, source);
    f.asym_max_ps2 = get_num(*t, "firmware", "asym_max_ps2", f.asym_max_ps2, source);
    f.dt_tol_us = get_int(*t, "firmware", "dt_tol_us", f.dt_tol_us, source);
    f.gravdr_trapezoid_only = get_bool(*t, "firmware", "gravdr_trapezoid_only", f.gravdr_trapezoid_only, source);
    if (!(f.f_max_mps2 > 0) || !(f.asym_max_ps2 > 0) || f.dt_tol_us < 0)
      fail(source, "firmware.f_max_mps2 and asym_max_ps2 must be > 0, dt_tol_us >= 0");
    f.fdi_parity_f_max_set = t->contains("fdi_parity_f_max_mps2");
    f.fdi_asym_max_set = t->contains("fdi_asym_max_ps2");
    f.fdi_parity_f_max_mps2 = get_num(*t, "firmware", "fdi_parity_f_max_mps2", f.fdi_parity_f_max_mps2, source);
    f.fdi_asym_max_ps2 = get_num(*t, "firmware", "fdi_asym_max_ps2", f.fdi_asym_max_ps2, source);
    if (f.fdi_parity_f_max_mps2 < 0 || f.fdi_asym_max_ps2 < 0)
      fail(source, "firmware.fdi_parity_f_max_mps2 and fdi_asym_max_ps2 must be >= 0 (0: off)");
  }
  if (const auto* t = sub(root, "transport", source)) {
    check_keys(*t, "transport", {"seed", "drop_prob", "duplicate_prob", "reorder_prob", "output_drop_prob", "garbage_prob"}, source);
    auto& p = s.transport;
    p.seed = get_seed(*t, "transport", source);
    p.drop_prob = get_num(*t, "transport", "drop_prob", 0.0, source);
    p.duplicate_prob = get_num(*t, "transport", "duplicate_prob", 0.0, source);
    p.reorder_prob = get_num(*t, "transport", "reorder_prob", 0.0, source);
    check_prob(p.drop_prob, "transport.drop_prob", source);
    check_prob(p.duplicate_prob, "transport.duplicate_prob", source);
    p.output_drop_prob = get_num(*t, "transport", "output_drop_prob", 0.0, source);
    check_prob(p.reorder_prob, "transport.reorder_prob", source);
    check_prob(p.output_drop_prob, "transport.output_drop_prob", source);
    p.garbage_prob = get_num(*t, "transport", "garbage_prob", 0.0, source);
    check_prob(p.garbage_prob, "transport.garbage_prob", source);
  }
  if (const auto* t = sub(root, "navigation", source)) {
    const std::string w = "navigation";
    check_keys(*t, w, {"gravity", "r_ref_m", "model", "baro", "survey"}, source);
    auto& n = s.navigation;
    n.gravity = get_str(*t, w, "gravity", n.gravity, source);
    if (n.gravity != "gradiometer" && n.gravity != "model")
      fail(source, "navigation.gravity '" + n.gravity + "' unknown (known: gradiometer, model)");
    n.r_ref_m = get_num(*t, w, "r_ref_m", n.r_ref_m, source);
    if (n.r_ref_m < 0) fail(source, "navigation.r_ref_m must be >= 0 (0: trajectory.radius_m)");
    if (const auto* m = sub(*t, "model", source)) {
      const std::string wm = "navigation.model";
      check_keys(*m, wm, {"gm_m3ps2", "a_m", "j"}, source);
      n.model.set = true;
      n.model.gm_m3ps2 = get_num(*m, wm, "gm_m3ps2", s.gravity.gm_m3ps2, source);
      n.model.a_m = get_num(*m, wm, "a_m", s.trajectory.radius_m, source);
      const std::vector<double> j = get_num_array(*m, wm, "j", 0, 7, source);
      for (size_t i = 0; i < j.size(); ++i) n.model.j[i + 2] = j[i];
      if (!(n.model.gm_m3ps2 > 0) || !(n.model.a_m > 0)) fail(source, wm + ": gm_m3ps2 and a_m must be > 0");
    }
    if (const auto* v = sub(*t, "survey", source)) {
      const std::string wv = "navigation.survey";
      check_keys(*v, wv,
                 {"enable", "seed", "spacing_m", "margin_m", "n_rho", "drho_m", "noise_gravity_mgal",
                  "noise_deflection_arcsec"},
                 source);
      auto& g = n.survey;
      g.enable = get_bool(*v, wv, "enable", true, source);
      g.seed = get_seed(*v, wv, source);
      g.spacing_m = get_num(*v, wv, "spacing_m", g.spacing_m, source);
      g.margin_m = get_num(*v, wv, "margin_m", g.margin_m, source);
      g.n_rho = get_int(*v, wv, "n_rho", g.n_rho, source);
      g.drho_m = get_num(*v, wv, "drho_m", g.drho_m, source);
      g.noise_gravity_mgal = get_num(*v, wv, "noise_gravity_mgal", g.noise_gravity_mgal, source);
      g.noise_deflection_arcsec = get_num(*v, wv, "noise_deflection_arcsec", g.noise_deflection_arcsec, source);
      if (!(g.spacing_m >= 10 && g.spacing_m <= 1e6) || !(g.margin_m >= 0 && g.margin_m <= 1e6) || g.n_rho < 2 ||
          g.n_rho > 64 || !(g.drho_m >= 1 && g.drho_m <= 1e5) || !(g.noise_gravity_mgal >= 0) ||
          !(g.noise_deflection_arcsec >= 0) || !std::isfinite(g.noise_gravity_mgal) ||
          !std::isfinite(g.noise_deflection_arcsec))
        fail(source, wv + ": spacing_m in [10, 1e6], margin_m in [0, 1e6], n_rho in [2, 64], drho_m in [1, 1e5], "
                          "noise_* >= 0 and finite");
    }
    if (const auto* b = sub(*t, "baro", source)) {
      const std::string wb = "navigation.baro";
      check_keys(*b, wb,
                 {"enable", "poles_radps", "period_s", "omega_s2", "max_age_s", "coast_s", "alt_min_m", "alt_max_m",
                  "gate_m", "max_rejects"},
                 source);
      auto& l = n.baro;
      if (b->get("enable")) l.enable = get_bool(*b, wb, "enable", false, source) ? 1 : 0;
      const std::vector<double> p = get_num_array(*b, wb, "poles_radps", 3, 3, source);
      if (!p.empty()) l.poles_radps = {p[0], p[1], p[2]};
      l.period_s = get_num(*b, wb, "period_s", l.period_s, source);
      l.omega_s2 = get_num(*b, wb, "omega_s2", l.omega_s2, source);
      l.max_age_s = get_num(*b, wb, "max_age_s", l.max_age_s, source);
      l.coast_s = get_num(*b, wb, "coast_s", l.coast_s, source);
      l.alt_min_m = get_num(*b, wb, "alt_min_m", l.alt_min_m, source);
      l.alt_max_m = get_num(*b, wb, "alt_max_m", l.alt_max_m, source);
      l.gate_m = get_num(*b, wb, "gate_m", l.gate_m, source);
      l.max_rejects = get_int(*b, wb, "max_rejects", l.max_rejects, source);
      for (double q : l.poles_radps)
        if (!(q > 0)) fail(source, wb + ".poles_radps must be > 0 (the loop's poles are -p)");
      if (l.period_s < 0 || l.omega_s2 < 0 || l.max_age_s < 0 || !(l.coast_s > 0) || !(l.alt_max_m > l.alt_min_m) ||
          !(l.gate_m > 0) || l.max_rejects < 1 || l.max_rejects > 1000000)
        fail(source, wb + ": period_s, omega_s2, max_age_s must be >= 0, coast_s and gate_m > 0, alt_max_m > alt_min_m, "
                          "max_rejects >= 1");
    }
  }
  if (const auto* t = sub(root, "baro", source)) {
    const std::string w = "baro";
    check_keys(*t, w,
               {"enable", "seed", "rate_hz", "bias_m", "gm_sigma_m", "gm_tau_s", "noise_sigma_m", "dropout_prob",
                "dropouts", "outlier_prob", "outlier_m", "invalid_prob", "latency_s"},
               source);
    auto& b = s.baro;
    b.enable = get_bool(*t, w, "enable", true, source);  // a [baro] table means a barometer unless it says otherwise
    b.seed = get_seed(*t, w, source);
    b.rate_hz = get_num(*t, w, "rate_hz", b.rate_hz, source);
    b.bias_m = get_num(*t, w, "bias_m", b.bias_m, source);
    b.gm_sigma_m = get_num(*t, w, "gm_sigma_m", b.gm_sigma_m, source);
    b.gm_tau_s = get_num(*t, w, "gm_tau_s", b.gm_tau_s, source);
    b.noise_sigma_m = get_num(*t, w, "noise_sigma_m", b.noise_sigma_m, source);
    b.dropout_prob = get_num(*t, w, "dropout_prob", b.dropout_prob, source);
    b.outlier_prob = get_num(*t, w, "outlier_prob", b.outlier_prob, source);
    b.outlier_m = get_num(*t, w, "outlier_m", b.outlier_m, source);
    b.invalid_prob = get_num(*t, w, "invalid_prob", b.invalid_prob, source);
    b.latency_s = get_num(*t, w, "latency_s", b.latency_s, source);
    if (b.latency_s < 0 || std::fabs(b.latency_s * 1e6 - std::round(b.latency_s * 1e6)) > 1e-6)
      fail(source, "baro.latency_s must be >= 0 and a whole number of microseconds");
    check_prob(b.dropout_prob, "baro.dropout_prob", source);
    check_prob(b.outlier_prob, "baro.outlier_prob", source);
    check_prob(b.invalid_prob, "baro.invalid_prob", source);
    if (!(b.rate_hz > 0) || b.gm_sigma_m < 0 || !(b.gm_tau_s > 0) || b.noise_sigma_m < 0 || b.outlier_m < 0)
      fail(source, "baro: rate_hz and gm_tau_s must be > 0, gm_sigma_m, noise_sigma_m, outlier_m >= 0");
    if (const toml::node* d = t->get("dropouts")) {
      const toml::array* rows = d->as_array();
      if (!rows) fail(source, "baro.dropouts must be an array of [t0_s, t1_s] pairs");
      for (const auto& r : *rows) {
        const toml::array* pr = r.as_array();
        auto a0 = pr && pr->size() == 2 ? (*pr)[0].value<double>() : std::nullopt;
        auto a1 = pr && pr->size() == 2 ? (*pr)[1].value<double>() : std::nullopt;
        if (!a0 || !a1 || !std::isfinite(*a0) || !std::isfinite(*a1) || !(*a1 > *a0))
          fail(source, "baro.dropouts entries must be [t0_s, t1_s] with t1_s > t0_s");
        b.dropouts.push_back({*a0, *a1});
      }
    }
  }
  if (const auto* t = sub(root, "sensor_faults", source)) s.sensor_faults = parse_sensor_faults(*t, source);
  if (s.baro.enable) {
    const double every = s.rate_hz / s.baro.rate_hz;
    if (!(every >= 1.0) || std::fabs(every - std::round(every)) > 1e-9 * every)
      fail(source, "baro.rate_hz must divide time.rate_hz (an integer number of steps per sample)");
  }
  if (s.baro_loop_enabled()) {
    const double pmax = std::max({s.navigation.baro.poles_radps[0], s.navigation.baro.poles_radps[1],
                                  s.navigation.baro.poles_radps[2]});
    if (pmax * s.baro_period_s() > 1.0)
      fail(source, "navigation.baro: largest pole times period_s must be <= 1 (vchan.h)");
  }
  if (const auto* t = sub(root, "output", source)) {
    check_keys(*t, "output", {"csv_rate_hz", "truth_rate_hz"}, source);
    s.output.csv_rate_hz = get_num(*t, "output", "csv_rate_hz", s.output.csv_rate_hz, source);
    s.output.truth_rate_hz = get_num(*t, "output", "truth_rate_hz", s.output.truth_rate_hz, source);
    if (!(s.output.csv_rate_hz > 0) || s.output.truth_rate_hz < 0)
      fail(source, "output.csv_rate_hz must be > 0 and truth_rate_hz >= 0");
  }
  return s;
}

std::vector<std::string> builtin_scenario_names() {
  std::vector<std::string> v;
  for (int i = 0; i < kBuiltinScenarioCount; ++i) v.emplace_back(kBuiltinScenarios[i].name);
  return v;
}

namespace {
Scenario with_fdi_defaults(Scenario s) {
  apply_default_fdi_thresholds(s);
  return s;
}
}  // namespace

Scenario load_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs) {
  namespace fs = std::filesystem;
  auto read_file = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    if (!in) throw std::runtime_error("cannot read scenario file " + p.string());
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  std::error_code ec;
  const fs::path p(name_or_path);
  if (fs::is_regular_file(p, ec)) return with_fdi_defaults(parse_scenario(read_file(p), p.stem().string(), p.string()));
  const bool looks_like_path =
      name_or_path.find('/') != std::string::npos || p.extension() == ".toml";
  if (looks_like_path) throw std::runtime_error("scenario file not found: " + name_or_path);
  for (const auto& d : search_dirs) {
    const fs::path f = fs::path(d) / (name_or_path + ".toml");
    if (fs::is_regular_file(f, ec)) return with_fdi_defaults(parse_scenario(read_file(f), name_or_path, f.string()));
  }
  for (int i = 0; i < kBuiltinScenarioCount; ++i)
    if (name_or_path == kBuiltinScenarios[i].name)
      return with_fdi_defaults(parse_scenario(kBuiltinScenarios[i].text, name_or_path, "built-in:" + name_or_path));
  std::string known;
  for (const auto& n : builtin_scenario_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::runtime_error("unknown scenario '" + name_or_path + "' (built-in: " + known +
                           "; or give a path to a .toml file)");
}

}  // namespace ggins::truth
