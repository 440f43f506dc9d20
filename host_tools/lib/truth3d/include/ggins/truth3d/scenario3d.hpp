// 3-D scenario (TOML, toml++): a flight or a tumbling body over the rotating
// WGS-84 Earth, the sensor errors, and what the firmware (nav3d.h) is
// configured with. Built-ins: scenarios/3d-*.toml (compiled in). Unknown keys
// and out-of-range values are errors.
//
// Every table and key (type, unit, default, allowed range, meaning): the scenario schema
// (truth/scenario_schema.hpp, built in scenario3d.cpp from these structs' initialisers) and
// docs/scenario-reference.md generated from it (ggins scenario-reference).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "ggins/truth/scenario.hpp"
#include "ggins/truth/sensors.hpp"
#include "ggins/truth3d/aids3d.hpp"
#include "ggins/truth3d/coldatom3d.hpp"
#include "ggins/truth3d/faults3d.hpp"

namespace ggins::truth3d {

struct ManeuverParams {
  double t_s = 0, duration_s = 60;
  std::array<double, 3> dv_ned_mps{0, 0, 0};
};

struct WaypointParams {  // [[trajectory.waypoint]] of a route (route3d.hpp)
  double lat_deg = 0, lon_deg = 0, height_m = 0;
  double speed_mps = 0, turn_rate_dps = 0, climb_rate_mps = 0, accel_mps2 = 0, vertical_accel_mps2 = 0;
  int64_t line = 0;  // line of the entry in the scenario text (0: unknown)
};

struct Trajectory3Params {
  std::string type = "flight";
  // route: waypoint 0 = (lat_deg, lon_deg, height_m); defaults of the waypoints' keys
  std::vector<WaypointParams> waypoints;
  double initial_speed_mps = -1;  // < 0: speed_mps
  double turn_rate_dps = 3, climb_rate_mps = 5, accel_mps2 = 0.5, vertical_accel_mps2 = 0.5;
  double lat_deg = 45, lon_deg = 10, height_m = 5000;
  std::array<double, 3> velocity_ned_mps{200, 0, 0};
  std::vector<ManeuverParams> maneuvers;
  double radius_m = 5000, speed_mps = 200;
  double spin_radps = 1, precession_radps = 0.2, nutation_deg = 30, nutation_amp_deg = 5, nutation_radps = 0.05,
         psi0_deg = 0, phi0_deg = 0;
};

using GyroErrorParams = truth::GyroErrorParams;  // the gyro error model's parameters (truth/sensors.hpp)

struct ShFieldParams {  // [gravity.sh], model = "egm96"
  std::string path;      // empty: GGINS_DATA_DIR/egm96_to360.ascii.txt
  int64_t nmax = 360;
  double lattice_spacing_m = 2500;
  int64_t lattice_points = 8;
};

// The 3-D default field: the WGS-84 normal field; an anomaly region centred on the
// trajectory's start unless given (NaN: resolved by parse_scenario3).
inline truth::GravityParams default_gravity3() {
  truth::GravityParams g;
  g.model = "wgs84-normal";
  g.anomaly.lon_deg = NAN;
  return g;
}

// [initial_error]: the navigation computer's initial state minus nothing but these errors
// (x = true - estimate, the aids' convention): position and velocity in the local NED
// frame of the true start, attitude as the small rotation psi (NED) with
// C_b_n(estimate) = (I - [psi x]) C_b_n(true). The initial gravitation stays the true
// value at the true start (surveyed, as Welker et al.).
struct InitialError3 {
  std::array<double, 3> position_ned_m{0, 0, 0};
  std::array<double, 3> velocity_ned_mps{0, 0, 0};
  std::array<double, 3> attitude_ned_rad{0, 0, 0};
};

// [draw]: a Monte Carlo draw of the run's constant errors, added to the fixed values:
// a bias common to the six accelerometers (added to every row of [accel] bias_mps2; a
// bias common to all six is no gradient error), the gyro bias (added to [gyro]
// bias_radps) and the initial errors (added to [initial_error]). One draw per seed
// (a campaign sets draw.seed to its run's seed), from counter_normal / counter_uniform
// stream 71 (truth/sensors.hpp): element (0, 0, j) the accelerometer bias of axis j,
// (0, 1, j) the gyro bias, (0, 2..4, j) position, velocity, attitude. Biases: "gaussian"
// (each value one sigma per axis) or "sign" (each value with a random sign per axis, as
// Gao et al.'s Table 1 states the biases as magnitudes); initial errors are gaussian,
// each value one sigma. The filters are configured from the values (sigmas), never from
// the draw.
struct Draw3 {
  uint64_t seed = 1;
  std::string bias = "gaussian";  // or "sign"
  std::array<double, 3> accel_common_bias_mps2{0, 0, 0};
  std::array<double, 3> gyro_bias_radps{0, 0, 0};
  std::array<double, 3> position_ned_m{0, 0, 0};
  std::array<double, 3> velocity_ned_mps{0, 0, 0};
  std::array<double, 3> attitude_ned_rad{0, 0, 0};
  bool active() const;  // any value non-zero
};

// One draw of [draw] (all zero when it is inactive).
struct DrawnErrors3 {
  std::array<double, 3> accel_common_bias_mps2{0, 0, 0};
  std::array<double, 3> gyro_bias_radps{0, 0, 0};
  std::array<double, 3> position_ned_m{0, 0, 0};
  std::array<double, 3> velocity_ned_mps{0, 0, 0};
  std::array<double, 3> attitude_ned_rad{0, 0, 0};
};
DrawnErrors3 draw_errors(const Draw3& d);

struct Scenario3 {
  std::string name, description, source, text;
  Trajectory3Params trajectory;
  std::string platform = "strapdown";  // or "stabilized"
  double a_m = 0.5, b_m = 0.5, c_m = 0.5;
  truth::GravityParams gravity = default_gravity3();
  ShFieldParams sh;
  double duration_s = 3600, rate_hz = 100;
  truth::AccelErrorParams accel;
  GyroErrorParams gyro;
  truth::BaroParams baro;  // enable, seed, rate_hz, bias_m, gm_sigma_m, gm_tau_s, noise_sigma_m
  std::string nav_gravity = "gradiometer";
  InitialError3 initial_error;     // [initial_error]
  Draw3 draw;                      // [draw]: the run's Monte Carlo draw, added to the fixed errors
  truth::BaroLoopParams nav_baro;
  truth::FirmwareParams firmware;  // f_max_mps2, asym_max_ps2, dt_tol_us
  // [firmware] fdi_parity_f_max_mps2: the pair-mean fault detection threshold
  // (fdi3d.h; 0 = off). Default, derived from [accel]: a pair-mean difference
  // (f_p + f_p' - f_q - f_q')/2 of four readings has sigma_p = sqrt(sigma_b^2 +
  // sigma_n^2 + (10 m/s^2 sigma_s)^2); threshold 7 sigma_p (a false alarm once in
  // ~4e11 tests) + the fixed biases' largest pair-mean difference + the
  // curvature floor GG_FDI3D_FLOOR_MPS2 (2e-12 m/s^2). A 1e-8 m/s^2 bias on one
  // reading moves its pair mean by 5e-9: flagged at once on perfect sensors.
  double fdi_parity_f_max_mps2 = 0;
  bool fdi_parity_f_max_set = false;  // given in the file (else derived, and not written back)
  double csv_rate_hz = 1;
  SensorFaults3 sensor_faults;  // [sensor_faults] (faults3d.hpp)
  AidUkf3 aid_ukf;              // [aid_ukf]: the gradient-map aid (aids3d.hpp)
  ColdAtom3 coldatom;           // [coldatom]: the cold-atom gradiometer (coldatom3d.hpp)
  AidPf3 aid_pf;                // [aid_pf]: the cold-atom particle-filter aid (coldatom3d.hpp)

