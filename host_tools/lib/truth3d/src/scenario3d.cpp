#include "ggins/truth3d/scenario3d.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>
#include <toml++/toml.h>

#include "ggins/truth/fdi_thresholds.hpp"
#include "ggins/truth/scenario_keys.hpp"
#include "ggins/truth/scenario_schema.hpp"
#include "ggins/truth3d/faults3d.hpp"
#include "ggins/truth3d/route3d.hpp"

extern "C" {
#include "ggins/fdi3d.h"
#include "ggins/limits.h"
#include "ggins/pf.h"
}

namespace ggins::truth3d {

struct BuiltinScenario3 {
  const char* name;
  const char* text;
};
extern const BuiltinScenario3 kBuiltinScenarios3[];
extern const int kBuiltinScenario3Count;

namespace {

namespace sch = ggins::truth::sch;
namespace keys = ggins::truth::keys;
using S = Scenario3;
using T3 = Trajectory3Params;

std::string at_line(int64_t line) { return line > 0 ? " (line " + std::to_string(line) + ")" : ""; }

bool is_route(const T3& r) { return r.type == "route"; }

// [[trajectory.waypoint]] of a route: the keys of one entry (defaults: the previous
// waypoint's height and speed, the route's rates).
sch::Key<T3> waypoint_key() {
  sch::Key<T3> k = sch::mk<T3>("waypoint", "array of tables", "", "[[trajectory.waypoint]]: lat_deg, lon_deg (required), "
                                "height_m, speed_mps, turn_rate_dps, climb_rate_mps, accel_mps2, vertical_accel_mps2",
                                "the route's waypoints after its start (route3d.hpp); height_m [previous], speed_mps "
                                "[previous leg's] (ground speed on the leg ending here), climb_rate_mps, accel_mps2, "
                                "vertical_accel_mps2 (of that leg), turn_rate_dps (of the turn at this waypoint) "
                                "[the route's]", "");
  k.read = [](T3& r, const toml::node& wn, const sch::Ctx& c, const std::string& p) {
    const toml::array* a = wn.as_array();
    if (!a) c.fail_at(&wn, p, p + " must be an array of tables ([[trajectory.waypoint]])");
    static const sch::Range lat = sch::in(-85, 85), lon = sch::in(-360, 360), h = sch::in(-1000, 1e5),
                            v = sch::in(1, 3000), pos = sch::gt(0);
    static const std::set<std::string> allowed = {"lat_deg",    "lon_deg",       "height_m",       "speed_mps",
                                                  "turn_rate_dps", "climb_rate_mps", "accel_mps2", "vertical_accel_mps2"};
    double hp = r.height_m, vp = r.speed_mps;
    for (size_t i = 0; i < a->size(); ++i) {
      const toml::table* e = (*a)[i].as_table();
      const std::string where = "trajectory.waypoint[" + std::to_string(i + 1) + "]";
      if (!e) c.fail_at(&(*a)[i], where, where + " must be a table");
      for (const auto& [kk, val] : *e)
        if (!allowed.count(std::string(kk.str())))
          c.fail_at(&val, where, "unknown key '" + where + "." + std::string(kk.str()) +
                                     "' (allowed: " + sch::detail::allowed_list(allowed) + ")");
      if (!e->contains("lat_deg") || !e->contains("lon_deg"))
        c.fail_at(&(*a)[i], where, where + ": lat_deg and lon_deg are required");
      WaypointParams q;
      q.line = static_cast<int64_t>((*a)[i].source().begin.line);
      auto num = [&](const char* key, double d, const sch::Range& rg, const char* unit) {
        const toml::node* n = e->get(key);
        return n ? sch::read_num(*n, c, where + "." + key, rg, unit) : d;
      };
      q.lat_deg = num("lat_deg", 0, lat, "deg");
      q.lon_deg = num("lon_deg", 0, lon, "deg");
      q.height_m = num("height_m", hp, h, "m");
      q.speed_mps = num("speed_mps", vp, v, "m/s");
      q.turn_rate_dps = num("turn_rate_dps", r.turn_rate_dps, pos, "deg/s");
      q.climb_rate_mps = num("climb_rate_mps", r.climb_rate_mps, pos, "m/s");
      q.accel_mps2 = num("accel_mps2", r.accel_mps2, pos, "m/s^2");
      q.vertical_accel_mps2 = num("vertical_accel_mps2", r.vertical_accel_mps2, pos, "m/s^2");
      hp = q.height_m;
      vp = q.speed_mps;
      r.waypoints.push_back(q);
    }
  };
  k.write = [](const T3& r) -> std::optional<std::string> {
    std::string s = "[";
    for (size_t i = 0; i < r.waypoints.size(); ++i) {
      const auto& q = r.waypoints[i];
      s += std::string(i ? ",\n  " : "\n  ") + "{lat_deg = " + sch::num_text(q.lat_deg) +
           ", lon_deg = " + sch::num_text(q.lon_deg) + ", height_m = " + sch::num_text(q.height_m) +
           ", speed_mps = " + sch::num_text(q.speed_mps) + ", turn_rate_dps = " + sch::num_text(q.turn_rate_dps) +
           ", climb_rate_mps = " + sch::num_text(q.climb_rate_mps) + ", accel_mps2 = " + sch::num_text(q.accel_mps2) +
           ", vertical_accel_mps2 = " + sch::num_text(q.vertical_accel_mps2) + "}";
    }
    return s + (r.waypoints.empty() ? "]" : "\n]");
  };
  return k;
}

// [[trajectory.maneuver]] of a flight: t_s, duration_s, dv_ned_mps.
sch::Key<T3> maneuver_key() {
  sch::Key<T3> k = sch::mk<T3>("maneuver", "array of tables", "", "[[trajectory.maneuver]]: t_s, duration_s (> 0), dv_ned_mps",
                                "velocity changes of a flight: start t_s [0] s, duration_s [60] s, velocity change "
                                "dv_ned_mps [[0, 0, 0]] m/s (trajectory3d.hpp)", "");
  k.read = [](T3& r, const toml::node& mn, const sch::Ctx& c, const std::string& p) {
    const toml::array* a = mn.as_array();
    if (!a) c.fail_at(&mn, p, p + " must be an array of tables ([[trajectory.maneuver]])");
    static const std::set<std::string> allowed = {"t_s", "duration_s", "dv_ned_mps"};
    for (size_t i = 0; i < a->size(); ++i) {
      const toml::table* mt = (*a)[i].as_table();
      const std::string where = "trajectory.maneuver[" + std::to_string(i + 1) + "]";
      if (!mt) c.fail_at(&(*a)[i], where, "trajectory.maneuver entries must be tables");
      for (const auto& [kk, val] : *mt)
        if (!allowed.count(std::string(kk.str())))
          c.fail_at(&val, where, "unknown key 'trajectory.maneuver." + std::string(kk.str()) +
                                     "' (allowed: " + sch::detail::allowed_list(allowed) + ")");
      ManeuverParams m;
      if (const toml::node* n = mt->get("t_s")) m.t_s = sch::read_num(*n, c, where + ".t_s", sch::in(0, 1e8), "s");
      if (const toml::node* n = mt->get("duration_s"))
        m.duration_s = sch::read_num(*n, c, where + ".duration_s", sch::in_lopen(0, 1e8), "s");
      if (const toml::node* n = mt->get("dv_ned_mps")) {
        const auto v = sch::read_nums(*n, c, where + ".dv_ned_mps", 3, 3, sch::in(-1e4, 1e4), "m/s");
        m.dv_ned_mps = {v[0], v[1], v[2]};
      }
      r.maneuvers.push_back(m);
    }
  };
  k.write = [](const T3& r) -> std::optional<std::string> {
    std::string s = "[";
    for (size_t i = 0; i < r.maneuvers.size(); ++i) {
      const auto& m = r.maneuvers[i];
      s += std::string(i ? ",\n  " : "\n  ") + "{t_s = " + sch::num_text(m.t_s) + ", duration_s = " +
           sch::num_text(m.duration_s) + ", dv_ned_mps = [" + sch::num_text(m.dv_ned_mps[0]) + ", " +
           sch::num_text(m.dv_ned_mps[1]) + ", " + sch::num_text(m.dv_ned_mps[2]) + "]}";
    }
    return s + (r.maneuvers.empty() ? "]" : "\n]");
  };
  return k;
}

// [coldatom] (coldatom3d.hpp): the cold-atom gradiometer of Phillips et al. as a sensor of the flight.
sch::Table<ColdAtom3> coldatom3_table() {
  using C = ColdAtom3;
  using G = coldatom::GradiometerParams;
  sch::Table<C> t("coldatom", "The cold-atom gradiometer (coldatom3d.hpp): two interferometers, fringe pairs.");
  t.boolean("enabled", &C::enabled, "the cold-atom gradiometer is carried (a shot per 1/rate_hz)")
      .str("gzz_map", &C::gzz_map, {"phillips-route", "phillips-route-normal", "field"},
           "the true Gamma_zz field the shots sample (Phillips et al.: EGM96 + topography, or normal only; or the "
           "scenario's own [gravity] field, on any route)")
      .str("egm96", &C::egm96, {}, "EGM96 coefficients (relative: from the scenario file's directory)")
      .default_doc("egm96", "data/egm96_to360.ascii.txt")
      .str("cache", &C::cache, {}, "cache of the route map grid (relative: from the scenario file's directory)")
      .default_doc("cache", "\"\" (none)");
  sch::Table<G> g("coldatom", "");
  g.num("rate_hz", &G::rate_hz, "Hz", sch::gt(0), "shot rate (fringe pairs)")
      .num("dz_m", &G::dz, "m", sch::gt(0), "vertical separation of the two interferometers")
      .num("T_s", &G::T, "s", sch::gt(0), "pulse separation")
      .num("n_atoms", &G::n_atoms, "1", sch::gt(0), "atoms per cloud (shot noise)")
      .num("contrast", &G::contrast, "1", sch::in_lopen(0, 1), "fringe contrast");
  sch::Key<G> phase = sch::mk<G>("phase_noise_mrad", "number", "mrad", sch::ge(0).text(), "phase noise per shot", "");
  phase.read = [](G& x, const toml::node& n, const sch::Ctx& c, const std::string& p) {
    x.phase_noise = 1e-3 * sch::read_num(n, c, p, sch::ge(0), "mrad");  // held in rad
  };
  phase.write = [](const G& x) -> std::optional<std::string> { return sch::num_text(1e3 * x.phase_noise); };
  g.custom(phase)
      .boolean("shot_noise", &G::shot_noise, "atom shot noise on the fringe")
      .num("p_fail", &G::p_fail, "1", sch::in(0, 1), "probability of a failed shot")
      .num("cloud_rw_m_rts", &G::cloud_rw, "m/sqrt(s)", sch::ge(0), "cloud position random walk")
      .num("beam_radius_m", &G::beam_radius, "m", sch::gt(0), "beam radius");
  t.lift(g, std::function<G&(C&)>([](C& c) -> G& { return c.grad; }));
  t.seed("seed", &C::seed, "seed of the shots' draws")
      .num("topo_rms_m", &C::topo_rms_m, "m", sch::in(0, 5000),
           "rms height of the synthetic terrain in the route map (phillips-route; Gamma_zz 17.0 E rms at 3000 m for "
           "150 m, proportional to it)");
  return t;
}

// [aid_pf] (coldatom3d.hpp): the filter's settings, their ranges the firmware's (limits.h,
// pf.h), so that a setting the filter would refuse is refused here with its key and line.
sch::Table<AidPf3> aid_pf3_table() {
  using A = AidPf3;
  sch::Table<A> t("aid_pf", "The cold-atom particle-filter aid (aid_pf.h) on the gradiometer's shots.");
  t.boolean("enabled", &A::enabled, "the particle-filter aid runs (needs [coldatom] and map_dir or map_from_field)")
      .str("map_dir", &A::map_dir, {}, "Gamma_zz tiles (*.gmap) for the map storage, a directory; relative from the "
                                        "scenario file's directory")
      .boolean("map_from_field", &A::map_from_field,
               "the onboard map written by the runner from the sensor's own route map ([coldatom] gzz_map "
               "phillips-route or phillips-route-normal): Gamma_zz tiles of 50 x 50 nodes centred on the route, "
               "in <out>/maps/aid_pf/, instead of map_dir; with gzz_map \"field\": Gamma_zz tiles of the "
               "scenario's own [gravity] field along the route, in height layers where it climbs (cut as the map "
               "UKF's map_from_field)")
      .num("map_step_m", &A::map_step_m, "m", sch::in(10, 5000), "map_from_field, route map: node spacing")
      .num("map_tile_spacing_m", &A::map_tile_spacing_m, "m", sch::in(100, 1e6),
           "map_from_field, route map: distance along the route between the tiles' centres")
      .num("map_spacing_deg", &A::map_spacing_deg, "deg", sch::in(0.001, 1),
           "map_from_field, gzz_map \"field\": node spacing")
      .num("map_margin_deg", &A::map_margin_deg, "deg", sch::in(0, 5),
           "map_from_field, gzz_map \"field\": margin around the route and overlap of neighbouring tiles (the "
           "cloud's spread must stay inside a tile)")
      .num("map_noise_E", &A::map_noise_E, "E", sch::in(0, 1e3),
           "map_from_field, gzz_map \"field\": database noise, one sigma, on Gamma_DD of a node")
      .seed("map_seed", &A::map_seed, "map_from_field, gzz_map \"field\": seed of the database noise")
      .integer("particles", &A::particles, "", sch::in(1, GG_PF_MAX), "particles")
      .integer("chunk", &A::chunk, "", sch::in(1, GG_PF_MAX), "particles predicted and weighed per step")
      .integer("end_chunk", &A::end_chunk, "", sch::in(1, GG_PF_MAX), "particle passes of a shot's end per step")
      .str("model", &A::model, {"rbpf", "ins", "rw"}, "process model (pf.h)")
      .str("feedback", &A::feedback, {"position", "position-velocity"}, "what the closed loop corrects")
      .seed("seed", &A::seed, "generator seed")
      .num("sigma", &A::sigma, "1", sch::in(0, GG_LIM_PF_S_MAX), "likelihood sd, signal units (0: from the sensor)")
      .num("sigma0_pos_m", &A::sigma0_pos_m, "m", sch::in(0, GG_LIM_PF_POS_SIGMA_MAX_M), "initial spread of position")
      .num("sigma0_vel_mps", &A::sigma0_vel_mps, "m/s", sch::in(0, GG_LIM_PF_VEL_SIGMA_MAX_MPS), "initial spread of velocity")
      .num("sigma0_tilt_mps2", &A::sigma0_tilt_mps2, "m/s^2", sch::in(0, GG_LIM_PF_ACC_SIGMA_MAX_MPS2), "initial spread of tilt")
      .num("sigma0_gyro_mps3", &A::sigma0_gyro_mps3, "m/s^3", sch::in(0, GG_LIM_PF_JERK_SIGMA_MAX_MPS3),
           "initial spread of g x gyro bias", -1.0,
           "g x the root sum of squares of gyro.bias_sigma_radps, the largest |gyro.bias_radps| and the largest "
           "draw.gyro_bias_radps")
      .num("sigma0_accel_mps2", &A::sigma0_accel_mps2, "m/s^2", sch::in(0, GG_LIM_PF_ACC_SIGMA_MAX_MPS2),
           "initial spread of the horizontal accelerometer error", -1.0,
           "the root sum of squares of the largest horizontal accel.bias_mps2, accel.bias_sigma_mps2 on two axes and "
           "the horizontal draw.accel_common_bias_mps2")
      .num("q_pos_m", &A::q_pos_m, "m", sch::in(0, GG_LIM_PF_POS_SIGMA_MAX_M), "process noise per shot: position")
      .num("q_vel_mps", &A::q_vel_mps, "m/s", sch::in(0, GG_LIM_PF_VEL_SIGMA_MAX_MPS),
           "process noise per shot: velocity (> 0 with model rbpf)", -1.0,
           "accel.noise_sigma_mps2 x dt x sqrt(steps per shot), at least 1e-9")
      .num("q_tilt_mps2", &A::q_tilt_mps2, "m/s^2", sch::in(0, GG_LIM_PF_ACC_SIGMA_MAX_MPS2), "process noise per shot: tilt",
           -1.0, "g x gyro.noise_sigma_radps x dt x sqrt(steps per shot)")
      .num("q_gyro_mps3", &A::q_gyro_mps3, "m/s^3", sch::in(0, GG_LIM_PF_JERK_SIGMA_MAX_MPS3),
           "process noise per shot: g x gyro bias")
      .num("q_accel_mps2", &A::q_accel_mps2, "m/s^2", sch::in(0, GG_LIM_PF_ACC_SIGMA_MAX_MPS2),
           "process noise per shot: acc error")
      .num("reg_bw", &A::reg_bw, "1", sch::in(0, 100), "regularisation bandwidth, x Silverman (the kernel h it gives must stay < 1: pf.h)")
      .num("gain", &A::gain, "1", sch::in_lopen(0, 1), "smoothing gain of the fed-back correction")
      .num("ess_frac", &A::ess_frac, "1", sch::in(0, 1), "resample when N_eff < ess_frac N")
      .num("info_min", &A::info_min, "1", sch::in_ropen(0, 1),
           "information gate: feed corrections only while the cloud has removed at least this share of the "
           "free-inertial position variance (released below half of it; model rbpf; 0: always feed)");
  integrity_keys(t, "weighed shots");
  return t;
}

std::vector<std::pair<std::string, std::optional<std::string>>> write_sensor_faults3(const SensorFaults3& p) {
  std::vector<std::pair<std::string, std::optional<std::string>>> out;
  out.emplace_back("seed", std::to_string(p.seed));
  if (p.faults.empty()) return out;
  std::string a = "[";
  for (size_t i = 0; i < p.faults.size(); ++i) {
    const SensorFault3& f = p.faults[i];
    const std::string sensor = f.sensor == kFaultGyro ? "\"gyro\"" : std::to_string(f.sensor);
    const char* axis = f.axis == 0 ? "\"x\"" : (f.axis == 1 ? "\"y\"" : "\"z\"");
    a += std::string(i ? ",\n  " : "\n  ") + "{kind = " + sch::str_text(f.kind) + ", sensor = " + sensor +
         ", axis = " + axis + ", start_s = " + sch::num_text(f.start_s) + ", duration_s = " +
         sch::num_text(f.duration_s) + ", size = " + sch::num_text(f.size) + ", prob = " + sch::num_text(f.prob) + "}";
  }
  out.emplace_back("fault", a + "\n]");
  return out;
}

sch::Schema<S> build_schema3() {
  sch::Schema<S> sc;
  sc.title = "3-D scenario (ggins run3d, covariance3d, montecarlo3d)";
  auto& secs = sc.secs;
  {
    sch::Table<S> t("", "Name and description.");
    t.custom(truth::keys::name_key<S>()).str("description", &S::description, {}, "one line shown by --list-scenarios");
    secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<T3> t("trajectory",
                     "The analytic trajectory over the rotating WGS-84 Earth (trajectory3d.hpp, route3d.hpp).");
    auto route = [](const T3& r) { return is_route(r); };
    t.str("type", &T3::type, {"flight", "circle", "tumble", "route"},
          "flight with maneuvers; circle; tumbling body; route through waypoints")
        .num("lat_deg", &T3::lat_deg, "deg", sch::in(-85, 85),
             "latitude (flight, route: start; circle: centre; tumble: the fixed point)")
        .num("lon_deg", &T3::lon_deg, "deg", sch::in(-360, 360), "longitude (as lat_deg)")
        .num("height_m", &T3::height_m, "m", sch::in(-1000, 1e5), "height above the ellipsoid (as lat_deg)")
        .vec<3>("velocity_ned_mps", &T3::velocity_ned_mps, "m/s", sch::in(-1e4, 1e4), "flight: initial velocity, NED")
        .custom(maneuver_key())
        .num("radius_m", &T3::radius_m, "m", sch::in_lopen(0, 1e7), "circle: radius")
        .num("speed_mps", &T3::speed_mps, "m/s", sch::in(-1e4, 1e4), "circle: speed; route: first leg's ground speed (>= 1)")
        .num("spin_radps", &T3::spin_radps, "rad/s", sch::in(-1e3, 1e3), "tumble: spin rate")
        .num("precession_radps", &T3::precession_radps, "rad/s", sch::in(-1e3, 1e3), "tumble: precession rate")
        .num("nutation_deg", &T3::nutation_deg, "deg", sch::in(-360, 360), "tumble: mean nutation angle")
        .num("nutation_amp_deg", &T3::nutation_amp_deg, "deg", sch::in(-360, 360), "tumble: nutation amplitude")
        .num("nutation_radps", &T3::nutation_radps, "rad/s", sch::in(-1e3, 1e3), "tumble: nutation rate")
        .num("psi0_deg", &T3::psi0_deg, "deg", sch::in(-360, 360), "tumble: initial precession angle")
        .num("phi0_deg", &T3::phi0_deg, "deg", sch::in(-360, 360), "tumble: initial spin angle")
        .num("initial_speed_mps", &T3::initial_speed_mps, "m/s", sch::in(1, 3000), "route: speed at t = 0", -1.0,
             "speed_mps")
        .only_if(route, "of type = \"route\"")
        .num("turn_rate_dps", &T3::turn_rate_dps, "deg/s", sch::gt(0), "route: turn rate (default of every waypoint)")
        .only_if(route, "of type = \"route\"")
        .num("climb_rate_mps", &T3::climb_rate_mps, "m/s", sch::gt(0), "route: climb rate (default of every waypoint)")
        .only_if(route, "of type = \"route\"")
        .num("accel_mps2", &T3::accel_mps2, "m/s^2", sch::gt(0), "route: along-track acceleration (default of every waypoint)")
        .only_if(route, "of type = \"route\"")
        .num("vertical_accel_mps2", &T3::vertical_accel_mps2, "m/s^2", sch::gt(0),
             "route: vertical acceleration (default of every waypoint)")
        .only_if(route, "of type = \"route\"")
        .custom(waypoint_key())
        .only_if(route, "of type = \"route\"");
    secs.push_back(sch::section<S>(t, &S::trajectory));
  }
  {
    sch::Table<S> t("platform", "The gradiometer: six tri-axis accelerometers, their platform.");
    t.str("kind", &S::platform, {"stabilized", "strapdown"}, "stabilized (locally level) or strapdown platform")
        .num("a_m", &S::a_m, "m", sch::in_lopen(0, 100), "half-baseline along x")
        .num("b_m", &S::b_m, "m", sch::in_lopen(0, 100), "half-baseline along y")
        .num("c_m", &S::c_m, "m", sch::in_lopen(0, 100), "half-baseline along z");
    secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<truth::GravityParams> t("gravity", "The truth gravity field.");
    using G = truth::GravityParams;
    t.str("model", &G::model, {"point-mass", "wgs84-normal", "rw-anomaly", "egm96"},
          "point mass; WGS-84 normal field; + Rubenstein & Winter point masses ([gravity.anomaly]); + the EGM96 "
          "disturbing potential ([gravity.sh]) on the lattice fast path")
        .num("gm_m3ps2", &G::gm_m3ps2, "m^3/s^2", sch::in_lopen(0, 1e21), "GM of the point-mass model");
    secs.push_back(sch::section<S>(t, &S::gravity));
  }
  {
    sch::Table<ShFieldParams> t("gravity.sh", "The spherical-harmonic disturbing field of model \"egm96\".");
    using H = ShFieldParams;
    t.str("path", &H::path, {}, "coefficient file", "<source>/data/egm96_to360.ascii.txt")
        .integer("nmax", &H::nmax, "", sch::in(2, 360), "highest degree")
        .num("lattice_spacing_m", &H::lattice_spacing_m, "m", sch::in_lopen(0, 1e7), "spacing of the fast-path lattice")
        .integer("lattice_points", &H::lattice_points, "", sch::in(2, 16), "points per lattice cell edge", true);
    secs.push_back(sch::section<S>(t, &S::sh, [](const S& s) { return s.gravity.model == "egm96"; }));
  }
  secs.push_back(sch::section<S>(keys::anomaly_table("trajectory.lat_deg", "trajectory.lon_deg"),
                                 std::function<truth::AnomalyParams&(S&)>(
                                     [](S& s) -> truth::AnomalyParams& { return s.gravity.anomaly; }),
                                 [](const S& s) { return s.gravity.model == "rw-anomaly"; }));
  secs.push_back(sch::section<S>(keys::time_table<S>()));
  secs.push_back(sch::section<S>(keys::accel_table(6, 6), &S::accel));
  {
    sch::Table<GyroErrorParams> t("gyro", "The gyro's errors (strapdown).");
    using Y = GyroErrorParams;
    t.seed("seed", &Y::seed, "seed of the random errors")
        .num("bias_sigma_radps", &Y::bias_sigma_radps, "rad/s", sch::in(0, 1), "constant random bias per axis, 1 sigma")
        .num("noise_sigma_radps", &Y::noise_sigma_radps, "rad/s", sch::in(0, 1), "white noise per sample, 1 sigma")
        .num("scale_sigma", &Y::scale_sigma, "1", sch::in(0, 0.1), "constant random scale-factor error, 1 sigma")
        .vec<3>("bias_radps", &Y::bias_radps, "rad/s", sch::in(-1, 1), "fixed bias per axis")
        .vec<3>("scale", &Y::scale, "1", sch::in(-0.1, 0.1), "fixed scale-factor error per axis");
    secs.push_back(sch::section<S>(t, &S::gyro));
  }
  secs.push_back(sch::section<S>(keys::baro_table(), &S::baro, [](const S& s) { return s.baro.enable; }));
  {
    sch::Table<S> t("navigation", "What the firmware navigates with beyond the sensors (nav3d.h).");
    t.str("gravity", &S::nav_gravity, {"gradiometer", "model"},
          "gravity from the gradiometer, or the onboard WGS-84 zonal series (J2..J8)");
    secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<InitialError3> t("initial_error",
                                "The navigation computer's initial errors, true minus estimate (the gravitation "
                                "stays the true start's).");
    using I = InitialError3;
    t.vec<3>("position_ned_m", &I::position_ned_m, "m", sch::in(-1e5, 1e5),
             "position error, local NED axes of the true start")
        .vec<3>("velocity_ned_mps", &I::velocity_ned_mps, "m/s", sch::in(-1e3, 1e3), "velocity error, NED axes")
        .vec<3>("attitude_ned_rad", &I::attitude_ned_rad, "rad", sch::in(-0.5, 0.5),
                "attitude error psi, NED axes: C_b_n(estimate) = (I - [psi x]) C_b_n(true)");
    secs.push_back(sch::section<S>(t, &S::initial_error));
  }
  {
    sch::Table<Draw3> t("draw",
                        "A Monte Carlo draw of the run's constant errors, added to the fixed values (none without "
                        "this table; a campaign sets seed to its run's seed). The filters are configured from these "
                        "values, never from the draw.");
    using D = Draw3;
    t.seed("seed", &D::seed, "seed of the draw")
        .str("bias", &D::bias, {"gaussian", "sign"},
             "the biases: gaussian (each value one sigma per axis) or sign (each value with a random sign per axis)")
        .vec<3>("accel_common_bias_mps2", &D::accel_common_bias_mps2, "m/s^2", sch::in(0, 1),
                "bias common to the six accelerometers, per body axis (added to every accel.bias_mps2 row)")
        .vec<3>("gyro_bias_radps", &D::gyro_bias_radps, "rad/s", sch::in(0, 1), "gyro bias per axis (added to gyro.bias_radps)")
        .vec<3>("position_ned_m", &D::position_ned_m, "m", sch::in(0, 1e4),
                "initial position error, 1 sigma per NED axis (added to initial_error)")
        .vec<3>("velocity_ned_mps", &D::velocity_ned_mps, "m/s", sch::in(0, 100), "initial velocity error, 1 sigma per NED axis")
        .vec<3>("attitude_ned_rad", &D::attitude_ned_rad, "rad", sch::in(0, 0.1), "initial attitude error, 1 sigma per NED axis");
    secs.push_back(sch::section<S>(t, &S::draw, [](const S& s) { return s.draw.active(); }));
    secs.back().presence_matters = true;  // a scenario without a draw writes no [draw]
  }
  secs.push_back(sch::section<S>(keys::baro_loop_table(), &S::nav_baro));
  {
    sch::Table<truth::FirmwareParams> f("firmware", "");
    keys::firmware_keys(f, "7 sigma of the parity residuals from [gyro] noise (3.84 sigma_g / h, strapdown), [accel] "
                           "errors over the baselines, + the fixed biases' + 1e-6 (scenario3d.hpp)");
    sch::Table<S> t("firmware", "The firmware's configuration (nav3d.h, fdi3d.h).");
    t.lift(f, std::function<truth::FirmwareParams&(S&)>([](S& s) -> truth::FirmwareParams& { return s.firmware; }));
    sch::Key<S> fdi = sch::mk<S>("fdi_parity_f_max_mps2", "number", "m/s^2",
                                 "0 (off) or >= " + sch::num_text(GG_FDI3D_FLOOR_MPS2),
                                 "pair-mean fault detection threshold (fdi3d.h)", "");
    fdi.read = [](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      const double v = sch::read_num(n, c, p, sch::in(0, 1e6), "m/s^2");
      if (!(v == 0 || v >= GG_FDI3D_FLOOR_MPS2))
        c.fail_at(&n, p, p + " = " + sch::value_text(n) + ": must be 0 (off) or >= " + std::to_string(GG_FDI3D_FLOOR_MPS2) +
                             " m/s^2 (the pair means' curvature differences)");
      s.fdi_parity_f_max_mps2 = v;
    };
    fdi.write = [](const S& s) -> std::optional<std::string> { return sch::num_text(s.fdi_parity_f_max_mps2); };
    t.custom(fdi).derived_unless_given(
        &S::fdi_parity_f_max_set, "7 sigma of a pair-mean difference from [accel] + the fixed biases' + 2e-12 (scenario3d.hpp)");
    secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<S> t("output", "What the run writes.");
    t.num("csv_rate_hz", &S::csv_rate_hz, "Hz", sch::in_lopen(0, 1e6), "rows per second of timeseries.csv");
    secs.push_back(sch::section<S>(t));
  }
  secs.push_back(sch::delegated_section<S>(
      "sensor_faults", "Injected sensor faults (faults3d.hpp).", keys::sensor_fault_rows(fault_instrument3d()),
      [](S& s, const toml::table& t, const sch::Ctx& c) { s.sensor_faults = parse_sensor_faults3(t, c); },
      [](const S& s) { return write_sensor_faults3(s.sensor_faults); },
      [](const S& s) { return !s.sensor_faults.faults.empty(); }));
  secs.push_back(sch::section<S>(aid_ukf_table(), &S::aid_ukf, [](const S& s) { return s.aid_ukf.enabled; }));
  secs.push_back(sch::section<S>(coldatom3_table(), &S::coldatom, [](const S& s) { return s.coldatom.enabled; }));
  secs.push_back(sch::section<S>(aid_pf3_table(), &S::aid_pf, [](const S& s) { return s.aid_pf.enabled; }));
  return sc;
}

}  // namespace

const sch::Schema<Scenario3>& scenario3_schema() {
  static const sch::Schema<Scenario3> s = build_schema3();
  return s;
}

std::string scenario3_to_toml(const Scenario3& s, bool template_comments) {
  std::string head = template_comments ? "# 3-D scenario: every key with its default (ggins run3d --print-scenario --defaults;\n"
                                         "# docs/scenario-reference.md). A commented key is derived, or belongs to\n"
                                         "# another trajectory type or model, unless given.\n"
                                       : "# scenario " + s.name + " as flown (defaults filled in, overrides applied)\n";
  return head + scenario3_schema().to_toml(s, template_comments);
}

bool Draw3::active() const {
  for (const auto* v : {&accel_common_bias_mps2, &gyro_bias_radps, &position_ned_m, &velocity_ned_mps, &attitude_ned_rad})
    for (double x : *v)
      if (x != 0) return true;
  return false;
}

DrawnErrors3 draw_errors(const Draw3& d) {
  constexpr uint64_t kStreamDraw = 71;  // distinct from the sensors', faults' and shots' streams
  DrawnErrors3 e;
  if (!d.active()) return e;
  auto bias = [&](uint64_t i, size_t j, double v) {
    if (d.bias == "sign") return truth::counter_uniform(d.seed, kStreamDraw, 0, i, j) < 0.5 ? -v : v;
    return v * truth::counter_normal(d.seed, kStreamDraw, 0, i, j);
  };
  for (size_t j = 0; j < 3; ++j) {
    e.accel_common_bias_mps2[j] = bias(0, j, d.accel_common_bias_mps2[j]);
    e.gyro_bias_radps[j] = bias(1, j, d.gyro_bias_radps[j]);
    e.position_ned_m[j] = d.position_ned_m[j] * truth::counter_normal(d.seed, kStreamDraw, 0, 2, j);
    e.velocity_ned_mps[j] = d.velocity_ned_mps[j] * truth::counter_normal(d.seed, kStreamDraw, 0, 3, j);
    e.attitude_ned_rad[j] = d.attitude_ned_rad[j] * truth::counter_normal(d.seed, kStreamDraw, 0, 4, j);
  }
  return e;
}

truth::AccelErrorParams Scenario3::accel_flown() const {
  truth::AccelErrorParams a = accel;
  const DrawnErrors3 e = draw_errors(draw);
  for (size_t i = 0; i < 6; ++i)
    for (size_t j = 0; j < 3; ++j) a.bias_mps2[i][j] += e.accel_common_bias_mps2[j];
  return a;
}

GyroErrorParams Scenario3::gyro_flown() const {
  GyroErrorParams g = gyro;
  const DrawnErrors3 e = draw_errors(draw);
  for (size_t j = 0; j < 3; ++j) g.bias_radps[j] += e.gyro_bias_radps[j];
  return g;
}

InitialError3 Scenario3::initial_error_flown() const {
  InitialError3 i = initial_error;
  const DrawnErrors3 e = draw_errors(draw);
  for (size_t j = 0; j < 3; ++j) {
    i.position_ned_m[j] += e.position_ned_m[j];
    i.velocity_ned_mps[j] += e.velocity_ned_mps[j];
    i.attitude_ned_rad[j] += e.attitude_ned_rad[j];
  }
  return i;
}

int64_t Scenario3::dt_us() const { return std::llround(1e6 / rate_hz); }
int64_t Scenario3::n_steps() const { return std::llround(duration_s * rate_hz) + 1; }
int64_t Scenario3::baro_every() const {
  const int64_t e = std::llround(rate_hz / baro.rate_hz);
  return e < 1 ? 1 : e;
}

Scenario3 parse_scenario3(const std::string& text, const std::string& fallback_name, const std::string& source) {
  const sch::Ctx c{source};
  const toml::table root = sch::parse_toml(text, source);
  Scenario3 s;
  s.source = source;
  s.text = text;
  s.name = fallback_name;
  scenario3_schema().read(s, root, c);
  if (s.name.empty() || s.name.size() > 63) c.fail("name must have 1..63 characters (give name = \"...\")");

  // relations between keys
  auto& r = s.trajectory;
  if (is_route(r)) {
    if (!(r.speed_mps >= 1))
      c.fail_key(root, "trajectory.speed_mps",
                 "trajectory.speed_mps must be >= 1 m/s for a route (the attitude follows the velocity)");
    if (r.waypoints.empty())
      c.fail_key(root, "trajectory", "trajectory.waypoint: a route needs at least one [[trajectory.waypoint]] after its start");
    try {  // the geometry and the timing: legs, turns, climbs must fit
      Route3 check(route_params(r), Attitude::Coordinated);
    } catch (const RouteError& e) {
      const size_t k = static_cast<size_t>(e.waypoint);
      const int64_t line = k >= 1 && k <= r.waypoints.size() ? r.waypoints[k - 1].line : 0;
      c.fail((k == 0 ? std::string("trajectory (the start)") : "trajectory.waypoint[" + std::to_string(k) + "]") +
             at_line(line) + ": " + e.what());
    }
  }
  // anomaly region centred on the trajectory's (start) point unless given
  if (std::isnan(s.gravity.anomaly.lat_deg)) s.gravity.anomaly.lat_deg = s.trajectory.lat_deg;
  if (std::isnan(s.gravity.anomaly.lon_deg)) s.gravity.anomaly.lon_deg = s.trajectory.lon_deg;
  if (std::isnan(s.gravity.anomaly.ref_height_m)) s.gravity.anomaly.ref_height_m = s.trajectory.height_m;
  if (std::fabs(1e6 / s.rate_hz - static_cast<double>(s.dt_us())) > 1e-9)
    c.fail_key(root, "time.rate_hz", "time.rate_hz = " + sch::num_text(s.rate_hz) +
                                         ": must give an integer number of microseconds per step");
  if (s.baro.enable && s.baro.rate_hz > s.rate_hz)
    c.fail_key(root, "baro.rate_hz", "baro.rate_hz must not exceed time.rate_hz");
  if (!(s.nav_baro.alt_max_m > s.nav_baro.alt_min_m))
    c.fail_key(root, "navigation.baro.alt_max_m", "navigation.baro: alt_max_m must be > alt_min_m");
  if (s.aid_ukf.average_s > s.aid_ukf.update_period_s)
    c.fail_key(root, "aid_ukf.average_s", "aid_ukf.average_s = " + sch::num_text(s.aid_ukf.average_s) +
                                              ": must be <= aid_ukf.update_period_s");
  // the sensor's files, relative from the scenario file's directory
  s.coldatom.egm96 = scenario_file(s.coldatom.egm96, source);
  s.coldatom.cache = scenario_file(s.coldatom.cache, source);
  if (s.aid_pf.enabled && !s.coldatom.enabled)
    c.fail_key(root, "aid_pf.enabled", "aid_pf.enabled needs [coldatom] enabled (its sensor)");
  if (s.aid_pf.enabled && s.aid_pf.map_dir.empty() && !s.aid_pf.map_from_field)
    c.fail_key(root, "aid_pf.enabled",
               "aid_pf.enabled needs aid_pf.map_dir (the onboard Gamma_zz tiles) or aid_pf.map_from_field = true");
  if (s.aid_pf.map_from_field && !s.aid_pf.map_dir.empty())
    c.fail_key(root, "aid_pf.map_from_field", "aid_pf: map_from_field and map_dir exclude each other (one map storage)");
  if (s.aid_pf.enabled && s.aid_pf.model == "rbpf" && s.aid_pf.q_vel_mps == 0.0)
    c.fail_key(root, "aid_pf.q_vel_mps", "aid_pf.q_vel_mps must be > 0 with model rbpf (it keeps the position "
                                         "prediction's covariance positive definite)");
  if (s.aid_ukf.enabled && s.aid_ukf.maps.empty() && !s.aid_ukf.map_from_field)
    c.fail_key(root, "aid_ukf.enabled",
               "aid_ukf.enabled needs aid_ukf.map (the onboard tiles) or aid_ukf.map_from_field = true");
  if (s.aid_ukf.map_from_field && !s.aid_ukf.maps.empty())
    c.fail_key(root, "aid_ukf.map_from_field", "aid_ukf: map_from_field and map exclude each other (one map storage)");
  if (s.aid_ukf.map_from_field && s.aid_ukf.map_margin_deg < 2.0 * s.aid_ukf.map_spacing_deg)
    c.fail_key(root, "aid_ukf.map_margin_deg", "aid_ukf.map_margin_deg = " + sch::num_text(s.aid_ukf.map_margin_deg) +
                                                   ": must be >= 2 map_spacing_deg (tiles overlap by it)");
  if (!s.firmware.acc_frozen_frames_set)
    s.firmware.acc_frozen_frames = truth::default_frozen_frames(s.accel.noise_sigma_mps2, s.firmware.f_max_mps2);
  if (!s.fdi_parity_f_max_set) {
    const auto& a = s.accel;
    const double sp = std::sqrt(a.bias_sigma_mps2 * a.bias_sigma_mps2 + a.noise_sigma_mps2 * a.noise_sigma_mps2 +
                                (10.0 * a.scale_sigma) * (10.0 * a.scale_sigma));
    double fixed = 0;  // the fixed biases' largest pair-mean difference
    for (size_t j = 0; j < 3; ++j)
      for (size_t q = 0; q < 3; ++q)
        for (size_t w = q + 1; w < 3; ++w)
          fixed = std::max(fixed, 0.5 * std::fabs((a.bias_mps2[q][j] + a.bias_mps2[q + 3][j]) -
                                                  (a.bias_mps2[w][j] + a.bias_mps2[w + 3][j])));
    s.fdi_parity_f_max_mps2 = 7.0 * sp + fixed + GG_FDI3D_FLOOR_MPS2;
  }
  if (!s.firmware.asym_max_set) {
    try {
      s.firmware.asym_max_ps2 = derived_asym_max_ps2(s);
    } catch (const std::runtime_error& e) {
      c.fail(e.what());
    }
  }
  return s;
}

// The derivation and its equations: scenario3d.hpp, above the declaration.
double derived_asym_max_ps2(const Scenario3& s) {
  const double h = 1.0 / s.rate_hz;                        // step, s
  const std::array<double, 3> d{s.a_m, s.b_m, s.c_m};      // half-baselines, m
  const auto& a = s.accel;
  const double sp2 = a.bias_sigma_mps2 * a.bias_sigma_mps2 + a.noise_sigma_mps2 * a.noise_sigma_mps2 +
                     (10.0 * a.scale_sigma) * (10.0 * a.scale_sigma);  // per reading, (m/s^2)^2
  const auto inv2 = [&](size_t k) { return 1.0 / (d[k] * d[k]); };
  // accelerometer part of each residual's variance, s^-4: p_x (y, z baselines), p_y (z, x), p_z (x, y), trace
  const std::array<double, 4> acc2{sp2 * (inv2(1) + inv2(2)) / 8.0, sp2 * (inv2(2) + inv2(0)) / 8.0,
                                   sp2 * (inv2(0) + inv2(1)) / 8.0, sp2 * (inv2(0) + inv2(1) + inv2(2)) / 2.0};
  // the fixed biases: the residuals they move, s^-2 (beta[i][j]: sensor i, body axis j)
  const auto& be = a.bias_mps2;
  const auto m = [&](size_t j, size_t k) { return (be[k][j] - be[k + 3][j]) / (2.0 * d[k]); };  // M[j][k]
  double fixed = std::max({std::fabs(0.5 * (m(2, 1) - m(1, 2))), std::fabs(0.5 * (m(0, 2) - m(2, 0))),
                           std::fabs(0.5 * (m(1, 0) - m(0, 1))), std::fabs(m(0, 0) + m(1, 1) + m(2, 2))});
  double s_max = std::sqrt(std::max({acc2[0], acc2[1], acc2[2], acc2[3]}));
  if (s.strapdown()) {
    const auto& g = s.gyro;
    const double sg = g.noise_sigma_radps;                                // rad/s per sample
    const double wd = std::sqrt(530.0) / 6.0 * sg / h;                    // gyro-derived w' noise, rad/s^2
    // constant rate error: random, a sigma per axis (the draw's largest axis value as one more), and fixed
    double dmax = 0, fb2 = 0;
    for (size_t j = 0; j < 3; ++j) {
      dmax = std::max(dmax, std::fabs(s.draw.gyro_bias_radps[j]));
      fb2 += g.bias_radps[j] * g.bias_radps[j];
    }
    const double eb2 = g.bias_sigma_radps * g.bias_sigma_radps + dmax * dmax;
    const double W = GG_LIM_W_MAX_RPS, fb = std::sqrt(fb2);
    const double tr2 = 16.0 * W * W * (sg * sg + eb2) + acc2[3];
    for (size_t j = 0; j < 3; ++j) s_max = std::max(s_max, std::sqrt(wd * wd + acc2[j]));
    s_max = std::max(s_max, std::sqrt(tr2));
    fixed = std::max(fixed, std::fabs(m(0, 0) + m(1, 1) + m(2, 2)) + 4.0 * W * fb + 2.0 * fb2);
  }
  const double t = 7.0 * s_max + fixed + kAsymFloorPs2;
  if (!(t <= GG_LIM_ASYM_MAX))
    throw std::runtime_error("[firmware] asym_max_ps2: the threshold derived from [gyro] noise_sigma_radps, [accel] "
                             "and the baselines, " + sch::num_text(t) + " s^-2, exceeds the firmware's limit " +
                             sch::num_text(GG_LIM_ASYM_MAX) + " (limits.h): give asym_max_ps2");
  return t;
}

std::vector<std::string> builtin_scenario3_names() {
  std::vector<std::string> v;
  for (int i = 0; i < kBuiltinScenario3Count; ++i) v.emplace_back(kBuiltinScenarios3[i].name);
  return v;
}

std::string scenario_file(const std::string& name, const std::string& source) {
  namespace fs = std::filesystem;
  if (name.empty()) return name;
  const fs::path p(name), dir = fs::path(source).parent_path();
  return (p.is_absolute() || dir.empty() ? p : dir / p).string();
}

Scenario3 with_absolute_files(Scenario3 s) {
  namespace fs = std::filesystem;
  auto abs = [](const std::string& f) { return f.empty() ? f : fs::absolute(f).lexically_normal().string(); };
  for (auto& m : s.aid_ukf.maps) m = abs(scenario_file(m, s.source));
  s.aid_pf.map_dir = abs(scenario_file(s.aid_pf.map_dir, s.source));
  s.coldatom.egm96 = abs(s.coldatom.egm96);  // resolved against the scenario's directory when read
  s.coldatom.cache = abs(s.coldatom.cache);
  s.sh.path = abs(s.sh.path);  // as read (from the working directory)
  return s;
}

Scenario3 load_scenario3(const std::string& name_or_path, const std::vector<std::string>& search_dirs) {
  namespace fs = std::filesystem;
  auto read = [](const fs::path& f) {
    std::ifstream in(f);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  auto refuse_empty = [](const Scenario3& s) {
    if (toml::parse(s.text).empty())
      throw std::runtime_error("scenario " + s.source +
                               ": sets no key (allowed: a scenario that sets at least one key; an empty file would fly "
                             "every default: start from ggins run3d --print-scenario --defaults)");
    return s;
  };
  if (fs::is_regular_file(name_or_path))
    return refuse_empty(parse_scenario3(read(name_or_path), fs::path(name_or_path).stem().string(), name_or_path));
  for (const auto& d : search_dirs) {
    const fs::path f = fs::path(d) / (name_or_path + ".toml");
    if (fs::is_regular_file(f)) return refuse_empty(parse_scenario3(read(f), name_or_path, f.string()));
  }
  for (int i = 0; i < kBuiltinScenario3Count; ++i)
    if (name_or_path == kBuiltinScenarios3[i].name)
      return parse_scenario3(kBuiltinScenarios3[i].text, name_or_path, "built-in:" + name_or_path);
  std::string known;
  for (const auto& n : builtin_scenario3_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::runtime_error("unknown scenario '" + name_or_path + "' (built-in 3-D: " + known + ")");
}

}  // namespace ggins::truth3d
