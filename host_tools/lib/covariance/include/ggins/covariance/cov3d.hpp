// 3-D covariance scenarios: parameters, model construction,
// NED projection and the eigen analysis of the 3-D error dynamics, shared by
// ggins-covariance3d, ggins-montecarlo3d and the tests.
#pragma once

#include <complex>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ggins/covariance/nav3d_model.hpp"
#include "ggins/gravity/wgs84.hpp"

namespace ggins::covariance {

struct Cov3DScenario {
  std::string name = "gc3d-stabilized";
  Platform platform = Platform::kStabilized;
  std::string field = "normal";    // "normal" (WGS-84 normal gravitation) or "point-mass"
  double omega_ie = static_cast<double>(gravity::wgs84::kOmega);  // rad/s; 0 = non-rotating Earth
  double radius_m = static_cast<double>(gravity::wgs84::kA), height_m = 0.0;  // geocentric radius of the circle = radius + height
  double lat0_deg = 45.0, lon0_deg = 0.0, heading_deg = 45.0, speed_mps = 300.0;
  double duration_s = 3600.0;
  Nav3DModelConfig model;
  double acc_bias_sigma_mps2 = 2e-12;     // each of the 18 readings
  double gyro_bias_sigma_radps = 0.0;     // each gyro axis (strapdown)
  double g0_sigma_mps2 = 0.0;             // initial dG, each ECEF axis
  double r0_sigma_m = 0.0, v0_sigma_mps = 0.0, psi0_sigma_rad = 0.0;
  double baro_bias_sigma_m = 0.0;         // constant barometer bias, 1 sigma (baro loop)
  // Set when the scenario comes from the 3-D truth generator (cov3d_truth3d.hpp):
  // its trajectory and field replace the great circle and the field above.
  std::shared_ptr<const Trajectory3D> traj_override;
  std::shared_ptr<const gravity::Field> field_override;
  std::string source = "built-in";
};

std::optional<Cov3DScenario> builtin_scenario3d(const std::string& name);
std::vector<std::string> builtin_names3d();

// The great-circle scenario as a file (TOML; its schema: cov3d_scenario.cpp, the keys
// [great_circle], [time], [instrument], [errors], [baro]): what the gc3d-* built-ins
// are, written out and read back by the same rows. A file is one when it has a
// [great_circle] table. Errors name file:line, the key, the value and the allowed range.
bool is_great_circle_text(const std::string& text);
Cov3DScenario parse_great_circle_scenario(const std::string& text, const std::string& fallback_name,
                                          const std::string& source);
// Every key with its effective value; template_comments: unit, range and meaning of each.
std::string great_circle_scenario_to_toml(const Cov3DScenario& s, bool template_comments = false);
std::string great_circle_reference_markdown();

std::shared_ptr<const gravity::Field> make_field3d(const Cov3DScenario& s);
std::shared_ptr<const Trajectory3D> make_trajectory3d(const Cov3DScenario& s);
std::shared_ptr<const Nav3DModel> make_model3d(const Cov3DScenario& s);
MatrixXd initial_covariance3d(const Cov3DScenario& s, const Nav3DModel& m);

// One-sigma values in NED (north, east, down) of the 3-vector blocks of the
// navigation states starting at index i0 (position, velocity, gravity, psi).
Eigen::Vector3d ned_sigma(const MatrixXd& P, int i0, const Eigen::Matrix3d& C_n_e);

// Eigen analysis of the reduced F at time t.
struct Eigen3D {
  std::vector<std::complex<double>> ev;  // all eigenvalues of F (sorted)
  double omega_s = 0;       // sqrt(-mean horizontal eigenvalue of Gamma_e): Schuler frequency
  double gamma_up = 0;      // radial eigenvalue of Gamma_e (2 w_s^2 for a point mass)
  double lat_gc = 0;        // geocentric latitude of the point, rad
  double foucault = 0;      // omega_ie sin(lat), rad/s
  // Nav-block eigenvalues (first 9 states, no attitude/baro): the residual
  // |det((sI + W)^2 - Gamma_e)| / |s|^6 of each non-zero eigenvalue (an
  // independent characterisation: F's nav block has the characteristic
  // polynomial s^3 det((sI + W)^2 - Gamma_e)).
  double max_charpoly_residual = 0;
  std::vector<std::complex<double>> nav_ev;
};
Eigen3D eigen3d(const Nav3DModel& m, double t);

}  // namespace ggins::covariance
