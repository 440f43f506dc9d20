// Scenario: everything one host-in-the-loop flight needs, read from a TOML
// file (toml++). Built-in scenarios live in ../../scenarios/<name>.toml and
// are also compiled into the library, so `--scenario welker-perfect` works
// from any directory. Unknown keys and out-of-range values are errors.
//
// Every table and key (type, unit, default, allowed range, meaning) is in the scenario
// schema (scenario_schema.hpp; built in scenario.cpp from these structs' initialisers)
// and on the page generated from it, docs/scenario-reference.md (ggins scenario-reference).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth/sensor_faults.hpp"

namespace ggins::truth {

constexpr int kMaxAcc = 6;  // GG_MAX_ACC

struct TrajectoryParams {
  std::string type = "north-flight";
  double speed_mps = 300.0;
  double height_m = 0.0;
  double lat0_deg = 0.0;
  double radius_m = static_cast<double>(gravity::wgs84::kA);  // WGS-84 semi-major axis (the paper's R_e)
};

struct AnomalyParams {  // [gravity.anomaly], model = "rw-anomaly"
  uint64_t seed = 1;
  double lat_deg = NAN;           // region centre (NaN: the trajectory's mid-latitude)
  double lon_deg = 0.0;
  double half_size_m = 300e3;
  double ref_height_m = NAN;      // NaN: trajectory.height_m
  double rms_arcsec = 4.5;        // Rubenstein & Winter eq. (5)
  double corr_length_m = 33.0 * 1852.0;
  double ewald_sigma_m = 8000.0;  // SplitPointMassField (lattice.hpp)
  double lattice_spacing_m = 1000.0;
  int64_t lattice_points = 12;
};

struct GravityParams {
  std::string model = "point-mass";
  double gm_m3ps2 = static_cast<double>(gravity::wgs84::kGm);
  AnomalyParams anomaly;
};

// [navigation]: what the firmware is configured with beyond the sensors (nav2d.h).
struct NavModelParams {  // onboard zonal model (gmodel.h)
  bool set = false;      // false: the truth field's normal part (resolved by nav_model())
  double gm_m3ps2 = 0;
  double a_m = 0;
  std::array<double, 9> j{};  // J_n, n = 2..8
};

struct BaroLoopParams {  // vchan.h
  int enable = -1;       // -1: same as baro.enable
  std::array<double, 3> poles_radps{0.01, 0.02, 0.03};
  double period_s = 0;   // 0: 1 / baro.rate_hz
  double omega_s2 = 0;   // 0: |G(r0)| / |r0| from the truth at t0
  double max_age_s = 0.5;
  double coast_s = 10.0;
  double alt_min_m = -1000.0;
  double alt_max_m = 30000.0;
  double gate_m = 50.0;
  int64_t max_rejects = 5;
};

// [navigation.survey]: the anomaly grid programmed into the onboard model
// (gmodel.h polar grid; truth/survey.hpp): the truth disturbance at the nodes
// plus seeded independent Gaussian "survey" noise.
struct SurveyParams {
  bool enable = false;
  uint64_t seed = 1;
  double spacing_m = 2000.0;       // along-track node spacing at the flight radius
  double margin_m = 20000.0;       // grid extends this far before the start and after the end
  int64_t n_rho = 2;               // nodes in radius, centred on the flight radius
  double drho_m = 1000.0;          // their spacing
  double noise_gravity_mgal = 1.0;       // radial component noise, 1 sigma, mGal (1e-5 m/s^2)
  double noise_deflection_arcsec = 0.5;  // tangential component noise, 1 sigma, as g * deflection
};

struct NavigationParams {
  std::string gravity = "gradiometer";  // or "model"
  double r_ref_m = 0;                   // 0: trajectory.radius_m
  NavModelParams model;
  SurveyParams survey;
  BaroLoopParams baro;
};

struct BaroParams {  // [baro]: the truth generator's barometer
  bool enable = false;
  uint64_t seed = 1;
  double rate_hz = 1.0;
  double bias_m = 0.0;          // constant
  double gm_sigma_m = 0.0;      // first-order Gauss-Markov error, stationary sigma
  double gm_tau_s = 600.0;      // its correlation time
  double noise_sigma_m = 0.0;   // white noise per sample
  double dropout_prob = 0.0;    // a sample is missing (status ABSENT) with this probability
  std::vector<std::array<double, 2>> dropouts;  // scheduled windows [t0, t1) without samples, s
  double outlier_prob = 0.0;    // a sample is off by +-outlier_m with this probability
  double outlier_m = 0.0;
  double invalid_prob = 0.0;    // a sample is NaN (status OK: the firmware must notice)
  double latency_s = 0.0;       // sample taken (and stamped) this long before its frame
};

struct AccelErrorParams {
  uint64_t seed = 1;
  double bias_sigma_mps2 = 0.0;   // constant random bias per sensor axis, 1 sigma
  double noise_sigma_mps2 = 0.0;  // white noise per sample, 1 sigma
  double scale_sigma = 0.0;       // constant random scale-factor error, 1 sigma
  std::array<std::array<double, 3>, kMaxAcc> bias_mps2{};  // fixed bias added per sensor axis
  std::array<std::array<double, 3>, kMaxAcc> scale{};       // fixed scale-factor error per axis
};

struct FirmwareParams {
  double f_max_mps2 = 50.0;
  // GG_HEALTH_GAMMA_ASYM threshold: 2-D a fixed default; 3-D derived from the gyro and
  // accelerometer noise, baselines and step unless given (asym_max_set; scenario3d.hpp)
  double asym_max_ps2 = 1e-6;
  bool asym_max_set = false;
  int64_t dt_tol_us = 0;
  bool gravdr_trapezoid_only = false;
  double fdi_parity_f_max_mps2 = 0.0;  // accelerometer parity detection threshold (0: off)
  double fdi_asym_max_ps2 = 0.0;       // gradient-symmetry detection threshold (0: off)
  bool fdi_parity_f_max_set = false;   // given in the scenario (else derived, and not written back)
  bool fdi_asym_max_set = false;
  // Frozen-reading window (navtask.h): used frames in a row with one value that make an
  // accelerometer reading stuck; 0 off. Default derived from [accel] noise
  // (default_frozen_frames, fdi_thresholds.hpp).
  int64_t acc_frozen_frames = 0;
  bool acc_frozen_frames_set = false;
};

struct TransportParams {
  uint64_t seed = 1;
  double drop_prob = 0.0;       // first transmission of a frame silently dropped
  double duplicate_prob = 0.0;  // frame sent twice
  double reorder_prob = 0.0;    // frame k+1 sent before frame k
  double output_drop_prob = 0.0;  // hal_sim does not send a navigation output
  double garbage_prob = 0.0;      // an undecodable payload on the frame channel before a frame
};

struct OutputParams {
  double csv_rate_hz = 1.0;
  double truth_rate_hz = 10.0;  // truth messages on LCM per second; 0: every step
};

struct Scenario {
  std::string name;
  std::string description;
  std::string source;  // where it was read from (file path or "built-in")
  std::string text;    // the TOML text as read
  TrajectoryParams trajectory;
  GravityParams gravity;
  double a_m = 0.5;
  double b_m = 0.5;
  double duration_s = 3600.0;
  double rate_hz = 100.0;
  AccelErrorParams accel;
  FirmwareParams firmware;
  TransportParams transport;
  OutputParams output;
  NavigationParams navigation;
  BaroParams baro;
  SensorFaultParams sensor_faults;  // injected sensor faults (sensor_faults.hpp)

