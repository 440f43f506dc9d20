#include "ggins/truth3d/scenario3d.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/truth/scenario_toml.hpp"
#include "ggins/truth3d/faults3d.hpp"
#include "ggins/truth3d/route3d.hpp"

extern "C" {
#include "ggins/fdi3d.h"
}

namespace ggins::truth3d {

struct BuiltinScenario3 {
  const char* name;
  const char* text;
};
extern const BuiltinScenario3 kBuiltinScenarios3[];
extern const int kBuiltinScenario3Count;

namespace {

namespace scenario_toml = ggins::truth::scenario_toml;

struct P {
  std::string src;
  [[noreturn]] void fail(const std::string& what) const { scenario_toml::fail(src, what); }
  void keys(const toml::table& t, const std::string& where, const std::set<std::string>& allowed) const {
    scenario_toml::check_keys(t, where, allowed, src);
  }
  const toml::table* sub(const toml::table& root, const char* name) const {
    const toml::node* n = root.get(name);
    if (!n) return nullptr;
    if (!n->is_table()) fail(std::string("'") + name + "' must be a table");
    return n->as_table();
  }
  double num(const toml::table& t, const std::string& w, const char* key, double d) const {
    return scenario_toml::get_num(t, w, key, d, src);
  }
  int64_t integer(const toml::table& t, const std::string& w, const char* key, int64_t d) const {
    return scenario_toml::get_int(t, w, key, d, src);
  }
  bool boolean(const toml::table& t, const std::string& w, const char* key, bool d) const {
    return scenario_toml::get_bool(t, w, key, d, src);
  }
  std::string str(const toml::table& t, const std::string& w, const char* key, const std::string& d) const {
    return scenario_toml::get_str(t, w, key, d, src);
  }
  template <size_t K>
  std::array<double, K> vec(const toml::table& t, const std::string& w, const char* key, std::array<double, K> d) const {
    const toml::node* n = t.get(key);
    if (!n) return d;
    const toml::array* a = n->as_array();
    if (!a || a->size() != K) fail(w + "." + key + " must be an array of " + std::to_string(K) + " numbers");
    for (size_t i = 0; i < K; ++i) {
      auto v = (*a)[i].value<double>();
      if (!v || !std::isfinite(*v)) fail(w + "." + key + " must hold finite numbers");
      d[i] = *v;
    }
    return d;
  }
  void positive(double v, const std::string& what) const {
    if (!(v > 0)) fail(what + " must be > 0");
  }
  void nonneg(double v, const std::string& what) const {
    if (!(v >= 0)) fail(what + " must be >= 0");
  }
};

int64_t line_of(const toml::node& n) { return static_cast<int64_t>(n.source().begin.line); }
std::string at_line(int64_t line) { return line > 0 ? " (line " + std::to_string(line) + ")" : ""; }

// route keys of [trajectory] and its [[trajectory.waypoint]] entries
void parse_route(const P& p, const toml::table& t, Trajectory3Params& r) {
  const std::string w = "trajectory";
  const bool route = r.type == "route";
  for (const char* k : {"waypoint", "initial_speed_mps", "turn_rate_dps", "climb_rate_mps", "accel_mps2",
                        "vertical_accel_mps2"})
    if (!route && t.contains(k))
      p.fail(std::string("trajectory.") + k + at_line(line_of(*t.get(k))) + " is a key of type = \"route\"");
  if (!route) return;
  r.initial_speed_mps = p.num(t, w, "initial_speed_mps", r.initial_speed_mps);
  r.turn_rate_dps = p.num(t, w, "turn_rate_dps", r.turn_rate_dps);
  r.climb_rate_mps = p.num(t, w, "climb_rate_mps", r.climb_rate_mps);
  r.accel_mps2 = p.num(t, w, "accel_mps2", r.accel_mps2);
  r.vertical_accel_mps2 = p.num(t, w, "vertical_accel_mps2", r.vertical_accel_mps2);
  if (!(r.speed_mps >= 1)) p.fail("trajectory.speed_mps must be >= 1 m/s for a route (the attitude follows the velocity)");
  if (t.contains("initial_speed_mps") && !(r.initial_speed_mps >= 1))
    p.fail("trajectory.initial_speed_mps" + at_line(line_of(*t.get("initial_speed_mps"))) + " must be >= 1 m/s");
  p.positive(r.turn_rate_dps, "trajectory.turn_rate_dps");
  p.positive(r.climb_rate_mps, "trajectory.climb_rate_mps");
  p.positive(r.accel_mps2, "trajectory.accel_mps2");
  p.positive(r.vertical_accel_mps2, "trajectory.vertical_accel_mps2");
  const toml::node* wn = t.get("waypoint");
  if (!wn) p.fail("trajectory.waypoint: a route needs at least one [[trajectory.waypoint]] after its start");
  const toml::array* a = wn->as_array();
  if (!a) p.fail("trajectory.waypoint" + at_line(line_of(*wn)) + " must be an array of tables ([[trajectory.waypoint]])");
  double h = r.height_m, v = r.speed_mps;
  for (size_t i = 0; i < a->size(); ++i) {
    const toml::table* e = (*a)[i].as_table();
    const std::string where = "trajectory.waypoint[" + std::to_string(i + 1) + "]";
    const int64_t line = line_of((*a)[i]);
    const std::string loc = where + at_line(line);
    if (!e) p.fail(loc + " must be a table");
    for (const auto& [k, val] : *e) {
      (void)val;
      static const std::set<std::string> allowed = {"lat_deg",       "lon_deg",        "height_m",
                                                    "speed_mps",     "turn_rate_dps",  "climb_rate_mps",
                                                    "accel_mps2",    "vertical_accel_mps2"};
      if (!allowed.count(std::string(k.str()))) {
        std::string list;
        for (const auto& x : allowed) list += (list.empty() ? "" : ", ") + x;
        p.fail("unknown key '" + where + "." + std::string(k.str()) + "'" + at_line(line) + " (allowed: " + list + ")");
      }
    }
    if (!e->contains("lat_deg") || !e->contains("lon_deg")) p.fail(loc + ": lat_deg and lon_deg are required");
    WaypointParams q;
    q.line = line;
    q.lat_deg = p.num(*e, loc, "lat_deg", 0);
    q.lon_deg = p.num(*e, loc, "lon_deg", 0);
    q.height_m = p.num(*e, loc, "height_m", h);
    q.speed_mps = p.num(*e, loc, "speed_mps", v);
    q.turn_rate_dps = p.num(*e, loc, "turn_rate_dps", r.turn_rate_dps);
    q.climb_rate_mps = p.num(*e, loc, "climb_rate_mps", r.climb_rate_mps);
    q.accel_mps2 = p.num(*e, loc, "accel_mps2", r.accel_mps2);
    q.vertical_accel_mps2 = p.num(*e, loc, "vertical_accel_mps2", r.vertical_accel_mps2);
    if (std::fabs(q.lat_deg) > 85) p.fail(loc + ".lat_deg must be within +-85");
    if (!(std::fabs(q.lon_deg) <= 360)) p.fail(loc + ".lon_deg must be within +-360");
    if (q.height_m < -1000 || q.height_m > 1e5) p.fail(loc + ".height_m must be in [-1000, 1e5]");
    if (!(q.speed_mps >= 1)) p.fail(loc + ".speed_mps must be >= 1 m/s (the attitude follows the velocity)");
    if (!(q.speed_mps <= 3000)) p.fail(loc + ".speed_mps must be <= 3000 m/s");
    p.positive(q.turn_rate_dps, loc + ".turn_rate_dps");
    p.positive(q.climb_rate_mps, loc + ".climb_rate_mps");
    p.positive(q.accel_mps2, loc + ".accel_mps2");
    p.positive(q.vertical_accel_mps2, loc + ".vertical_accel_mps2");
    h = q.height_m;
    v = q.speed_mps;
    r.waypoints.push_back(q);
  }
  // the geometry and the timing: legs, turns, climbs must fit
  try {
    Route3 check(route_params(r), Attitude::Coordinated);
  } catch (const RouteError& e) {
    const size_t k = static_cast<size_t>(e.waypoint);
    const int64_t line = k >= 1 && k <= r.waypoints.size() ? r.waypoints[k - 1].line : 0;
    p.fail((k == 0 ? std::string("trajectory (the start)") : "trajectory.waypoint[" + std::to_string(k) + "]") +
           at_line(line) + ": " + e.what());
  }
}

}  // namespace

int64_t Scenario3::dt_us() const { return std::llround(1e6 / rate_hz); }
int64_t Scenario3::n_steps() const { return std::llround(duration_s * rate_hz) + 1; }
int64_t Scenario3::baro_every() const {
  const int64_t e = std::llround(rate_hz / baro.rate_hz);
  return e < 1 ? 1 : e;
}

Scenario3 parse_scenario3(const std::string& text, const std::string& fallback_name, const std::string& source) {
  P p{source};
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << e.description() << " at line " << e.source().begin.line;
    p.fail(os.str());
  }
  Scenario3 s;
  s.source = source;
  s.text = text;
  s.gravity.model = "wgs84-normal";
  p.keys(root, "", {"name", "description", "trajectory", "platform", "gravity", "time", "accel", "gyro", "baro",
                    "navigation", "firmware", "output", "sensor_faults",
                    "aid_ukf", "coldatom", "aid_pf"});  // the aiding sources (aids3d.hpp, coldatom3d.hpp)
  s.name = p.str(root, "", "name", fallback_name);
  s.description = p.str(root, "", "description", "");
  if (const auto* t = p.sub(root, "trajectory")) {
    const std::string w = "trajectory";
    p.keys(*t, w, {"type", "lat_deg", "lon_deg", "height_m", "velocity_ned_mps", "maneuver", "radius_m", "speed_mps",
                   "spin_radps", "precession_radps", "nutation_deg", "nutation_amp_deg", "nutation_radps", "psi0_deg",
                   "phi0_deg", "waypoint", "initial_speed_mps", "turn_rate_dps", "climb_rate_mps", "accel_mps2",
                   "vertical_accel_mps2"});
    auto& r = s.trajectory;
    r.type = p.str(*t, w, "type", r.type);
    if (r.type != "flight" && r.type != "circle" && r.type != "tumble" && r.type != "route")
      p.fail("trajectory.type must be \"flight\", \"circle\", \"tumble\" or \"route\"");
    r.lat_deg = p.num(*t, w, "lat_deg", r.lat_deg);
    r.lon_deg = p.num(*t, w, "lon_deg", r.lon_deg);
    r.height_m = p.num(*t, w, "height_m", r.height_m);
    if (std::fabs(r.lat_deg) > 85) p.fail("trajectory.lat_deg must be within +-85");
    if (r.height_m < -1000 || r.height_m > 1e5) p.fail("trajectory.height_m must be in [-1000, 1e5]");
    r.velocity_ned_mps = p.vec<3>(*t, w, "velocity_ned_mps", r.velocity_ned_mps);
    if (const toml::node* mn = t->get("maneuver")) {
      const toml::array* a = mn->as_array();
      if (!a) p.fail("trajectory.maneuver must be an array of tables ([[trajectory.maneuver]])");
      for (const auto& e : *a) {
        const toml::table* mt = e.as_table();
        if (!mt) p.fail("trajectory.maneuver entries must be tables");
        p.keys(*mt, "trajectory.maneuver", {"t_s", "duration_s", "dv_ned_mps"});
        ManeuverParams m;
        m.t_s = p.num(*mt, "trajectory.maneuver", "t_s", m.t_s);
        m.duration_s = p.num(*mt, "trajectory.maneuver", "duration_s", m.duration_s);
        p.positive(m.duration_s, "trajectory.maneuver.duration_s");
        m.dv_ned_mps = p.vec<3>(*mt, "trajectory.maneuver", "dv_ned_mps", m.dv_ned_mps);
        r.maneuvers.push_back(m);
      }
    }
    r.radius_m = p.num(*t, w, "radius_m", r.radius_m);
    r.speed_mps = p.num(*t, w, "speed_mps", r.speed_mps);
    parse_route(p, *t, r);
    p.positive(r.radius_m, "trajectory.radius_m");
    r.spin_radps = p.num(*t, w, "spin_radps", r.spin_radps);
    r.precession_radps = p.num(*t, w, "precession_radps", r.precession_radps);
    r.nutation_deg = p.num(*t, w, "nutation_deg", r.nutation_deg);
    r.nutation_amp_deg = p.num(*t, w, "nutation_amp_deg", r.nutation_amp_deg);
    r.nutation_radps = p.num(*t, w, "nutation_radps", r.nutation_radps);
    r.psi0_deg = p.num(*t, w, "psi0_deg", r.psi0_deg);
    r.phi0_deg = p.num(*t, w, "phi0_deg", r.phi0_deg);
  }
  if (const auto* t = p.sub(root, "platform")) {
    p.keys(*t, "platform", {"kind", "a_m", "b_m", "c_m"});
    s.platform = p.str(*t, "platform", "kind", s.platform);
    if (s.platform != "stabilized" && s.platform != "strapdown")
      p.fail("platform.kind must be \"stabilized\" or \"strapdown\"");
    s.a_m = p.num(*t, "platform", "a_m", s.a_m);
    s.b_m = p.num(*t, "platform", "b_m", s.b_m);
    s.c_m = p.num(*t, "platform", "c_m", s.c_m);
    p.positive(s.a_m, "platform.a_m");
    p.positive(s.b_m, "platform.b_m");
    p.positive(s.c_m, "platform.c_m");
  }
  if (const auto* t = p.sub(root, "gravity")) {
    p.keys(*t, "gravity", {"model", "gm_m3ps2", "anomaly", "sh"});
    s.gravity.model = p.str(*t, "gravity", "model", s.gravity.model);
    if (s.gravity.model != "point-mass" && s.gravity.model != "wgs84-normal" && s.gravity.model != "rw-anomaly" &&
        s.gravity.model != "egm96")
      p.fail("gravity.model must be \"point-mass\", \"wgs84-normal\", \"rw-anomaly\" or \"egm96\"");
    if (const auto* h = p.sub(*t, "sh")) {
      const std::string w = "gravity.sh";
      p.keys(*h, w, {"path", "nmax", "lattice_spacing_m", "lattice_points"});
      s.sh.path = p.str(*h, w, "path", s.sh.path);
      s.sh.nmax = p.integer(*h, w, "nmax", s.sh.nmax);
      s.sh.lattice_spacing_m = p.num(*h, w, "lattice_spacing_m", s.sh.lattice_spacing_m);
      s.sh.lattice_points = p.integer(*h, w, "lattice_points", s.sh.lattice_points);
      if (s.sh.nmax < 2 || s.sh.nmax > 360) p.fail("gravity.sh.nmax must be in [2, 360]");
      p.positive(s.sh.lattice_spacing_m, "gravity.sh.lattice_spacing_m");
      if (s.sh.lattice_points < 2 || s.sh.lattice_points > 16 || s.sh.lattice_points % 2)
        p.fail("gravity.sh.lattice_points must be even, 2..16");
    }
    s.gravity.gm_m3ps2 = p.num(*t, "gravity", "gm_m3ps2", s.gravity.gm_m3ps2);
    if (const auto* a = p.sub(*t, "anomaly")) {
      const std::string w = "gravity.anomaly";
      p.keys(*a, w, {"seed", "lat_deg", "lon_deg", "half_size_m", "ref_height_m", "rms_arcsec", "corr_length_m",
                     "ewald_sigma_m", "lattice_spacing_m", "lattice_points"});
      auto& g = s.gravity.anomaly;
      g.seed = static_cast<uint64_t>(p.integer(*a, w, "seed", static_cast<int64_t>(g.seed)));
      g.lat_deg = p.num(*a, w, "lat_deg", g.lat_deg);
      g.lon_deg = p.num(*a, w, "lon_deg", NAN);
      g.half_size_m = p.num(*a, w, "half_size_m", g.half_size_m);
      g.ref_height_m = p.num(*a, w, "ref_height_m", g.ref_height_m);
      g.rms_arcsec = p.num(*a, w, "rms_arcsec", g.rms_arcsec);
      g.corr_length_m = p.num(*a, w, "corr_length_m", g.corr_length_m);
      g.ewald_sigma_m = p.num(*a, w, "ewald_sigma_m", g.ewald_sigma_m);
      g.lattice_spacing_m = p.num(*a, w, "lattice_spacing_m", g.lattice_spacing_m);
      g.lattice_points = p.integer(*a, w, "lattice_points", g.lattice_points);
    } else {
      s.gravity.anomaly.lon_deg = NAN;
    }
  } else {
    s.gravity.anomaly.lon_deg = NAN;
  }
  // anomaly region centred on the trajectory's (start) point unless given
  if (std::isnan(s.gravity.anomaly.lat_deg)) s.gravity.anomaly.lat_deg = s.trajectory.lat_deg;
  if (std::isnan(s.gravity.anomaly.lon_deg)) s.gravity.anomaly.lon_deg = s.trajectory.lon_deg;
  if (std::isnan(s.gravity.anomaly.ref_height_m)) s.gravity.anomaly.ref_height_m = s.trajectory.height_m;
  if (const auto* t = p.sub(root, "time")) {
    p.keys(*t, "time", {"duration_s", "rate_hz"});
    s.duration_s = p.num(*t, "time", "duration_s", s.duration_s);
    s.rate_hz = p.num(*t, "time", "rate_hz", s.rate_hz);
  }
  p.positive(s.duration_s, "time.duration_s");
  p.positive(s.rate_hz, "time.rate_hz");
  if (std::fabs(1e6 / s.rate_hz - static_cast<double>(s.dt_us())) > 1e-9)
    p.fail("time.rate_hz must give an integer number of microseconds per step");
  if (const auto* t = p.sub(root, "accel")) {
    const std::string w = "accel";
    p.keys(*t, w, {"seed", "bias_sigma_mps2", "noise_sigma_mps2", "scale_sigma", "bias_mps2"});
    s.accel.seed = static_cast<uint64_t>(p.integer(*t, w, "seed", 1));
    s.accel.bias_sigma_mps2 = p.num(*t, w, "bias_sigma_mps2", 0);
    s.accel.noise_sigma_mps2 = p.num(*t, w, "noise_sigma_mps2", 0);
    s.accel.scale_sigma = p.num(*t, w, "scale_sigma", 0);
    p.nonneg(s.accel.bias_sigma_mps2, "accel.bias_sigma_mps2");
    p.nonneg(s.accel.noise_sigma_mps2, "accel.noise_sigma_mps2");
    p.nonneg(s.accel.scale_sigma, "accel.scale_sigma");
    if (const toml::node* n = t->get("bias_mps2")) {
      const toml::array* a = n->as_array();
      if (!a || a->size() != 6) p.fail("accel.bias_mps2 must be 6 arrays of 3 numbers");
      for (size_t i = 0; i < 6; ++i) {
        const toml::array* r = (*a)[i].as_array();
        if (!r || r->size() != 3) p.fail("accel.bias_mps2 must be 6 arrays of 3 numbers");
        for (size_t j = 0; j < 3; ++j) {
          auto v = (*r)[j].value<double>();
          if (!v || !std::isfinite(*v)) p.fail("accel.bias_mps2 must hold finite numbers");
          s.accel.bias_mps2[i][j] = *v;
        }
      }
    }
  }
  if (const auto* t = p.sub(root, "gyro")) {
    const std::string w = "gyro";
    p.keys(*t, w, {"seed", "bias_sigma_radps", "noise_sigma_radps", "scale_sigma", "bias_radps", "scale"});
    s.gyro.seed = static_cast<uint64_t>(p.integer(*t, w, "seed", static_cast<int64_t>(s.gyro.seed)));
    s.gyro.bias_sigma_radps = p.num(*t, w, "bias_sigma_radps", 0);
    s.gyro.noise_sigma_radps = p.num(*t, w, "noise_sigma_radps", 0);
    s.gyro.scale_sigma = p.num(*t, w, "scale_sigma", 0);
    p.nonneg(s.gyro.bias_sigma_radps, "gyro.bias_sigma_radps");
    p.nonneg(s.gyro.noise_sigma_radps, "gyro.noise_sigma_radps");
    p.nonneg(s.gyro.scale_sigma, "gyro.scale_sigma");
    s.gyro.bias_radps = p.vec<3>(*t, w, "bias_radps", s.gyro.bias_radps);
    s.gyro.scale = p.vec<3>(*t, w, "scale", s.gyro.scale);
  }
  if (const auto* t = p.sub(root, "baro")) {
    const std::string w = "baro";
    p.keys(*t, w, {"enable", "seed", "rate_hz", "bias_m", "gm_sigma_m", "gm_tau_s", "noise_sigma_m"});
    s.baro.enable = p.boolean(*t, w, "enable", true);
    s.baro.seed = static_cast<uint64_t>(p.integer(*t, w, "seed", 1));
    s.baro.rate_hz = p.num(*t, w, "rate_hz", s.baro.rate_hz);
    s.baro.bias_m = p.num(*t, w, "bias_m", 0);
    s.baro.gm_sigma_m = p.num(*t, w, "gm_sigma_m", 0);
    s.baro.gm_tau_s = p.num(*t, w, "gm_tau_s", s.baro.gm_tau_s);
    s.baro.noise_sigma_m = p.num(*t, w, "noise_sigma_m", 0);
    p.positive(s.baro.rate_hz, "baro.rate_hz");
    p.positive(s.baro.gm_tau_s, "baro.gm_tau_s");
    p.nonneg(s.baro.gm_sigma_m, "baro.gm_sigma_m");
    p.nonneg(s.baro.noise_sigma_m, "baro.noise_sigma_m");
    if (s.baro.rate_hz > s.rate_hz) p.fail("baro.rate_hz must not exceed time.rate_hz");
  }
  if (const auto* t = p.sub(root, "navigation")) {
    p.keys(*t, "navigation", {"gravity", "baro"});
    s.nav_gravity = p.str(*t, "navigation", "gravity", s.nav_gravity);
    if (s.nav_gravity != "gradiometer" && s.nav_gravity != "model")
      p.fail("navigation.gravity must be \"gradiometer\" or \"model\"");
    if (const auto* b = p.sub(*t, "baro")) {
      const std::string w = "navigation.baro";
      p.keys(*b, w, {"enable", "poles_radps", "period_s", "omega_s2", "max_age_s", "coast_s", "alt_min_m",
                     "alt_max_m", "gate_m", "max_rejects"});
      auto& l = s.nav_baro;
      if (b->get("enable")) l.enable = p.boolean(*b, w, "enable", false) ? 1 : 0;
      l.poles_radps = p.vec<3>(*b, w, "poles_radps", l.poles_radps);
      l.period_s = p.num(*b, w, "period_s", l.period_s);
      l.omega_s2 = p.num(*b, w, "omega_s2", l.omega_s2);
      l.max_age_s = p.num(*b, w, "max_age_s", l.max_age_s);
      l.coast_s = p.num(*b, w, "coast_s", l.coast_s);
      l.alt_min_m = p.num(*b, w, "alt_min_m", l.alt_min_m);
      l.alt_max_m = p.num(*b, w, "alt_max_m", l.alt_max_m);
      l.gate_m = p.num(*b, w, "gate_m", l.gate_m);
      l.max_rejects = p.integer(*b, w, "max_rejects", l.max_rejects);
    }
  }
  bool fdi_set = false;
  if (const auto* t = p.sub(root, "firmware")) {
    p.keys(*t, "firmware", {"f_max_mps2", "asym_max_ps2", "dt_tol_us", "fdi_parity_f_max_mps2"});
    s.firmware.f_max_mps2 = p.num(*t, "firmware", "f_max_mps2", s.firmware.f_max_mps2);
    s.firmware.asym_max_ps2 = p.num(*t, "firmware", "asym_max_ps2", s.firmware.asym_max_ps2);
    s.firmware.dt_tol_us = p.integer(*t, "firmware", "dt_tol_us", s.firmware.dt_tol_us);
    if (t->contains("fdi_parity_f_max_mps2")) {
      fdi_set = true;
      s.fdi_parity_f_max_mps2 = p.num(*t, "firmware", "fdi_parity_f_max_mps2", 0);
      if (!(s.fdi_parity_f_max_mps2 == 0 || s.fdi_parity_f_max_mps2 >= GG_FDI3D_FLOOR_MPS2))
        p.fail("firmware.fdi_parity_f_max_mps2 must be 0 (off) or >= " + std::to_string(GG_FDI3D_FLOOR_MPS2) +
               " m/s^2 (the pair means' curvature differences)");
    }
  }
  if (!fdi_set) {
    const auto& a = s.accel;
    const double sp = std::sqrt(a.bias_sigma_mps2 * a.bias_sigma_mps2 + a.noise_sigma_mps2 * a.noise_sigma_mps2 +
                                (10.0 * a.scale_sigma) * (10.0 * a.scale_sigma));
    double fixed = 0;  // the fixed biases' largest pair-mean difference
    for (size_t j = 0; j < 3; ++j)
      for (size_t q = 0; q < 3; ++q)
        for (size_t r = q + 1; r < 3; ++r)
          fixed = std::max(fixed, 0.5 * std::fabs((a.bias_mps2[q][j] + a.bias_mps2[q + 3][j]) -
                                                  (a.bias_mps2[r][j] + a.bias_mps2[r + 3][j])));
    s.fdi_parity_f_max_mps2 = 7.0 * sp + fixed + GG_FDI3D_FLOOR_MPS2;
  }
  if (const auto* t = p.sub(root, "sensor_faults")) s.sensor_faults = parse_sensor_faults3(*t, source);
  s.aid_ukf = parse_aid_ukf(root["aid_ukf"].as_table(), source);
  s.coldatom = parse_coldatom3(root["coldatom"].as_table(), source);
  s.aid_pf = parse_aid_pf3(root["aid_pf"].as_table(), source);
  if (s.aid_pf.enabled && !s.coldatom.enabled) scenario_toml::fail(source, "aid_pf.enabled needs [coldatom] enabled (its sensor)");
  if (const auto* t = p.sub(root, "output")) {
    p.keys(*t, "output", {"csv_rate_hz"});
    s.csv_rate_hz = p.num(*t, "output", "csv_rate_hz", s.csv_rate_hz);
    p.positive(s.csv_rate_hz, "output.csv_rate_hz");
  }
  return s;
}

std::vector<std::string> builtin_scenario3_names() {
  std::vector<std::string> v;
  for (int i = 0; i < kBuiltinScenario3Count; ++i) v.emplace_back(kBuiltinScenarios3[i].name);
  return v;
}

Scenario3 load_scenario3(const std::string& name_or_path, const std::vector<std::string>& search_dirs) {
  namespace fs = std::filesystem;
  auto read = [](const fs::path& f) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  if (fs::is_regular_file(name_or_path))
    return parse_scenario3(read(name_or_path), fs::path(name_or_path).stem().string(), name_or_path);
  for (const auto& d : search_dirs) {
    const fs::path f = fs::path(d) / (name_or_path + ".toml");
    if (fs::is_regular_file(f)) return parse_scenario3(read(f), name_or_path, f.string());
  }
  for (int i = 0; i < kBuiltinScenario3Count; ++i)
    if (name_or_path == kBuiltinScenarios3[i].name)
      return parse_scenario3(kBuiltinScenarios3[i].text, name_or_path, "built-in:" + name_or_path);
  std::string known;
  for (const auto& n : builtin_scenario3_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::runtime_error("unknown scenario '" + name_or_path + "' (built-in 3-D: " + known + ")");
}

}  // namespace ggins::truth3d
