#include "ggins/covariance/cov3d_truth3d.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"
#include "ggins/truth3d/trajectory3d.hpp"

namespace ggins::covariance {

Truth3DTrajectory::Truth3DTrajectory(std::shared_ptr<const truth3d::Trajectory3> t) : t_(std::move(t)) {}

Traj3DPoint Truth3DTrajectory::at(Real t) const {
  const truth3d::State3 s = t_->at(t);
  Traj3DPoint p;
  p.r_e = s.r_e;
  p.v_e = s.v_e;
  p.a_e = s.a_e;
  p.C_b_e = s.C_b_e;
  p.w_ib_b = s.omega_b;
  p.wdot_ib_b = s.omega_dot_b;
  return p;
}

Real Truth3DTrajectory::omega_ie() const { return t_->omega_ie(); }

std::shared_ptr<const truth3d::Trajectory3> truth3d_trajectory(const Cov3DScenario& s) {
  if (const auto* t = dynamic_cast<const Truth3DTrajectory*>(s.traj_override.get())) return t->truth();
  return nullptr;
}

std::vector<std::string> truth3d_scenario_names() { return truth3d::builtin_scenario3_names(); }

Cov3DScenario load_truth3d_scenario(const std::string& name_or_path, const std::vector<std::string>& dirs,
                                    std::vector<std::string>* unmodelled) {
  return cov3d_from_truth3d(truth3d::load_scenario3(name_or_path, dirs), unmodelled);
}

Cov3DScenario cov3d_from_truth3d(const truth3d::Scenario3& t, std::vector<std::string>* unmodelled) {
  std::vector<std::string> um;
  Cov3DScenario s;
  s.name = t.name;
  s.source = t.source;
  s.platform = t.strapdown() ? Platform::kStrapdown : Platform::kStabilized;
  s.field = t.gravity.model;
  s.field_override = std::shared_ptr<const gravity::Field>(truth3d::make_field3(t));
  s.traj_override = std::make_shared<Truth3DTrajectory>(std::shared_ptr<const truth3d::Trajectory3>(truth3d::make_trajectory3(t)));
  s.omega_ie = double(truth3d::kOmegaIe);
  s.lat0_deg = t.trajectory.lat_deg;
  s.lon0_deg = t.trajectory.lon_deg;
  s.height_m = t.trajectory.height_m;
  s.speed_mps = 0;  // not used with a trajectory override
  s.heading_deg = 0;
  s.duration_s = t.duration_s;
  s.model.half_base_m = {t.a_m, t.b_m, t.c_m};
  s.model.rate_hz = t.rate_hz;
  s.acc_bias_sigma_mps2 = t.accel.bias_sigma_mps2;
  s.model.acc_noise_sigma_mps2 = t.accel.noise_sigma_mps2;
  s.gyro_bias_sigma_radps = t.gyro.bias_sigma_radps;
  s.model.gyro_noise_sigma_radps = t.gyro.noise_sigma_radps;
  if (t.accel.scale_sigma != 0) um.emplace_back("accel.scale_sigma");
  if (t.gyro.scale_sigma != 0) um.emplace_back("gyro.scale_sigma");
  for (double b : t.gyro.bias_radps)
    if (b != 0) um.emplace_back("gyro.bias_radps (deterministic)");
  if (t.draw.active()) um.emplace_back("draw (the run's Monte Carlo draw of biases and initial errors)");
  if (t.nav_gravity != "gradiometer") um.emplace_back("navigation.gravity = model (a different error model)");
  if (t.baro_loop_enabled()) {
    s.model.baro.on = true;
    for (int i = 0; i < 3; ++i) s.model.baro.poles_radps[size_t(i)] = t.nav_baro.poles_radps[size_t(i)];
    s.model.baro.omega_s2 = t.nav_baro.omega_s2;  // 0: from the field at r0
    s.model.baro.period_s = t.baro_period_s();
    s.model.baro.gm_sigma_m = t.baro.gm_sigma_m;
    s.model.baro.gm_tau_s = t.baro.gm_tau_s;
    s.model.baro.noise_sigma_m = t.baro.noise_sigma_m;
    s.baro_bias_sigma_m = std::abs(t.baro.bias_m);  // the constant bias as a random one of that size (as in 2-D)
  }
  if (unmodelled) *unmodelled = um;
  return s;
}

Scenario3DInput resolve_scenario3d(const std::string& name_or_path, const std::vector<std::string>& dirs) {
  Scenario3DInput in;
  if (auto b = builtin_scenario3d(name_or_path)) {
    in.cov = *b;
    return in;
  }
  // a great-circle file (a [great_circle] table), by path or <dir>/<name>.toml
  std::vector<std::string> cands{name_or_path};
  for (const auto& d : dirs) cands.push_back(d + "/" + name_or_path + ".toml");
  for (const auto& c : cands) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(c, ec)) continue;
    std::ifstream f(c);
    std::stringstream ss;
    ss << f.rdbuf();
    if (!is_great_circle_text(ss.str())) break;  // a truth3d scenario
    in.cov = parse_great_circle_scenario(ss.str(), std::filesystem::path(c).stem().string(), c);
    return in;
  }
  in.truth = truth3d::load_scenario3(name_or_path, dirs);
  in.cov = cov3d_from_truth3d(*in.truth, &in.unmodelled);
  return in;
}

std::string scenario3d_to_toml(const Scenario3DInput& in) {
  if (in.truth) return truth3d::scenario3_to_toml(truth3d::with_absolute_files(*in.truth));
  return great_circle_scenario_to_toml(in.cov);
}

}  // namespace ggins::covariance
