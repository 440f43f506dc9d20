// Scenario parameters for the covariance tool: built-in definitions and TOML
// scenario files (scenarios/*.toml). See docs/error-analysis.md for the keys.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::covariance {

struct CovScenario {
  std::string name;
  std::string source = "built-in";  // "built-in" or the TOML path
  double duration_s = 3600.0;
  // Earth (spherical point mass) -- Welker et al. section VI.
  double radius_m = static_cast<double>(gravity::wgs84::kA);   // R_e, WGS-84 semi-major axis
  double gm_m3ps2 = static_cast<double>(gravity::wgs84::kGm);  // GM, WGS-84
  // Trajectory: due north at constant speed (the only kind so far).
  std::string trajectory = "north-flight";
  double speed_mps = 300.0;
  double height_m = 0.0;
  double lat0_rad = 0.0;
  // Platform: half-baselines of accelerometers 1:(+a,0) 2:(0,+b) 3:(-a,0) 4:(0,-b).
  double a_m = 0.5, b_m = 0.5;
  // Constant random accelerometer biases, one sigma, eight axes
  // (order f1x f2x f3x f4x f1z f2z f3z f4z, Welker et al. eq. 7's d).
  std::vector<double> bias_sigma_mps2 = std::vector<double>(8, 2e-12);
  // White accelerometer noise, one sigma per sample at rate_hz (spectral
  // density sigma^2/rate_hz); zero in the paper. Scale-factor errors are not
  // in the linear model (they are listed in `unmodelled` when non-zero).
  std::vector<double> noise_sigma_mps2 = std::vector<double>(8, 0.0);
  double rate_hz = 100.0;
  double scale_sigma = 0.0;
  // Initial gravity uncertainty dG(0), one sigma, (x, z) (Welker et al. eq. 8).
  double gravity0_sigma_x_mps2 = 2e-12, gravity0_sigma_z_mps2 = 2e-12;
  // Initial position/velocity uncertainty (zero in the paper: "known position").
  double pos0_sigma_m = 0.0, vel0_sigma_mps = 0.0;
  // Barometric vertical loop ([navigation.baro] and [baro] of the
  // truth generator, same defaults): welker2d_baro.hpp. The constant baro bias
  // is treated as random with sigma = |bias_m|.
  bool baro_loop = false;
  std::vector<double> baro_poles_radps{0.01, 0.02, 0.03};
  double baro_period_s = 1.0, baro_omega_s2 = 0.0;  // 0: GM / r0^3
  double baro_bias_m = 0.0, baro_gm_sigma_m = 0.0, baro_gm_tau_s = 600.0, baro_noise_sigma_m = 0.0;
  // TOML keys that were absent (their defaults above were used).
  std::vector<std::string> defaulted;
  // Inputs present in the scenario that the linear model leaves out.
  std::vector<std::string> unmodelled;
};

// Built-in names: "welker-table1". Returns nullopt for an unknown name.
std::optional<CovScenario> builtin_scenario(const std::string& name);
std::vector<std::string> builtin_names();
// Reads a TOML scenario file; throws std::runtime_error with the reason.
CovScenario load_scenario_toml(const std::string& path);
// Name or path: an existing file is read as TOML; otherwise
// scenarios/<name>.toml (relative to cwd or the repo root) if present, else built-in.
CovScenario resolve_scenario(const std::string& name_or_path, const std::string& repo_root);
// The scenario as ggins covariance flies it, as a file that it reads back to the same
// values: ggins run's keys (every key, truth/scenario.hpp's scenario_to_toml) set to what
// the linear model uses, per-axis sigmas as arrays, and the covariance-only [initial]
// table. template_comments: the complete template (every key at its default, commented).
std::string cov_scenario_to_toml(const CovScenario& s, bool template_comments = false);

}  // namespace ggins::covariance
