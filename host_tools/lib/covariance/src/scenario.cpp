#include "ggins/covariance/scenario.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/truth/scenario.hpp"
#include "ggins/truth/scenario_schema.hpp"
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

// "scenario <path>:<line>" of a node (its line in the user's file, when known)
std::string at(const std::string& path, const toml::node* n) {
  const auto line = n ? n->source().begin.line : 0;
  return "scenario " + path + (line > 0 ? ":" + std::to_string(line) : "");
}

// where: "scenario <path>[:<line>]"
void check_sigma(double v, const std::string& where, const std::string& key) {
  if (!(std::isfinite(v) && v >= 0.0))
    throw std::runtime_error(where + ": " + key + " = " + ggins::truth::sch::num_text(v) +
                             " (allowed: a finite number >= 0)");
}

double num(const toml::node* n, const std::string& key, const std::string& path) {
  if (!n) throw std::runtime_error("scenario " + path + ": missing " + key);
  if (auto v = n->value<double>()) {
    if (!std::isfinite(*v))
      throw std::runtime_error(at(path, n) + ": " + key + " = " + ggins::truth::sch::num_text(*v) +
                               " is not finite (allowed: a finite number >= 0)");
    return *v;
  }
  throw std::runtime_error(at(path, n) + ": " + key + " is not a number (allowed: a finite number >= 0)");
}

// The file is a scenario of the truth generator (the same keys, types and ranges: an
// unknown key or section, a NaN, a value out of range is an error there) plus the
// covariance-only [initial] table, checked here. Returns the truth parser's scenario:
// every shared key's value and default comes from there (truth/scenario.hpp).
ggins::truth::Scenario parse_as_truth_scenario(const std::string& text, const std::string& path) {
  toml::table rest = ggins::truth::sch::parse_toml(text, path);
  if (rest.empty())
    throw std::runtime_error("scenario " + path + ": the file sets no key (allowed: a scenario table; for the defaults "
                             "use the built-in welker-table1)");
  if (const toml::node* n = rest.get("initial")) {
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
  return ggins::truth::parse_scenario_table(rest, text, fs::path(path).stem().string(), path);
}


}  // namespace

