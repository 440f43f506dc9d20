// The 3-D error analysis along the trajectories of the 3-D truth generator
// (host_tools/lib/truth3d): scenarios/3d-*.toml (flights with
// turns, climbs and descents; circles; tumbling bodies) and their gravity
// models, with their sensor-error sigmas, as a Cov3DScenario.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ggins/covariance/cov3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

namespace ggins::truth3d {
class Trajectory3;
}  // namespace ggins::truth3d

namespace ggins::covariance {

// A truth3d::Trajectory3 (Taylor jets: mutually exact r, v, a, C_b_i, omega, omega') as a Trajectory3D.
class Truth3DTrajectory final : public Trajectory3D {
 public:
  explicit Truth3DTrajectory(std::shared_ptr<const truth3d::Trajectory3> t);
  Traj3DPoint at(Real t) const override;
  Real omega_ie() const override;
  const std::shared_ptr<const truth3d::Trajectory3>& truth() const { return t_; }

 private:
  std::shared_ptr<const truth3d::Trajectory3> t_;
};

// The truth3d trajectory of a scenario loaded by load_truth3d_scenario (null for the built-in ones).
std::shared_ptr<const truth3d::Trajectory3> truth3d_trajectory(const Cov3DScenario& s);

// Loads a truth3d scenario (a file, <dir>/<name>.toml in search_dirs, or a
// truth3d built-in). Throws std::runtime_error with the reason.
// Mapped: trajectory + attitude (Truth3DTrajectory), the gravity field,
// platform kind, half-baselines, duration, rate, accel/gyro bias and noise
// sigmas, barometric loop ([navigation.baro] poles, omega_s2, period; [baro]
// gm_sigma_m, gm_tau_s, noise_sigma_m). Not modelled (listed in *unmodelled):
// scale factors, deterministic biases, the constant baro bias, gravity-model mode.
Cov3DScenario load_truth3d_scenario(const std::string& name_or_path, const std::vector<std::string>& search_dirs,
                                    std::vector<std::string>* unmodelled);
// The same from a loaded (and possibly overridden) truth3d scenario.
Cov3DScenario cov3d_from_truth3d(const truth3d::Scenario3& t, std::vector<std::string>* unmodelled);

// A 3-D error-analysis scenario as ggins covariance3d and montecarlo3d take it: a gc3d-*
// built-in, a great-circle file ([great_circle], cov3d.hpp), or a truth3d scenario (kept
// in `truth`; `cov` mapped from it, with what is not modelled).
struct Scenario3DInput {
  Cov3DScenario cov;
  std::optional<truth3d::Scenario3> truth;
  std::vector<std::string> unmodelled;
};
Scenario3DInput resolve_scenario3d(const std::string& name_or_path, const std::vector<std::string>& search_dirs);
// The scenario as flown, every key: scenario3_to_toml (files absolute) for a truth3d
// scenario, great_circle_scenario_to_toml otherwise. Each flies again as it is.
std::string scenario3d_to_toml(const Scenario3DInput& in);
std::vector<std::string> truth3d_scenario_names();

}  // namespace ggins::covariance
