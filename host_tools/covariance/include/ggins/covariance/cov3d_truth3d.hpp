// The 3-D error analysis along the trajectories of the 3-D truth generator
// (host_tools/truth3d): scenarios/3d-*.toml (flights with
// turns, climbs and descents; circles; tumbling bodies) and their gravity
// models, with their sensor-error sigmas, as a Cov3DScenario.
#pragma once

#include <string>
#include <vector>

#include "ggins/covariance/cov3d.hpp"

namespace ggins::covariance {

// Loads a truth3d scenario (a file, <dir>/<name>.toml in search_dirs, or a
// truth3d built-in). Throws std::runtime_error with the reason.
// Mapped: trajectory + attitude (Truth3DTrajectory), the gravity field,
// platform kind, half-baselines, duration, rate, accel/gyro bias and noise
// sigmas, barometric loop ([navigation.baro] poles, omega_s2, period; [baro]
// gm_sigma_m, gm_tau_s, noise_sigma_m). Not modelled (listed in *unmodelled):
// scale factors, deterministic biases, the constant baro bias, gravity-model mode.
Cov3DScenario load_truth3d_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs,
                                    std::vector<std::string>* unmodelled);
std::vector<std::string> truth3d_scenario_names();

}  // namespace ggins::covariance