  int64_t dt_us() const;    // step, microseconds
  int64_t n_steps() const;  // frames: seq 0 .. n_steps-1 (t = 0 .. duration)
  int n_acc() const { return 4; }
  double r_ref_m() const { return navigation.r_ref_m > 0 ? navigation.r_ref_m : trajectory.radius_m; }
  int64_t baro_every() const;   // steps per barometer sample
  bool baro_loop_enabled() const { return navigation.baro.enable < 0 ? baro.enable : navigation.baro.enable != 0; }
  double baro_period_s() const { return navigation.baro.period_s > 0 ? navigation.baro.period_s : 1.0 / baro.rate_hz; }
  NavModelParams nav_model() const;  // the onboard model, defaults resolved
};

// A change to the scenario as read (a front-end's --seed, --duration), applied before the
// values derived from the flight (fault thresholds, frozen-reading window) are derived.
using ScenarioAdjust = std::function<void(Scenario&)>;

// Parse TOML text. `fallback_name` names the scenario when the text has no
// `name`. Throws std::runtime_error with the offending key on bad input.
Scenario parse_scenario(const std::string& toml_text, const std::string& fallback_name,
                        const std::string& source, const ScenarioAdjust& adjust = {});
// (parse_scenario_table, in scenario_toml.hpp: the same on a table already parsed)

// Resolve `name_or_path`: an existing file path; else <dir>/<name>.toml for each
// dir in `search_dirs`; else a built-in. Throws with the list of known names.
Scenario load_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs,
                       const ScenarioAdjust& adjust = {});

// Names of the compiled-in scenarios.
std::vector<std::string> builtin_scenario_names();

namespace sch {
template <class R>
struct Schema;
}
// The 2-D scenario's schema (scenario_schema.hpp): every key, its type, unit, default,
// range and meaning; parse_scenario reads through it.
const sch::Schema<Scenario>& scenario_schema();
// The scenario as TOML (every table and key, effective values: defaults filled in,
// overrides applied); parse_scenario reads it back to the same values. With
// template_comments: each key commented with unit, range and meaning (a template).
std::string scenario_to_toml(const Scenario& s, bool template_comments = false);

}  // namespace ggins::truth
