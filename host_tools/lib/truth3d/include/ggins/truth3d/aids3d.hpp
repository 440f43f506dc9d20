// The aiding sources of a 3-D scenario, as the scenario file states them (read once, by
// parse_scenario3, into Scenario3::aid_ukf); src/aids3d.cpp maps them onto the firmware
// configuration (apply_aid_ukf, config3d.hpp). One table per aid source:
//
//   [aid_ukf]
//   enabled = true
//   map = ["tile.bin", ...]    # gmap tiles (ggins gmap) for the computer's map storage;
//                              # relative paths: from the scenario file's directory
//   map_from_field = false     # or: tiles built by the runner from the scenario's own
//                              # [gravity] field along the route, plus database noise
//   map_spacing_deg = 0.02, map_margin_deg = 0.1, map_noise_E = 0.001, map_seed = 1
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
//   sigma_gyro_bias_rps        # gyro bias one-sigma, rad/s: its share of R (without bias
//                              # states); default [gyro] bias_sigma_radps (+ the largest
//                              # |bias_radps| entry, + the largest [draw] gyro_bias_radps)
//   bias_states = false        # gyro and accelerometer bias states (18 states with dead
//                              # reckoning, 15 in model mode): the task subtracts its estimates
//   sig0_gyro_bias_rps, sig0_acc_bias_mps2            # their initial one-sigma (Gao Table 1)
//   q_gyro_bias_rps_rts, q_acc_bias_mps2_rts          # their random walks
//   sigma_baro_m               # barometer white noise of one sample, m: the baro loop's share
//                              # of Q (the loop is in the aid's error model); default [baro] noise_sigma_m
//   integrity = true, integrity_window = 8, ...       # the integrity monitor (integrity3d.hpp)
#pragma once

#include <cstdint>
#include <string>
#include <vector>
#include <toml++/toml.h>

#include "ggins/truth/scenario_schema.hpp"
#include "ggins/truth3d/integrity3d.hpp"

