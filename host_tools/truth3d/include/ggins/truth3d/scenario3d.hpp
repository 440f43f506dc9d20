// 3-D scenario (TOML, toml++): a flight or a tumbling body over the rotating
// WGS-84 Earth, the sensor errors, and what the firmware (nav3d.h) is
// configured with. Built-ins: scenarios/3d-*.toml (compiled in). Unknown keys
// and out-of-range values are errors.
//
// Layout (defaults in brackets):
//   name, description
//   [trajectory] type = "flight" | "circle" | "tumble" | "route"
//     lat_deg [45], lon_deg [10], height_m [5000]     (flight: start; circle: centre; tumble: the fixed point)
//     flight: velocity_ned_mps [[200, 0, 0]],
//             [[trajectory.maneuver]] t_s, duration_s [60], dv_ned_mps [[0, 0, 0]]  (trajectory3d.hpp)
//     circle: radius_m [5000], speed_mps [200]
//     route (route3d.hpp): the start is waypoint 0; speed_mps [200] (first leg), initial_speed_mps
//             [speed_mps] (at t = 0), turn_rate_dps [3], climb_rate_mps [5], accel_mps2 [0.5],
//             vertical_accel_mps2 [0.5] (defaults of every waypoint);
//             [[trajectory.waypoint]] lat_deg, lon_deg (required), height_m [previous], speed_mps
//             [previous leg's] (ground speed on the leg ending here), climb_rate_mps, accel_mps2,
//             vertical_accel_mps2 (of that leg), turn_rate_dps (of the turn at this waypoint)
//     tumble: spin_radps [1], precession_radps [0.2], nutation_deg [30], nutation_amp_deg [5],
//             nutation_radps [0.05], psi0_deg [0], phi0_deg [0]
//   [platform] kind = "stabilized" | "strapdown" [strapdown], a_m [0.5], b_m [0.5], c_m [0.5]
//   [gravity]  model = "wgs84-normal" [default] | "point-mass" | "rw-anomaly" (as in 2-D:
//              normal field + Rubenstein & Winter point masses on the fast path) | "egm96"
//              (normal field exactly + the EGM96 disturbing potential, spherical harmonics to
//              degree nmax, on the lattice fast path: gravity/lattice.hpp FastField),
//              gm_m3ps2 (point-mass), [gravity.anomaly] as in 2-D (centre [trajectory lat/lon]),
//              [gravity.sh] path [<source>/data/egm96_to360.ascii.txt], nmax [360],
//              lattice_spacing_m [2500], lattice_points [8]
//   [time]     duration_s [3600], rate_hz [100]
//   [accel]    seed [1], bias_sigma_mps2 [0], noise_sigma_mps2 [0], scale_sigma [0],
//              bias_mps2 = [[bx,by,bz] x 6] [0]
//   [gyro]     seed [2], bias_sigma_radps [0], noise_sigma_radps [0], scale_sigma [0],
//              bias_radps = [bx, by, bz] [0], scale = [sx, sy, sz] [0]
//   [baro]     truth barometer on the geodetic height: enable [false], seed [1], rate_hz [1],
//              bias_m [0], gm_sigma_m [0], gm_tau_s [600], noise_sigma_m [0]
//   [navigation] gravity = "gradiometer" | "model" [gradiometer] (model: the WGS-84 zonal series, J2..J8)
//   [navigation.baro] enable [= baro.enable], poles_radps [[0.01, 0.02, 0.03]],
//              period_s [1 / baro.rate_hz], omega_s2 [|G(r0)| / |r0|], max_age_s [0.5], coast_s [10],
//              alt_min_m [-1000], alt_max_m [30000], gate_m [50], max_rejects [5]
//   [firmware] f_max_mps2 [50], asym_max_ps2 [1e-6], dt_tol_us [0],
//              fdi_parity_f_max_mps2 [derived from [accel], see below; 0 = off]
//   [output]   csv_rate_hz [1]
//   [sensor_faults] seed [1], [[sensor_faults.fault]] kind, sensor (0..5 | "gyro"), axis, start_s,
//              duration_s, size, prob (faults3d.hpp)
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ggins/truth/scenario.hpp"
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

struct GyroErrorParams {
  uint64_t seed = 2;
  double bias_sigma_radps = 0, noise_sigma_radps = 0, scale_sigma = 0;
  std::array<double, 3> bias_radps{0, 0, 0};
  std::array<double, 3> scale{0, 0, 0};
};

struct ShFieldParams {  // [gravity.sh], model = "egm96"
  std::string path;      // empty: GGINS_DATA_DIR/egm96_to360.ascii.txt
  int64_t nmax = 360;
  double lattice_spacing_m = 2500;
  int64_t lattice_points = 8;
};

struct Scenario3 {
  std::string name, description, source, text;
  Trajectory3Params trajectory;
  std::string platform = "strapdown";  // or "stabilized"
  double a_m = 0.5, b_m = 0.5, c_m = 0.5;
  truth::GravityParams gravity;  // model default "wgs84-normal" here
  ShFieldParams sh;
  double duration_s = 3600, rate_hz = 100;
  truth::AccelErrorParams accel;
  GyroErrorParams gyro;
  truth::BaroParams baro;  // enable, seed, rate_hz, bias_m, gm_sigma_m, gm_tau_s, noise_sigma_m
  std::string nav_gravity = "gradiometer";
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
  double csv_rate_hz = 1;
  SensorFaults3 sensor_faults;  // [sensor_faults] (faults3d.hpp)
  AidUkf3 aid_ukf;              // [aid_ukf]: the gradient-map aid (aids3d.hpp)
  ColdAtom3 coldatom;           // [coldatom]: the cold-atom gradiometer (coldatom3d.hpp)
  AidPf3 aid_pf;                // [aid_pf]: the cold-atom particle-filter aid (coldatom3d.hpp)

  bool strapdown() const { return platform == "strapdown"; }
  int64_t dt_us() const;
  int64_t n_steps() const;  // frames seq 0 .. n_steps-1 (t = 0 .. duration)
  int64_t baro_every() const;
  bool baro_loop_enabled() const { return nav_baro.enable < 0 ? baro.enable : nav_baro.enable != 0; }
  double baro_period_s() const { return nav_baro.period_s > 0 ? nav_baro.period_s : 1.0 / baro.rate_hz; }
};

Scenario3 parse_scenario3(const std::string& toml_text, const std::string& fallback_name, const std::string& source);
// A file path, <dir>/<name>.toml in search_dirs, or a built-in (scenarios/3d-*.toml).
Scenario3 load_scenario3(const std::string& name_or_path, const std::vector<std::string>& search_dirs);
std::vector<std::string> builtin_scenario3_names();

}  // namespace ggins::truth3d
