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
  truth::FirmwareParams firmware;  // f_max_mps2, asym_max_ps2 (derived unless given: derived_asym_max_ps2), dt_tol_us
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

// [firmware] asym_max_ps2 unless the scenario gives it: the GG_HEALTH_GAMMA_ASYM threshold
// of nav3d (nav3d.h, "Parity"), applied to each of its four parity residuals p_0..p_3 per
// step. SI units throughout: h = 1 / time.rate_hz (s), half-baselines d = (a, b, c) =
// platform a_m, b_m, c_m (m); sensors i = 0..5 at +a x, +b y, +c z, -a x, -b y, -c z.
//
// The residuals (diff3d.h: M[j][k] = (f_k,j - f_k+3,j) / (2 d_k), f_i,j reading of sensor i
// on body axis j, m/s^2):
//   p_x = (M[2][1] - M[1][2]) / 2 - wd_x,   p_y = (M[0][2] - M[2][0]) / 2 - wd_y,
//   p_z = (M[1][0] - M[0][1]) / 2 - wd_z,   p_3 = trace(Gamma_b) = -2 |w|^2 - trace(M),
// strapdown: wd = (11 w_k+1 - 18 w_k + 9 w_k-1 - 2 w_k-2) / (6 h), the gyro-derived angular
// acceleration (w the gyro samples, rad/s); stabilized: wd = 0 and w = 0 (gyros unused).
// On a healthy rigid body the antisymmetric part is the true angular acceleration and the
// trace of the gravitational gradient is 0 (Laplace), so what the residuals carry is:
//
// 1. Gyro white noise, sigma_g = [gyro] noise_sigma_radps per sample (strapdown only): the
//    difference weights 11, -18, 9, -2 over 6h of independent samples,
//      sigma_wd = sigma_g sqrt(11^2 + 18^2 + 9^2 + 2^2) / (6 h) = sqrt(530)/6 sigma_g / h
//               = 3.837 sigma_g / h   (rad/s^2)
//    (Gao's 2.909e-6 rad/s at 100 Hz: 1.116e-3 rad/s^2, 1100 x the former fixed 1e-6).
//    The gyro biases cancel (the weights sum to 0). In the trace, -2 |w|^2 moves by -4 w . e
//    (e the rate error, rad/s): sigma 4 W sigma_g, W = GG_LIM_W_MAX_RPS (10 rad/s: the
//    largest rate the task accepts, the flight's own rate unknown here), and a constant rate
//    error e_b (random: [gyro] bias_sigma_radps and the [draw] gyro_bias_radps values, each a
//    sigma; fixed: [gyro] bias_radps) by 4 W |e_b| + 2 |e_b|^2.
// 2. Accelerometer errors, per reading sigma_p = sqrt(sigma_b^2 + sigma_n^2 + (10 m/s^2
//    sigma_s)^2) ([accel] bias_sigma_mps2, noise_sigma_mps2, scale_sigma on a ~10 m/s^2
//    reading; the same model as fdi_parity_f_max_mps2 above); each M entry is the difference
//    of two readings over 2 d_k, so
//      sigma_x^2 = sigma_p^2 (1/b^2 + 1/c^2) / 8,  sigma_y^2 = sigma_p^2 (1/c^2 + 1/a^2) / 8,
//      sigma_z^2 = sigma_p^2 (1/a^2 + 1/b^2) / 8,  sigma_3^2 = sigma_p^2 (1/a^2 + 1/b^2 + 1/c^2) / 2;
//    the fixed biases beta_i,j ([accel] bias_mps2) move them by
//      p_x: ((beta_1z - beta_4z)/(2b) - (beta_2y - beta_5y)/(2c)) / 2,
//      p_y: ((beta_2x - beta_5x)/(2c) - (beta_0z - beta_3z)/(2a)) / 2,
//      p_z: ((beta_0y - beta_3y)/(2a) - (beta_1x - beta_4x)/(2b)) / 2,
//      p_3: -sum_k (beta_k,k - beta_k+3,k) / (2 d_k);
//    a bias common to all six ([draw] accel_common_bias_mps2) cancels.
// 3. The differencing's own errors (nav3d.h): the third-order difference's h^3/4 |w''''|
//    (7.5e-8 rad/s^2 on a body spinning at 1 rad/s with 0.3 rad/s precession at 100 Hz) and
//    the field's curvature over the baselines: covered by the floor kAsymFloorPs2 = 1e-6
//    s^-2, the fixed default this derivation replaces.
//
// Threshold: asym_max = 7 max(S_x, S_y, S_z, S_3) + max_j |fixed_j| + kAsymFloorPs2, where
// S_j^2 = sigma_wd^2 + sigma_j^2 (j = x, y, z) and S_3^2 = 16 W^2 (sigma_g^2 + sigma_eb^2)
// + sigma_3^2 (the gyro terms strapdown only). A Gaussian residual exceeds 7 sigma with
// probability 2.6e-12 per test: four tests per step at 100 Hz make 1.4e7 in 10 h, 3.7e-5
// expected false alarms per 10 h flight (the steps' residuals are correlated through the
// shared gyro samples, which changes no single test's probability).
// Not in it: a gyro scale-factor error s leaves s w' in p_x..p_z and -4 s |w|^2 in the
// trace (unknown without the flight's rates): a scenario with [gyro] scale errors on a
// manoeuvring body gives asym_max_ps2. What the threshold costs: the residual of an
// accelerometer fault that corrupts the antisymmetric part must exceed it; a bias beta on
// one reading of an antisymmetric entry moves it by beta / (4 d), so with Gao's gyro noise
// and 0.5 m half-baselines a bias is seen by this check from 4 d asym_max = 1.6e-2 m/s^2 (the
// pair-mean detection, fdi_parity_f_max_mps2, sees the same reading from 2 x 7 sigma_p =
// 7.7e-9 m/s^2 with Gao's 5.5e-10 m/s^2 accelerometer noise).
// Errors: std::runtime_error when the derived value exceeds GG_LIM_ASYM_MAX (gyro noise above
// ~3.7e-4 rad/s per sample at 100 Hz: give asym_max_ps2).
constexpr double kAsymFloorPs2 = 1e-6;
double derived_asym_max_ps2(const Scenario3& s);
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
