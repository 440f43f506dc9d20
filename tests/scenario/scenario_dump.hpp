// Every field of a parsed 2-D / 3-D scenario, one "path = value" line each, numbers
// with 17 significant digits (exact for doubles). Listed here by hand, field by field,
// independently of the scenario schema: a field the schema forgets to read shows up
// as a difference against the dumps of the built-in scenarios recorded from the
// parsers before they went through the schema (tests/scenario/golden/*.txt).
#pragma once

#include <cstdio>
#include <sstream>
#include <string>

#include "ggins/truth/scenario.hpp"
#include "ggins/truth3d/scenario3d.hpp"

namespace scenario_dump {

class Dump {
 public:
  void v(const std::string& k, double x) {
    char b[64];
    std::snprintf(b, sizeof b, "%.17g", x);
    os_ << k << " = " << b << "\n";
  }
  void v(const std::string& k, int64_t x) { os_ << k << " = " << x << "\n"; }
  void v(const std::string& k, uint64_t x) { os_ << k << " = " << x << "\n"; }
  void v(const std::string& k, int x) { os_ << k << " = " << x << "\n"; }
  void v(const std::string& k, bool x) { os_ << k << " = " << (x ? "true" : "false") << "\n"; }
  void v(const std::string& k, const std::string& x) { os_ << k << " = \"" << x << "\"\n"; }
  template <class A>
  void arr(const std::string& k, const A& a) {
    for (size_t i = 0; i < a.size(); ++i) v(k + "[" + std::to_string(i) + "]", a[i]);
  }
  std::string str() const { return os_.str(); }

