#include "ggins/covariance/scenario.hpp"

#include <cmath>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/truth/scenario.hpp"
#include "ggins/truth/scenario_toml.hpp"

namespace ggins::covariance {

namespace fs = std::filesystem;

std::vector<std::string> builtin_names() { return {"welker-table1"}; }

std::optional<CovScenario> builtin_scenario(const std::string& name) {
  if (name == "welker-table1") {
    // Welker, Pachter & Huffman, section VI and Table I: V = 300 m/s, L0 = 0,
    // level flight (h = 0) due north for T = 3600 s over a spherical Earth,
    // sigma_a = 2e-12 m/s^2 on all eight accelerometer axes (eq. 11's P(0)),
    // dG(0) ~ 2e-12 m/s^2 (eq. 8), half-baseline a = b = 0.5 m (docs/design.md).
    CovScenario s;  // the defaults are this scenario
    s.name = name;
    return s;
  }
  return std::nullopt;
}

namespace {

double num(const toml::node* n, const std::string& key) {
  if (!n) throw std::runtime_error("missing " + key);
  if (auto v = n->value<double>()) {
    if (!std::isfinite(*v)) throw std::runtime_error(key + " = " + std::to_string(*v) + " is not finite (allowed: a finite number)");
    return *v;
  }
  throw std::runtime_error(key + " is not a number");
}

// The file is a scenario of the truth generator (the same keys, types and ranges: an
// unknown key or section, a NaN, a value out of range is an error there) plus the
// covariance-only [initial] table, checked here.
void check_against_truth_schema(const toml::table& tbl, const std::string& path) {
  if (tbl.empty())
    throw std::runtime_error("scenario " + path + ": the file sets no key (allowed: a scenario table; for the defaults "
                             "use the built-in welker-table1)");
  toml::table rest = tbl;
  if (const toml::node* n = tbl.get("initial")) {
    if (!n->is_table()) throw std::runtime_error("scenario " + path + ": 'initial' must be a table ([initial])");
    ggins::truth::scenario_toml::check_keys(*n->as_table(), "initial",
                                            {"gravity_sigma_mps2", "position_sigma_m", "velocity_sigma_mps"}, path);
    rest.erase("initial");
  }
  // per-axis sigmas (8 values, f1x..f4z) are a covariance-only form of two accel keys: the
  // truth generator takes one number there; the arrays are checked element by element here
  if (toml::table* acc = rest["accel"].as_table())
    for (const char* k : {"bias_sigma_mps2", "noise_sigma_mps2"})
      if (acc->get(k) && acc->get(k)->is_array()) acc->insert_or_assign(k, 0.0);
  std::ostringstream os;
  os << rest;
  (void)ggins::truth::parse_scenario(os.str(), fs::path(path).stem().string(), path);
}

void check_sigma(double v, const std::string& path, const std::string& key) {
  if (!(std::isfinite(v) && v >= 0.0))
    throw std::runtime_error("scenario " + path + ": " + key + " = " + std::to_string(v) +
                             " (allowed: a finite number >= 0)");
}

}  // namespace

CovScenario load_scenario_toml(const std::string& path) {
  toml::table tbl;
  try {
    tbl = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw std::runtime_error(path + ": " + std::string(e.description()));
  }
  check_against_truth_schema(tbl, path);
  // Keys shared with the truth generator / ggins run (scenarios/*.toml, see
  // host_tools/truth/include/ggins/truth/scenario.hpp). Missing keys take the
  // truth generator's defaults (no accelerometer errors) and are listed in
  // `defaulted`. The firmware starts from the true G(r0) in host-in-the-loop
  // runs, so dG(0) defaults to 0 here; the optional [initial] table is read by
  // ggins-covariance only (the truth generator rejects unknown tables, so put
  // it only in covariance-only files, or use --sigma-g0).
  CovScenario s;
  s.source = path;
  s.bias_sigma_mps2.assign(8, 0.0);
  s.gravity0_sigma_x_mps2 = s.gravity0_sigma_z_mps2 = 0.0;
  s.name = tbl["name"].value_or(fs::path(path).stem().string());
  auto node = [&](const char* dotted) { return tbl.at_path(dotted).node(); };
  auto get = [&](const char* dotted, double& dst) {
    const toml::node* n = node(dotted);
    if (!n) {
      s.defaulted.emplace_back(dotted);
      return;
    }
    try {
      dst = num(n, dotted);
    } catch (const std::exception& e) {
      throw std::runtime_error(path + ": " + e.what());
    }
  };
  if (auto m = tbl.at_path("gravity.model").value<std::string>(); m && *m != "point-mass")
    throw std::runtime_error(path + ": gravity.model '" + *m + "' not supported by ggins-covariance yet (point-mass)");
  if (auto t = tbl.at_path("trajectory.type").value<std::string>()) s.trajectory = *t;
  if (s.trajectory != "north-flight")
    throw std::runtime_error(path + ": trajectory.type '" + s.trajectory + "' not supported (north-flight)");
  if (auto g = tbl.at_path("navigation.gravity").value<std::string>(); g && *g != "gradiometer")
    throw std::runtime_error(path + ": navigation.gravity '" + *g +
                             "': ggins-covariance models the gradiometer mode (Welker et al.) only");
  // Inputs of the truth generator that the linear model does not contain.
  if (node("accel.bias_mps2")) s.unmodelled.emplace_back("accel.bias_mps2 (deterministic biases)");
  if (node("accel.scale")) s.unmodelled.emplace_back("accel.scale (deterministic scale factors)");
  {  // barometric vertical loop: the loop is on when [navigation.baro] enable says so,
     // else when there is a [baro] table that does not disable the barometer (truth generator rules)
    const bool baro_sensor = node("baro") && tbl.at_path("baro.enable").value_or(true);
    s.baro_loop = tbl.at_path("navigation.baro.enable").value_or(baro_sensor);
    if (s.baro_loop) {
      const double rate = tbl.at_path("baro.rate_hz").value_or(1.0);
      s.baro_period_s = tbl.at_path("navigation.baro.period_s").value_or(1.0 / rate);
      s.baro_omega_s2 = tbl.at_path("navigation.baro.omega_s2").value_or(0.0);
      if (const toml::array* a = tbl.at_path("navigation.baro.poles_radps").as_array()) {
        if (a->size() != 3) throw std::runtime_error(path + ": navigation.baro.poles_radps needs 3 values");
        for (size_t i = 0; i < 3; ++i) s.baro_poles_radps[i] = num(a->get(i), "navigation.baro.poles_radps");
      }
      if (baro_sensor) {
        s.baro_bias_m = tbl.at_path("baro.bias_m").value_or(0.0);
        s.baro_gm_sigma_m = tbl.at_path("baro.gm_sigma_m").value_or(0.0);
        s.baro_gm_tau_s = tbl.at_path("baro.gm_tau_s").value_or(600.0);
        s.baro_noise_sigma_m = tbl.at_path("baro.noise_sigma_m").value_or(0.0);
      }
      for (const char* k : {"baro.dropout_prob", "baro.dropouts", "baro.outlier_prob", "baro.invalid_prob"})
        if (node(k)) s.unmodelled.emplace_back(std::string(k) + " (barometer faults)");
    }
  }
  if (node("sensor_faults")) s.unmodelled.emplace_back("sensor_faults");
  get("time.duration_s", s.duration_s);
  get("gravity.gm_m3ps2", s.gm_m3ps2);
  get("trajectory.radius_m", s.radius_m);
  get("trajectory.speed_mps", s.speed_mps);
  get("trajectory.height_m", s.height_m);
  {
    double d = 0;
    get("trajectory.lat0_deg", d);
    s.lat0_rad = d * M_PI / 180.0;
  }
  get("platform.a_m", s.a_m);
  get("platform.b_m", s.b_m);
  get("time.rate_hz", s.rate_hz);
  auto vec8 = [&](const char* dotted, std::vector<double>& dst) {
    const toml::node* n = node(dotted);
    if (!n) {
      s.defaulted.emplace_back(dotted);
      return;
    }
    if (const toml::array* arr = n->as_array()) {
      if (arr->size() != 8) throw std::runtime_error(path + ": " + dotted + " needs 8 values (f1x f2x f3x f4x f1z f2z f3z f4z)");
      for (size_t i = 0; i < 8; ++i) dst[i] = num(arr->get(i), dotted);
    } else {
      dst.assign(8, num(n, dotted));
    }
  };
  try {
    vec8("accel.bias_sigma_mps2", s.bias_sigma_mps2);
    vec8("accel.noise_sigma_mps2", s.noise_sigma_mps2);
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    throw std::runtime_error(m.rfind(path, 0) == 0 ? m : "scenario " + path + ": " + m);
  }
  get("accel.scale_sigma", s.scale_sigma);
  if (const toml::node* n = node("initial.gravity_sigma_mps2")) {
    if (const toml::array* arr = n->as_array()) {
      if (arr->size() != 2) throw std::runtime_error(path + ": initial.gravity_sigma_mps2 needs [x, z]");
      s.gravity0_sigma_x_mps2 = num(arr->get(0), "initial.gravity_sigma_mps2[0]");
      s.gravity0_sigma_z_mps2 = num(arr->get(1), "initial.gravity_sigma_mps2[1]");
    } else {
      s.gravity0_sigma_x_mps2 = s.gravity0_sigma_z_mps2 = num(n, "initial.gravity_sigma_mps2");
    }
  } else {
    s.defaulted.emplace_back("initial.gravity_sigma_mps2");
  }
  get("initial.position_sigma_m", s.pos0_sigma_m);
  get("initial.velocity_sigma_mps", s.vel0_sigma_mps);
  for (size_t i = 0; i < 8; ++i) {
    check_sigma(s.bias_sigma_mps2[i], path, "accel.bias_sigma_mps2[" + std::to_string(i) + "]");
    check_sigma(s.noise_sigma_mps2[i], path, "accel.noise_sigma_mps2[" + std::to_string(i) + "]");
  }
  check_sigma(s.scale_sigma, path, "accel.scale_sigma");
  check_sigma(s.gravity0_sigma_x_mps2, path, "initial.gravity_sigma_mps2");
  check_sigma(s.gravity0_sigma_z_mps2, path, "initial.gravity_sigma_mps2");
  check_sigma(s.pos0_sigma_m, path, "initial.position_sigma_m");
  check_sigma(s.vel0_sigma_mps, path, "initial.velocity_sigma_mps");
  if (s.baro_loop) {
    check_sigma(s.baro_bias_m, path, "baro.bias_m");
    check_sigma(s.baro_gm_sigma_m, path, "baro.gm_sigma_m");
    check_sigma(s.baro_noise_sigma_m, path, "baro.noise_sigma_m");
    if (!(std::isfinite(s.baro_period_s) && s.baro_period_s > 0) || !(std::isfinite(s.baro_gm_tau_s) && s.baro_gm_tau_s > 0))
      throw std::runtime_error("scenario " + path + ": baro period and baro.gm_tau_s must be finite and > 0");
  }
  if (!(s.duration_s > 0) || !(s.radius_m > 0) || !(s.gm_m3ps2 > 0) || !(s.a_m > 0) || !(s.b_m > 0) ||
      !(s.rate_hz > 0))
    throw std::runtime_error(path + ": duration, radius, GM, rate and half-baselines must be > 0");
  return s;
}

CovScenario resolve_scenario(const std::string& arg, const std::string& repo_root) {
  std::error_code ec;
  if (fs::is_regular_file(arg, ec)) return load_scenario_toml(arg);
  std::vector<fs::path> dirs{fs::path("scenarios")};
  if (!repo_root.empty()) dirs.push_back(fs::path(repo_root) / "scenarios");
  for (const fs::path& dir : dirs) {
    const fs::path p = dir / (arg + ".toml");
    if (fs::is_regular_file(p, ec)) return load_scenario_toml(p.string());
  }
  if (auto b = builtin_scenario(arg)) return *b;
  throw std::runtime_error("unknown scenario '" + arg + "' (no such file, no scenarios/" + arg +
                           ".toml, not built in)");
}

}  // namespace ggins::covariance