CovScenario load_scenario_toml(const std::string& path) {
  std::string text;
  {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("scenario " + path + ": cannot read the file");
    std::ostringstream os;
    os << f.rdbuf();
    text = os.str();
  }
  const ggins::truth::Scenario t = parse_as_truth_scenario(text, path);
  const toml::table tbl = toml::parse(text, path);  // parsed above: well-formed
  // Keys shared with the truth generator / ggins run take their values and defaults from
  // the truth parser (no accelerometer errors unless given); the keys the file leaves out
  // are listed in `defaulted`. The firmware starts from the true G(r0) in host-in-the-loop
  // runs, so dG(0) defaults to 0 here; the optional [initial] table is read by
  // ggins-covariance only (the truth generator rejects unknown tables, so put
  // it only in covariance-only files, or use --sigma-g0).
  CovScenario s;
  s.source = path;
  s.name = t.name;
  s.gravity0_sigma_x_mps2 = s.gravity0_sigma_z_mps2 = 0.0;
  auto node = [&](const char* dotted) { return tbl.at_path(dotted).node(); };
  auto given = [&](const char* dotted) {
    if (node(dotted)) return true;
    s.defaulted.emplace_back(dotted);
    return false;
  };
  if (t.gravity.model != "point-mass")
    throw std::runtime_error(path + ": gravity.model '" + t.gravity.model + "' not supported by ggins-covariance yet (point-mass)");
  s.trajectory = t.trajectory.type;
  if (s.trajectory != "north-flight")
    throw std::runtime_error(path + ": trajectory.type '" + s.trajectory + "' not supported (north-flight)");
  if (t.navigation.gravity != "gradiometer")
    throw std::runtime_error(path + ": navigation.gravity '" + t.navigation.gravity +
                             "': ggins-covariance models the gradiometer mode (Welker et al.) only");
  // Inputs of the truth generator that the linear model does not contain.
  // (by value: a key written out at zero, as in a scenario as flown, adds nothing)
  auto any_nonzero = [](const auto& rows) {
    for (const auto& r : rows)
      for (double x : r)
        if (x != 0.0) return true;
    return false;
  };
  if (any_nonzero(t.accel.bias_mps2)) s.unmodelled.emplace_back("accel.bias_mps2 (deterministic biases)");
  if (any_nonzero(t.accel.scale)) s.unmodelled.emplace_back("accel.scale (deterministic scale factors)");
  // barometric vertical loop (the truth generator's rules: Scenario::baro_loop_enabled)
  s.baro_loop = t.baro_loop_enabled();
  if (s.baro_loop) {
    s.baro_period_s = t.baro_period_s();
    s.baro_omega_s2 = t.navigation.baro.omega_s2;
    for (size_t i = 0; i < 3; ++i) s.baro_poles_radps[i] = t.navigation.baro.poles_radps[i];
    if (t.baro.enable) {
      s.baro_bias_m = t.baro.bias_m;
      s.baro_gm_sigma_m = t.baro.gm_sigma_m;
      s.baro_gm_tau_s = t.baro.gm_tau_s;
      s.baro_noise_sigma_m = t.baro.noise_sigma_m;
    }
    const std::pair<const char*, bool> faults[] = {{"baro.dropout_prob", t.baro.dropout_prob > 0},
                                                   {"baro.dropouts", !t.baro.dropouts.empty()},
                                                   {"baro.outlier_prob", t.baro.outlier_prob > 0},
                                                   {"baro.invalid_prob", t.baro.invalid_prob > 0}};
    for (const auto& [k, on] : faults)
      if (on) s.unmodelled.emplace_back(std::string(k) + " (barometer faults)");
  }
  if (!t.sensor_faults.faults.empty()) s.unmodelled.emplace_back("sensor_faults");
  for (const char* k : {"time.duration_s", "gravity.gm_m3ps2", "trajectory.radius_m", "trajectory.speed_mps",
                        "trajectory.height_m", "trajectory.lat0_deg", "platform.a_m", "platform.b_m", "time.rate_hz"})
    (void)given(k);
  s.duration_s = t.duration_s;
  s.gm_m3ps2 = t.gravity.gm_m3ps2;
  s.radius_m = t.trajectory.radius_m;
  s.speed_mps = t.trajectory.speed_mps;
  s.height_m = t.trajectory.height_m;
  s.lat0_rad = t.trajectory.lat0_deg * M_PI / 180.0;
  s.a_m = t.a_m;
  s.b_m = t.b_m;
  s.rate_hz = t.rate_hz;
  // accelerometer sigmas: one number (the truth generator's key) or, covariance only, 8 per axis
  auto vec8 = [&](const char* dotted, double truth_value, std::vector<double>& dst) {
    if (!given(dotted)) {
      dst.assign(8, 0.0);
      return;
    }
    if (const toml::array* arr = node(dotted)->as_array()) {
      if (arr->size() != 8)
        throw std::runtime_error(at(path, arr) + ": " + dotted +
                                 " must have 8 values (allowed: f1x f2x f3x f4x f1z f2z f3z f4z, or one number)");
      for (size_t i = 0; i < 8; ++i) {
        dst[i] = num(arr->get(i), std::string(dotted) + "[" + std::to_string(i) + "]", path);
        check_sigma(dst[i], at(path, arr->get(i)), std::string(dotted) + "[" + std::to_string(i) + "]");
      }
    } else {
      dst.assign(8, truth_value);
    }
  };
  vec8("accel.bias_sigma_mps2", t.accel.bias_sigma_mps2, s.bias_sigma_mps2);
  vec8("accel.noise_sigma_mps2", t.accel.noise_sigma_mps2, s.noise_sigma_mps2);
  (void)given("accel.scale_sigma");
  s.scale_sigma = t.accel.scale_sigma;
  // the covariance-only [initial] table
  auto get = [&](const char* dotted, double& dst) {
    if (!given(dotted)) return;
    dst = num(node(dotted), dotted, path);
    check_sigma(dst, at(path, node(dotted)), dotted);
  };
  if (const toml::node* n = node("initial.gravity_sigma_mps2")) {
    if (const toml::array* arr = n->as_array()) {
      if (arr->size() != 2)
        throw std::runtime_error(at(path, arr) + ": initial.gravity_sigma_mps2 must have 2 values (allowed: [x, z], or one number)");
      s.gravity0_sigma_x_mps2 = num(arr->get(0), "initial.gravity_sigma_mps2[0]", path);
      s.gravity0_sigma_z_mps2 = num(arr->get(1), "initial.gravity_sigma_mps2[1]", path);
    } else {
      s.gravity0_sigma_x_mps2 = s.gravity0_sigma_z_mps2 = num(n, "initial.gravity_sigma_mps2", path);
    }
    check_sigma(s.gravity0_sigma_x_mps2, at(path, n), "initial.gravity_sigma_mps2");
    check_sigma(s.gravity0_sigma_z_mps2, at(path, n), "initial.gravity_sigma_mps2");
  } else {
    s.defaulted.emplace_back("initial.gravity_sigma_mps2");
  }
  get("initial.position_sigma_m", s.pos0_sigma_m);
  get("initial.velocity_sigma_mps", s.vel0_sigma_mps);
  if (s.baro_loop) check_sigma(s.baro_bias_m, at(path, node("baro.bias_m")), "baro.bias_m");  // the linear model's sigma of the constant bias
  return s;
}