 private:
  std::ostringstream os_;
};

inline void anomaly(Dump& d, const ggins::truth::AnomalyParams& a) {
  d.v("gravity.anomaly.seed", a.seed);
  d.v("gravity.anomaly.lat_deg", a.lat_deg);
  d.v("gravity.anomaly.lon_deg", a.lon_deg);
  d.v("gravity.anomaly.half_size_m", a.half_size_m);
  d.v("gravity.anomaly.ref_height_m", a.ref_height_m);
  d.v("gravity.anomaly.rms_arcsec", a.rms_arcsec);
  d.v("gravity.anomaly.corr_length_m", a.corr_length_m);
  d.v("gravity.anomaly.ewald_sigma_m", a.ewald_sigma_m);
  d.v("gravity.anomaly.lattice_spacing_m", a.lattice_spacing_m);
  d.v("gravity.anomaly.lattice_points", a.lattice_points);
}

inline void accel(Dump& d, const ggins::truth::AccelErrorParams& a) {
  d.v("accel.seed", a.seed);
  d.v("accel.bias_sigma_mps2", a.bias_sigma_mps2);
  d.v("accel.noise_sigma_mps2", a.noise_sigma_mps2);
  d.v("accel.scale_sigma", a.scale_sigma);
  for (size_t i = 0; i < a.bias_mps2.size(); ++i) d.arr("accel.bias_mps2[" + std::to_string(i) + "]", a.bias_mps2[i]);
  for (size_t i = 0; i < a.scale.size(); ++i) d.arr("accel.scale[" + std::to_string(i) + "]", a.scale[i]);
}

inline void firmware(Dump& d, const ggins::truth::FirmwareParams& f) {
  d.v("firmware.f_max_mps2", f.f_max_mps2);
  d.v("firmware.asym_max_ps2", f.asym_max_ps2);
  d.v("firmware.dt_tol_us", f.dt_tol_us);
  d.v("firmware.gravdr_trapezoid_only", f.gravdr_trapezoid_only);
  d.v("firmware.fdi_parity_f_max_mps2", f.fdi_parity_f_max_mps2);
  d.v("firmware.fdi_asym_max_ps2", f.fdi_asym_max_ps2);
  d.v("firmware.fdi_parity_f_max_set", f.fdi_parity_f_max_set);
  d.v("firmware.fdi_asym_max_set", f.fdi_asym_max_set);
  d.v("firmware.acc_frozen_frames", f.acc_frozen_frames);
  d.v("firmware.acc_frozen_frames_set", f.acc_frozen_frames_set);
}

inline void baro(Dump& d, const ggins::truth::BaroParams& b) {
  d.v("baro.enable", b.enable);
  d.v("baro.seed", b.seed);
  d.v("baro.rate_hz", b.rate_hz);
  d.v("baro.bias_m", b.bias_m);
  d.v("baro.gm_sigma_m", b.gm_sigma_m);
  d.v("baro.gm_tau_s", b.gm_tau_s);
  d.v("baro.noise_sigma_m", b.noise_sigma_m);
  d.v("baro.dropout_prob", b.dropout_prob);
  for (size_t i = 0; i < b.dropouts.size(); ++i) d.arr("baro.dropouts[" + std::to_string(i) + "]", b.dropouts[i]);
  d.v("baro.outlier_prob", b.outlier_prob);
  d.v("baro.outlier_m", b.outlier_m);
  d.v("baro.invalid_prob", b.invalid_prob);
  d.v("baro.latency_s", b.latency_s);
}

inline void baro_loop(Dump& d, const ggins::truth::BaroLoopParams& l) {
  d.v("navigation.baro.enable", l.enable);
  d.arr("navigation.baro.poles_radps", l.poles_radps);
  d.v("navigation.baro.period_s", l.period_s);
  d.v("navigation.baro.omega_s2", l.omega_s2);
  d.v("navigation.baro.max_age_s", l.max_age_s);
  d.v("navigation.baro.coast_s", l.coast_s);
  d.v("navigation.baro.alt_min_m", l.alt_min_m);
  d.v("navigation.baro.alt_max_m", l.alt_max_m);
  d.v("navigation.baro.gate_m", l.gate_m);
  d.v("navigation.baro.max_rejects", l.max_rejects);
}

inline std::string dump(const ggins::truth::Scenario& s) {
  Dump d;
  d.v("name", s.name);
  d.v("description", s.description);
  d.v("trajectory.type", s.trajectory.type);
  d.v("trajectory.speed_mps", s.trajectory.speed_mps);
  d.v("trajectory.height_m", s.trajectory.height_m);
  d.v("trajectory.lat0_deg", s.trajectory.lat0_deg);
  d.v("trajectory.radius_m", s.trajectory.radius_m);
  d.v("gravity.model", s.gravity.model);
  d.v("gravity.gm_m3ps2", s.gravity.gm_m3ps2);
  anomaly(d, s.gravity.anomaly);
  d.v("platform.a_m", s.a_m);
  d.v("platform.b_m", s.b_m);
  d.v("time.duration_s", s.duration_s);
  d.v("time.rate_hz", s.rate_hz);
  accel(d, s.accel);
  firmware(d, s.firmware);
  const auto& t = s.transport;
  d.v("transport.seed", t.seed);
  d.v("transport.drop_prob", t.drop_prob);
  d.v("transport.duplicate_prob", t.duplicate_prob);
  d.v("transport.reorder_prob", t.reorder_prob);
  d.v("transport.output_drop_prob", t.output_drop_prob);
  d.v("transport.garbage_prob", t.garbage_prob);
  d.v("output.csv_rate_hz", s.output.csv_rate_hz);
  d.v("output.truth_rate_hz", s.output.truth_rate_hz);
  const auto& n = s.navigation;
  d.v("navigation.gravity", n.gravity);
  d.v("navigation.r_ref_m", n.r_ref_m);
  d.v("navigation.model.set", n.model.set);
  d.v("navigation.model.gm_m3ps2", n.model.gm_m3ps2);
  d.v("navigation.model.a_m", n.model.a_m);
  d.arr("navigation.model.j", n.model.j);
  const auto& g = n.survey;
  d.v("navigation.survey.enable", g.enable);
  d.v("navigation.survey.seed", g.seed);
  d.v("navigation.survey.spacing_m", g.spacing_m);
  d.v("navigation.survey.margin_m", g.margin_m);
  d.v("navigation.survey.n_rho", g.n_rho);
  d.v("navigation.survey.drho_m", g.drho_m);
  d.v("navigation.survey.noise_gravity_mgal", g.noise_gravity_mgal);
  d.v("navigation.survey.noise_deflection_arcsec", g.noise_deflection_arcsec);
  baro_loop(d, n.baro);
  baro(d, s.baro);
  d.v("sensor_faults.seed", s.sensor_faults.seed);
  for (size_t i = 0; i < s.sensor_faults.faults.size(); ++i) {
    const auto& f = s.sensor_faults.faults[i];
    const std::string w = "sensor_faults.fault[" + std::to_string(i) + "].";
    d.v(w + "kind", f.kind);
    d.v(w + "sensor", f.sensor);
    d.v(w + "axis", f.axis);
    d.v(w + "start_s", f.start_s);
    d.v(w + "duration_s", f.duration_s);
    d.v(w + "size", f.size);
    d.v(w + "prob", f.prob);
  }
  return d.str();
}

inline std::string dump(const ggins::truth3d::Scenario3& s) {
  Dump d;
  d.v("name", s.name);
  d.v("description", s.description);
  const auto& r = s.trajectory;
  d.v("trajectory.type", r.type);
  for (size_t i = 0; i < r.waypoints.size(); ++i) {
    const auto& q = r.waypoints[i];
    const std::string w = "trajectory.waypoint[" + std::to_string(i) + "].";
    d.v(w + "lat_deg", q.lat_deg);
    d.v(w + "lon_deg", q.lon_deg);
    d.v(w + "height_m", q.height_m);
    d.v(w + "speed_mps", q.speed_mps);
    d.v(w + "turn_rate_dps", q.turn_rate_dps);
    d.v(w + "climb_rate_mps", q.climb_rate_mps);
    d.v(w + "accel_mps2", q.accel_mps2);
    d.v(w + "vertical_accel_mps2", q.vertical_accel_mps2);
    d.v(w + "line", q.line);
  }
  d.v("trajectory.initial_speed_mps", r.initial_speed_mps);
  d.v("trajectory.turn_rate_dps", r.turn_rate_dps);
  d.v("trajectory.climb_rate_mps", r.climb_rate_mps);
  d.v("trajectory.accel_mps2", r.accel_mps2);
  d.v("trajectory.vertical_accel_mps2", r.vertical_accel_mps2);
  d.v("trajectory.lat_deg", r.lat_deg);
  d.v("trajectory.lon_deg", r.lon_deg);
  d.v("trajectory.height_m", r.height_m);
  d.arr("trajectory.velocity_ned_mps", r.velocity_ned_mps);
  for (size_t i = 0; i < r.maneuvers.size(); ++i) {
    const auto& m = r.maneuvers[i];
    const std::string w = "trajectory.maneuver[" + std::to_string(i) + "].";
    d.v(w + "t_s", m.t_s);
    d.v(w + "duration_s", m.duration_s);
    d.arr(w + "dv_ned_mps", m.dv_ned_mps);
  }
  d.v("trajectory.radius_m", r.radius_m);
  d.v("trajectory.speed_mps", r.speed_mps);
  d.v("trajectory.spin_radps", r.spin_radps);
  d.v("trajectory.precession_radps", r.precession_radps);
  d.v("trajectory.nutation_deg", r.nutation_deg);
  d.v("trajectory.nutation_amp_deg", r.nutation_amp_deg);
  d.v("trajectory.nutation_radps", r.nutation_radps);
  d.v("trajectory.psi0_deg", r.psi0_deg);
  d.v("trajectory.phi0_deg", r.phi0_deg);
  d.v("platform.kind", s.platform);
  d.v("platform.a_m", s.a_m);
  d.v("platform.b_m", s.b_m);
  d.v("platform.c_m", s.c_m);
  d.v("gravity.model", s.gravity.model);
  d.v("gravity.gm_m3ps2", s.gravity.gm_m3ps2);
  anomaly(d, s.gravity.anomaly);
  d.v("gravity.sh.path", s.sh.path);
  d.v("gravity.sh.nmax", s.sh.nmax);
  d.v("gravity.sh.lattice_spacing_m", s.sh.lattice_spacing_m);
  d.v("gravity.sh.lattice_points", s.sh.lattice_points);
  d.v("time.duration_s", s.duration_s);
  d.v("time.rate_hz", s.rate_hz);
  accel(d, s.accel);
  const auto& y = s.gyro;
  d.v("gyro.seed", y.seed);
  d.v("gyro.bias_sigma_radps", y.bias_sigma_radps);
  d.v("gyro.noise_sigma_radps", y.noise_sigma_radps);
  d.v("gyro.scale_sigma", y.scale_sigma);
  d.arr("gyro.bias_radps", y.bias_radps);
  d.arr("gyro.scale", y.scale);
  baro(d, s.baro);
  d.v("navigation.gravity", s.nav_gravity);
  baro_loop(d, s.nav_baro);
  firmware(d, s.firmware);
  d.v("firmware.fdi_parity_f_max_mps2(3d)", s.fdi_parity_f_max_mps2);
  d.arr("initial_error.position_ned_m", s.initial_error.position_ned_m);
  d.arr("initial_error.velocity_ned_mps", s.initial_error.velocity_ned_mps);
  d.arr("initial_error.attitude_ned_rad", s.initial_error.attitude_ned_rad);
  d.v("output.csv_rate_hz", s.csv_rate_hz);
  d.v("sensor_faults.seed", s.sensor_faults.seed);
  for (size_t i = 0; i < s.sensor_faults.faults.size(); ++i) {
    const auto& f = s.sensor_faults.faults[i];
    const std::string w = "sensor_faults.fault[" + std::to_string(i) + "].";
    d.v(w + "kind", f.kind);
    d.v(w + "sensor", f.sensor);
    d.v(w + "axis", f.axis);
    d.v(w + "start_s", f.start_s);
    d.v(w + "duration_s", f.duration_s);
    d.v(w + "size", f.size);
    d.v(w + "prob", f.prob);
  }
  const auto& a = s.aid_ukf;
  d.v("aid_ukf.enabled", a.enabled);
  d.arr("aid_ukf.map", a.maps);
  d.v("aid_ukf.update_period_s", a.update_period_s);
  d.v("aid_ukf.max_passes", a.max_passes);
  d.v("aid_ukf.sigma_meas_E", a.sigma_meas_E);
  d.v("aid_ukf.sigma_db_E", a.sigma_db_E);
  d.v("aid_ukf.offdiag_ratio", a.offdiag_ratio);
  d.v("aid_ukf.sig0_pos_m", a.sig0_pos_m);
  d.v("aid_ukf.sig0_vel_mps", a.sig0_vel_mps);
  d.v("aid_ukf.sig0_att_rad", a.sig0_att_rad);
  d.v("aid_ukf.sig0_g_mps2", a.sig0_g_mps2);
  d.v("aid_ukf.q_vel_mps_rts", a.q_vel_mps_rts);
  d.v("aid_ukf.q_att_rad_rts", a.q_att_rad_rts);
  d.v("aid_ukf.q_g_mps2_rts", a.q_g_mps2_rts);
  d.v("aid_ukf.lambda", a.lambda);
  d.v("aid_ukf.gate_nis", a.gate_nis);
  d.v("aid_ukf.average_s", a.average_s);
  d.v("aid_ukf.sigma_gyro_rps", a.sigma_gyro_rps);
  d.v("aid_ukf.sigma_gyro_bias_rps", a.sigma_gyro_bias_rps);
  d.v("aid_ukf.bias_states", a.bias_states);
  d.v("aid_ukf.sig0_gyro_bias_rps", a.sig0_gyro_bias_rps);
  d.v("aid_ukf.sig0_acc_bias_mps2", a.sig0_acc_bias_mps2);
  d.v("aid_ukf.q_gyro_bias_rps_rts", a.q_gyro_bias_rps_rts);
  d.v("aid_ukf.q_acc_bias_mps2_rts", a.q_acc_bias_mps2_rts);
  d.v("aid_ukf.sigma_baro_m", a.sigma_baro_m);
  return d.str();
}

}  // namespace scenario_dump
