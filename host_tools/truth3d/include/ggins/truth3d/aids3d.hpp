// The aiding sources of a 3-D scenario, as the scenario file states them (read once, by
// parse_scenario3, into Scenario3::aid_ukf); run3d/aids3d.hpp maps them onto the firmware
// configuration. One table per aid source:
//
//   [aid_ukf]
//   enabled = true
//   map = ["tile.bin", ...]    # gmap tiles (ggins gmap) for the computer's map storage;
//                              # relative paths: from the scenario file's directory
//   update_period_s = 10.0     # between epochs
//   max_passes = 4             # progressive update passes
//   sigma_meas_E = 0.01        # gradiometer noise of a diagonal component (Gao: 0.01 E)
//   sigma_db_E = 0.001         # map noise (Gao: 0.001 E)
//   offdiag_ratio = 0.7071     # off-diagonal / diagonal noise (six differenced accelerometers)
//   sig0_pos_m, sig0_vel_mps, sig0_att_rad, sig0_g_mps2   # initial one-sigma
//   q_vel_mps_rts, q_att_rad_rts, q_g_mps2_rts           # process noise
//   gate_nis = 0.0             # NIS gate (chi-square, 6 dof); 0: none
//   average_s = 0.0            # tensors averaged into an epoch's measurement over this long
//                              # before it (0: the epoch's own sample), <= update_period_s
//   sigma_gyro_rps             # gyro white noise of one navigation step's rate, rad/s: its
//                              # share of R ([w x]^2 removal) and of Q; default [gyro] noise_sigma_radps
//   sigma_gyro_bias_rps        # gyro bias one-sigma, rad/s: its share of R; default [gyro]
//                              # bias_sigma_radps (+ the largest |bias_radps| entry)
#pragma once

#include <string>
#include <vector>
#include <toml++/toml.h>

#include "ggins/truth/scenario_toml.hpp"

namespace ggins::truth3d {

struct AidUkf3 {
  bool enabled = false;
  std::vector<std::string> maps;  // as written in the scenario
  double update_period_s = 10.0;
  int max_passes = 4;
  double sigma_meas_E = 0.01;
  double sigma_db_E = 0.001;
  double offdiag_ratio = 0.70710678118654752;
  double sig0_pos_m = 50.0;
  double sig0_vel_mps = 0.1;
  double sig0_att_rad = 1.0e-5;
  double sig0_g_mps2 = 1.0e-6;
  double q_vel_mps_rts = 1.0e-5;
  double q_att_rad_rts = 1.0e-8;
  double q_g_mps2_rts = 1.0e-9;
  double lambda = 0.0;
  double gate_nis = 0.0;
  double average_s = 0.0;
  double sigma_gyro_rps = -1.0;       // < 0: from the scenario's [gyro] (run3d/aids3d.hpp)
  double sigma_gyro_bias_rps = -1.0;  // < 0: from the scenario's [gyro]
};

// The [aid_ukf] table of a scenario (t null: absent, the defaults: aid off); throws naming
// the key, as the rest of the scenario parser.
inline AidUkf3 parse_aid_ukf(const toml::table* t, const std::string& source) {
  namespace st = ggins::truth::scenario_toml;
  AidUkf3 a;
  if (!t) return a;
  const std::string w = "aid_ukf";
  st::check_keys(*t, w,
                 {"enabled", "map", "update_period_s", "max_passes", "sigma_meas_E", "sigma_db_E", "offdiag_ratio",
                  "sig0_pos_m", "sig0_vel_mps", "sig0_att_rad", "sig0_g_mps2", "q_vel_mps_rts", "q_att_rad_rts",
                  "q_g_mps2_rts", "lambda", "gate_nis", "average_s", "sigma_gyro_rps", "sigma_gyro_bias_rps"},
                 source);
  a.enabled = st::get_bool(*t, w, "enabled", a.enabled, source);
  if (const toml::node* n = t->get("map")) {
    if (n->is_string()) {
      a.maps.push_back(n->as_string()->get());
    } else if (const toml::array* arr = n->as_array()) {
      for (const auto& e : *arr) {
        if (!e.is_string()) st::fail(source, "aid_ukf.map must be a file name or a list of them");
        a.maps.push_back(e.as_string()->get());
      }
    } else {
      st::fail(source, "aid_ukf.map must be a file name or a list of them");
    }
  }
  a.update_period_s = st::get_num(*t, w, "update_period_s", a.update_period_s, source);
  a.max_passes = static_cast<int>(st::get_int(*t, w, "max_passes", a.max_passes, source));
  a.sigma_meas_E = st::get_num(*t, w, "sigma_meas_E", a.sigma_meas_E, source);
  a.sigma_db_E = st::get_num(*t, w, "sigma_db_E", a.sigma_db_E, source);
  a.offdiag_ratio = st::get_num(*t, w, "offdiag_ratio", a.offdiag_ratio, source);
  a.sig0_pos_m = st::get_num(*t, w, "sig0_pos_m", a.sig0_pos_m, source);
  a.sig0_vel_mps = st::get_num(*t, w, "sig0_vel_mps", a.sig0_vel_mps, source);
  a.sig0_att_rad = st::get_num(*t, w, "sig0_att_rad", a.sig0_att_rad, source);
  a.sig0_g_mps2 = st::get_num(*t, w, "sig0_g_mps2", a.sig0_g_mps2, source);
  a.q_vel_mps_rts = st::get_num(*t, w, "q_vel_mps_rts", a.q_vel_mps_rts, source);
  a.q_att_rad_rts = st::get_num(*t, w, "q_att_rad_rts", a.q_att_rad_rts, source);
  a.q_g_mps2_rts = st::get_num(*t, w, "q_g_mps2_rts", a.q_g_mps2_rts, source);
  a.lambda = st::get_num(*t, w, "lambda", a.lambda, source);
  a.gate_nis = st::get_num(*t, w, "gate_nis", a.gate_nis, source);
  a.average_s = st::get_num(*t, w, "average_s", a.average_s, source);
  a.sigma_gyro_rps = st::get_num(*t, w, "sigma_gyro_rps", a.sigma_gyro_rps, source);
  a.sigma_gyro_bias_rps = st::get_num(*t, w, "sigma_gyro_bias_rps", a.sigma_gyro_bias_rps, source);
  if (t->get("sigma_gyro_rps") && !(a.sigma_gyro_rps >= 0)) st::fail(source, "aid_ukf.sigma_gyro_rps must be >= 0");
  if (t->get("sigma_gyro_bias_rps") && !(a.sigma_gyro_bias_rps >= 0))
    st::fail(source, "aid_ukf.sigma_gyro_bias_rps must be >= 0");
  if (!(a.average_s >= 0) || a.average_s > a.update_period_s)
    st::fail(source, "aid_ukf.average_s must be in [0, update_period_s]");
  if (a.enabled && a.maps.empty()) st::fail(source, "aid_ukf.enabled needs aid_ukf.map (the onboard tiles)");
  if (!(a.update_period_s > 0)) st::fail(source, "aid_ukf.update_period_s must be > 0");
  return a;
}

}  // namespace ggins::truth3d
