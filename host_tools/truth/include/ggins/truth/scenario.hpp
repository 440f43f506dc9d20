// Scenario: everything one host-in-the-loop flight needs, read from a TOML
// file (toml++). Built-in scenarios live in ../../scenarios/<name>.toml and
// are also compiled into the library, so `--scenario welker-perfect` works
// from any directory. Unknown keys and out-of-range values are errors.
//
// File layout (all keys optional unless noted; defaults in brackets):
//   name = "..."                      [file name without .toml]
//   description = "..."
//   [trajectory]  type = "north-flight", speed_mps [300], height_m [0],
//                 lat0_deg [0], radius_m [6378137]
//   [gravity]     model = "point-mass", gm_m3ps2 [3.986004418e14]
//   [platform]    a_m [0.5], b_m [0.5]            (half-baselines along x and z)
//   [time]        duration_s [3600], rate_hz [100] (1e6/rate_hz must be an integer)
//   [accel]       seed [1], bias_sigma_mps2 [0], noise_sigma_mps2 [0],
//                 scale_sigma [0] (dimensionless), bias_mps2 = [[bx,by,bz] x n] [0],
//                 scale = [[sx,sy,sz] x n] [0]
//   [firmware]    f_max_mps2 [50], asym_max_ps2 [1e-6], dt_tol_us [0],
//                 gravdr_trapezoid_only [false]
//   [transport]   seed [1], drop_prob [0], duplicate_prob [0], reorder_prob [0], output_drop_prob [0],
//                 garbage_prob [0]
//   [output]      csv_rate_hz [1], truth_rate_hz [10; 0 = every step]
//   [sensor_faults] seed [1], [[sensor_faults.fault]] ... (sensor_faults.hpp)
//   [firmware]    also fdi_parity_f_max_mps2 [0 = off], fdi_asym_max_ps2 [0 = off] (fdi2d.h)
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ggins/truth/sensor_faults.hpp"

namespace ggins::truth {

constexpr int kMaxAcc = 6;  // GG_MAX_ACC

struct TrajectoryParams {
  std::string type = "north-flight";
  double speed_mps = 300.0;
  double height_m = 0.0;
  double lat0_deg = 0.0;
  double radius_m = 6378137.0;  // WGS-84 semi-major axis (the paper's R_e)
};

struct GravityParams {
  std::string model = "point-mass";
  double gm_m3ps2 = 3.986004418e14;
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
  double asym_max_ps2 = 1e-6;
  int64_t dt_tol_us = 0;
  bool gravdr_trapezoid_only = false;
  double fdi_parity_f_max_mps2 = 0.0;  // accelerometer parity detection threshold (0: off)
  double fdi_asym_max_ps2 = 0.0;       // gradient-symmetry detection threshold (0: off)
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
  SensorFaultParams sensor_faults;  // injected sensor faults (sensor_faults.hpp)

  int64_t dt_us() const;    // step, microseconds
  int64_t n_steps() const;  // frames: seq 0 .. n_steps-1 (t = 0 .. duration)
  int n_acc() const { return 4; }
};

// Parse TOML text. `fallback_name` names the scenario when the text has no
// `name`. Throws std::runtime_error with the offending key on bad input.
Scenario parse_scenario(const std::string& toml_text, const std::string& fallback_name,
                        const std::string& source);

// Resolve `name_or_path`: an existing file path; else <dir>/<name>.toml for each
// dir in `search_dirs`; else a built-in. Throws with the list of known names.
Scenario load_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs);

// Names of the compiled-in scenarios.
std::vector<std::string> builtin_scenario_names();

}  // namespace ggins::truth
