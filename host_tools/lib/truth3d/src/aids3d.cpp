// The aiding sources of a 3-D scenario (Scenario3::aid_ukf, its keys in
// aids3d.hpp) mapped onto the firmware configuration (gg_nav3d_config_t.aid_mm):
// the [aid_ukf] table is the gradient-map UKF of aid_mmukf.h.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "ggins/truth3d/aids3d.hpp"
#include "ggins/truth3d/config3d.hpp"

namespace ggins::truth3d {

std::vector<std::string> aid_ukf_map_paths(const AidUkf3& a, const std::string& scenario_source) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  for (const auto& m : a.maps) out.push_back(truth3d::scenario_file(m, scenario_source));
  return out;
}

void apply_aid_ukf(const AidUkf3& a, double rate_hz, const GyroErrorParams& gyro, double baro_noise_m,
                   gg_nav3d_config_t& c) {
  gg_aid_mm_config_t& m = c.aid_mm;
  m = gg_aid_mm_config_t{};
  m.enable = a.enabled ? 1 : 0;
  if (!a.enabled) return;
  m.update_steps = static_cast<int32_t>(std::llround(a.update_period_s * rate_hz));
  m.max_passes = a.max_passes;
  m.sigma_meas_s2 = a.sigma_meas_E * 1e-9;
  m.sigma_db_s2 = a.sigma_db_E * 1e-9;
  m.offdiag_ratio = a.offdiag_ratio;
  m.sig0_pos_m = a.sig0_pos_m;
  m.sig0_vel_mps = a.sig0_vel_mps;
  m.sig0_att_rad = a.sig0_att_rad;
  m.sig0_g_mps2 = a.sig0_g_mps2;
  m.q_vel_mps_rts = a.q_vel_mps_rts;
  m.q_att_rad_rts = a.q_att_rad_rts;
  m.q_g_mps2_rts = a.q_g_mps2_rts;
  m.lambda = a.lambda;
  m.gate_nis = a.gate_nis;
  m.average_steps = static_cast<int32_t>(std::llround(a.average_s * rate_hz));
  double b2 = gyro.bias_sigma_radps * gyro.bias_sigma_radps;
  double bmax2 = 0;
  for (double b : gyro.bias_radps) bmax2 = std::max(bmax2, b * b);
  m.sigma_gyro_rps = a.sigma_gyro_rps >= 0 ? a.sigma_gyro_rps : gyro.noise_sigma_radps;
  m.sigma_gyro_bias_rps = a.sigma_gyro_bias_rps >= 0 ? a.sigma_gyro_bias_rps : std::sqrt(b2 + bmax2);
  m.bias_states = a.bias_states ? 1 : 0;
  m.sig0_gyro_bias_rps = a.sig0_gyro_bias_rps;
  m.sig0_acc_bias_mps2 = a.sig0_acc_bias_mps2;
  m.q_gyro_bias_rps_rts = a.q_gyro_bias_rps_rts;
  m.q_acc_bias_mps2_rts = a.q_acc_bias_mps2_rts;
  m.sigma_baro_m = a.sigma_baro_m >= 0 ? a.sigma_baro_m : baro_noise_m;
  m.integ = integrity_config(a);
}

}  // namespace ggins::truth3d