namespace ggins::truth3d {

struct AidUkf3 : Integrity3 {
  bool enabled = false;
  std::vector<std::string> maps;  // as written in the scenario
  // the onboard map built from the scenario's field (ggins run3d: field_map.hpp)
  bool map_from_field = false;
  double map_spacing_deg = 0.02;  // node spacing in latitude and longitude
  double map_margin_deg = 0.1;    // around the route, and the overlap of neighbouring tiles
  double map_noise_E = 0.001;     // database noise added to each tensor component of a node
  uint64_t map_seed = 1;
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
  double sigma_gyro_rps = -1.0;       // < 0: from the scenario's [gyro] (apply_aid_ukf)
  double sigma_gyro_bias_rps = -1.0;  // < 0: from the scenario's [gyro]
  bool bias_states = false;
  double sig0_gyro_bias_rps = 4.85e-8;  // 0.01 deg/h (Gao Table 1)
  double sig0_acc_bias_mps2 = 9.8e-5;   // 10 ug (Gao Table 1)
  double q_gyro_bias_rps_rts = 0.0;
  double q_acc_bias_mps2_rts = 0.0;
  double sigma_baro_m = -1.0;  // < 0: from the scenario's [baro] noise_sigma_m
};

// The map files with relative names resolved against the scenario's directory.
std::vector<std::string> aid_ukf_map_paths(const AidUkf3& a, const std::string& scenario_source);

// The [aid_ukf] table of a scenario (scenario_schema.hpp): absent, the defaults (aid off).
inline truth::sch::Table<AidUkf3> aid_ukf_table() {
  namespace sch = truth::sch;
  using A = AidUkf3;
  sch::Table<A> t("aid_ukf", "The gradient-map aid: map-matching UKF on the gradiometer (aid_mmukf.h).");
  sch::Key<A> map = sch::mk<A>("map", "string or array of strings", "", "file names",
                               "gmap tiles (ggins gmap) for the computer's map storage; relative paths from the "
                               "scenario file's directory", "");
  map.read = [](A& a, const toml::node& n, const sch::Ctx& c, const std::string& p) {
    if (n.is_string()) {
      a.maps.push_back(n.as_string()->get());
    } else if (const toml::array* arr = n.as_array()) {
      for (const auto& e : *arr) {
        if (!e.is_string()) c.fail_at(&e, p, p + " = " + sch::value_text(n) + ": must be a file name or a list of them");
        a.maps.push_back(e.as_string()->get());
      }
    } else {
      c.fail_at(&n, p, p + " = " + sch::value_text(n) + ": must be a file name or a list of them");
    }
  };
  map.write = [](const A& a) -> std::optional<std::string> {
    std::string s = "[";
    for (size_t i = 0; i < a.maps.size(); ++i) s += (i ? ", " : "") + sch::str_text(a.maps[i]);
    return s + "]";
  };
  t.boolean("enabled", &A::enabled, "the aid runs (needs map or map_from_field)")
      .custom(map)
      .default_doc("map", "[] (none)")
      .boolean("map_from_field", &A::map_from_field,
               "the onboard map built by the runner from the scenario's own [gravity] field along the route "
               "(tiles of the whole tensor and its height derivatives in <out>/maps/aid_ukf/, at the route's mid "
               "height, plus database noise) instead of map files")
      .num("map_spacing_deg", &A::map_spacing_deg, "deg", sch::in(0.001, 1), "map_from_field: node spacing")
      .num("map_margin_deg", &A::map_margin_deg, "deg", sch::in(0, 5),
           "map_from_field: margin around the route and overlap of neighbouring tiles")
      .num("map_noise_E", &A::map_noise_E, "E", sch::in(0, 1e3),
           "map_from_field: database noise, one sigma, on each tensor component of a node")
      .seed("map_seed", &A::map_seed, "map_from_field: seed of the database noise")
      .num("update_period_s", &A::update_period_s, "s", sch::in_lopen(0, 1e6), "time between epochs")
      .integer("max_passes", &A::max_passes, "", sch::in(1, 100), "progressive update passes")
      .num("sigma_meas_E", &A::sigma_meas_E, "E", sch::in_lopen(0, 1e6),
           "gradiometer noise of a diagonal component (Gao: 0.01 E)")
      .num("sigma_db_E", &A::sigma_db_E, "E", sch::in(0, 1e6), "map noise (Gao: 0.001 E)")
      .num("offdiag_ratio", &A::offdiag_ratio, "1", sch::in(0, 10),
           "off-diagonal / diagonal noise (six differenced accelerometers)")
      .num("sig0_pos_m", &A::sig0_pos_m, "m", sch::in_lopen(0, 1e7), "initial position sigma")
      .num("sig0_vel_mps", &A::sig0_vel_mps, "m/s", sch::in_lopen(0, 1e4), "initial velocity sigma")
      .num("sig0_att_rad", &A::sig0_att_rad, "rad", sch::in_lopen(0, 10), "initial attitude sigma")
      .num("sig0_g_mps2", &A::sig0_g_mps2, "m/s^2", sch::in_lopen(0, 100), "initial gravity sigma")
      .num("q_vel_mps_rts", &A::q_vel_mps_rts, "m/s/sqrt(s)", sch::in(0, 1e3), "velocity process noise")
      .num("q_att_rad_rts", &A::q_att_rad_rts, "rad/sqrt(s)", sch::in(0, 10), "attitude process noise")
      .num("q_g_mps2_rts", &A::q_g_mps2_rts, "m/s^2/sqrt(s)", sch::in(0, 100), "gravity process noise")
      .num("lambda", &A::lambda, "1", sch::in(-1e3, 1e3), "UKF sigma-point spread parameter")
      .num("gate_nis", &A::gate_nis, "1", sch::in(0, 1e9), "NIS gate (chi-square, 6 dof); 0: none")
      .num("average_s", &A::average_s, "s", sch::in(0, 1e6),
           "tensors averaged into an epoch's measurement over this long before it (0: the epoch's own sample; "
           "<= update_period_s)")
      .num("sigma_gyro_rps", &A::sigma_gyro_rps, "rad/s", sch::in(0, 1),
           "gyro white noise of one navigation step's rate: its share of R ([w x]^2 removal) and of Q", -1.0,
           "gyro.noise_sigma_radps")
      .num("sigma_gyro_bias_rps", &A::sigma_gyro_bias_rps, "rad/s", sch::in(0, 1),
           "gyro bias one-sigma: its share of R (without bias states)", -1.0,
           "gyro.bias_sigma_radps + the largest |gyro.bias_radps| entry + the largest draw.gyro_bias_radps")
      .boolean("bias_states", &A::bias_states,
               "gyro and accelerometer bias states in the filter (the task subtracts its estimates from the readings)")
      .num("sig0_gyro_bias_rps", &A::sig0_gyro_bias_rps, "rad/s", sch::in_lopen(0, 1),
           "initial gyro bias sigma (bias states)")
      .num("sig0_acc_bias_mps2", &A::sig0_acc_bias_mps2, "m/s^2", sch::in_lopen(0, 1),
           "initial sigma of the accelerometers' common bias (bias states)")
      .num("q_gyro_bias_rps_rts", &A::q_gyro_bias_rps_rts, "rad/s/sqrt(s)", sch::in(0, 1),
           "gyro bias random walk (bias states)")
      .num("q_acc_bias_mps2_rts", &A::q_acc_bias_mps2_rts, "m/s^2/sqrt(s)", sch::in(0, 1),
           "accelerometer bias random walk (bias states)")
      .num("sigma_baro_m", &A::sigma_baro_m, "m", sch::in(0, 1000),
           "barometer white noise of one sample: the vertical loop's share of Q (the loop is part of the aid's "
           "error model; a bias or Gauss-Markov error is not)",
           -1.0, "baro.noise_sigma_m");
  integrity_keys(t, "map epochs");
  return t;
}

}  // namespace ggins::truth3d