  // the sensor errors and initial errors as flown: the fixed values plus the draw
  truth::AccelErrorParams accel_flown() const;
  GyroErrorParams gyro_flown() const;
  InitialError3 initial_error_flown() const;

  bool strapdown() const { return platform == "strapdown"; }
  int64_t dt_us() const;
  int64_t n_steps() const;  // frames seq 0 .. n_steps-1 (t = 0 .. duration)
  int64_t baro_every() const;
  bool baro_loop_enabled() const { return nav_baro.enable < 0 ? baro.enable : nav_baro.enable != 0; }
  double baro_period_s() const { return nav_baro.period_s > 0 ? nav_baro.period_s : 1.0 / baro.rate_hz; }
};

Scenario3 parse_scenario3(const std::string& toml_text, const std::string& fallback_name, const std::string& source);
// A file the scenario names: a relative name from the directory of the scenario's file (source).
std::string scenario_file(const std::string& name, const std::string& source);
// The scenario with every file it names absolute (the tiles of [aid_ukf].map, [aid_pf].map_dir,
// [coldatom] egm96 and cache, [gravity.sh] path): the copy "as flown" an output folder keeps
// names them so, and flies again from anywhere.
Scenario3 with_absolute_files(Scenario3 s);
// A file path, <dir>/<name>.toml in search_dirs, or a built-in (scenarios/3d-*.toml).
Scenario3 load_scenario3(const std::string& name_or_path, const std::vector<std::string>& search_dirs);
std::vector<std::string> builtin_scenario3_names();

// The 3-D scenario's schema (truth/scenario_schema.hpp); parse_scenario3 reads through it.
const truth::sch::Schema<Scenario3>& scenario3_schema();
// The scenario as TOML, every key (effective values); template_comments: a template
// with unit, range and meaning of each key.
std::string scenario3_to_toml(const Scenario3& s, bool template_comments = false);

}  // namespace ggins::truth3d