namespace {
// The shortest decimal degrees whose radians are exactly `rad` (the file's value read back).
double deg_of(double rad) {
  const double d = rad * 180.0 / M_PI;
  for (int p = 1; p <= 17; ++p) {
    char b[40];
    std::snprintf(b, sizeof b, "%.*g", p, d);
    const double c = std::strtod(b, nullptr);
    if (c * M_PI / 180.0 == rad) return c;
  }
  return d;
}
std::string nums_text(const std::vector<double>& v) {
  std::string t = "[";
  for (size_t i = 0; i < v.size(); ++i) t += (i ? ", " : "") + ggins::truth::sch::num_text(v[i]);
  return t + "]";
}
bool uniform(const std::vector<double>& v) {
  for (double x : v)
    if (x != v.front()) return false;
  return true;
}
}  // namespace

std::string cov_scenario_to_toml(const CovScenario& s, bool template_comments) {
  // the truth generator's keys through its schema (truth/scenario.hpp), set to what the
  // linear model uses; then the per-axis sigmas and the covariance-only [initial] table
  ggins::truth::Scenario t;
  if (!template_comments) {
    t.name = s.name;
    t.duration_s = s.duration_s;
    t.gravity.model = "point-mass";
    t.gravity.gm_m3ps2 = s.gm_m3ps2;
    t.trajectory.type = s.trajectory;
    t.trajectory.radius_m = s.radius_m;
    t.trajectory.speed_mps = s.speed_mps;
    t.trajectory.height_m = s.height_m;
    t.trajectory.lat0_deg = deg_of(s.lat0_rad);
    t.a_m = s.a_m;
    t.b_m = s.b_m;
    t.rate_hz = s.rate_hz;
    t.accel.bias_sigma_mps2 = s.bias_sigma_mps2.front();
    t.accel.noise_sigma_mps2 = s.noise_sigma_mps2.front();
    t.accel.scale_sigma = s.scale_sigma;
    t.navigation.gravity = "gradiometer";
    if (s.baro_loop) {
      t.navigation.baro.enable = 1;
      t.navigation.baro.period_s = s.baro_period_s;
      t.navigation.baro.omega_s2 = s.baro_omega_s2;
      for (size_t i = 0; i < 3; ++i) t.navigation.baro.poles_radps[i] = s.baro_poles_radps[i];
      t.baro.enable = true;
      t.baro.bias_m = s.baro_bias_m;
      t.baro.gm_sigma_m = s.baro_gm_sigma_m;
      t.baro.gm_tau_s = s.baro_gm_tau_s;
      t.baro.noise_sigma_m = s.baro_noise_sigma_m;
    } else {
      t.navigation.baro.enable = 0;
    }
  }
  std::string text = ggins::truth::scenario_to_toml(t, template_comments);
  if (template_comments) {
    text.replace(0, text.find('\n') + 1,
                 "# ggins covariance scenario: the keys of ggins run's (every key with its default; the\n"
                 "# covariance models north-flight, point-mass, gradiometer) and the covariance-only [initial]\n");
    return text +
           "\n# Initial-state uncertainty, one sigma (ggins covariance only)\n# [initial]\n"
           "# gravity_sigma_mps2 = 0                # m/s^2; >= 0; dG(0), one number or [x, z]\n"
           "# position_sigma_m = 0                  # m; >= 0; initial position error per axis\n"
           "# velocity_sigma_mps = 0                # m/s; >= 0; initial velocity error per axis\n";
  }
  // the eight per-axis sigmas (f1x f2x f3x f4x f1z f2z f3z f4z) when they differ
  auto per_axis = [&](const char* key, const std::vector<double>& v) {
    if (uniform(v)) return;
    const size_t a = text.find("\n[accel]\n");
    const size_t k = text.find(std::string("\n") + key + " = ", a);
    if (a == std::string::npos || k == std::string::npos) throw std::logic_error("[accel] not written");
    const size_t e = text.find('\n', k + 1);
    text.replace(k + 1, e - k - 1, std::string(key) + " = " + nums_text(v));
  };
  per_axis("bias_sigma_mps2", s.bias_sigma_mps2);
  per_axis("noise_sigma_mps2", s.noise_sigma_mps2);
  text += "\n[initial]\ngravity_sigma_mps2 = ";
  text += s.gravity0_sigma_x_mps2 == s.gravity0_sigma_z_mps2
              ? ggins::truth::sch::num_text(s.gravity0_sigma_x_mps2)
              : nums_text({s.gravity0_sigma_x_mps2, s.gravity0_sigma_z_mps2});
  text += "\nposition_sigma_m = " + ggins::truth::sch::num_text(s.pos0_sigma_m) +
          "\nvelocity_sigma_mps = " + ggins::truth::sch::num_text(s.vel0_sigma_mps) + "\n";
  return text;
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
