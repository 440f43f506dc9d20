#include "ggins/truth3d/config3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <Eigen/Geometry>

#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth/config2d.hpp"

namespace ggins::truth3d {

gg_nav3d_config_t config3d(const Scenario3& s, const Generator3& g) {
  gg_nav3d_config_t c;
  std::memset(&c, 0, sizeof c);
  c.geometry.half_base_m[0] = s.a_m;
  c.geometry.half_base_m[1] = s.b_m;
  c.geometry.half_base_m[2] = s.c_m;
  c.platform = s.strapdown() ? GG_PLATFORM_STRAPDOWN : GG_PLATFORM_STABILIZED;
  c.dt_us = s.dt_us();
  c.dt_tol_us = s.firmware.dt_tol_us;
  const Truth3 t0 = g.truth(0);
  // [initial_error] (x = true - estimate): estimate = truth - x, NED axes of the true start
  const Mat3 C_n_e = ned_to_ecef(t0.s.lat, t0.s.lon);
  const InitialError3 ie = s.initial_error_flown();  // the fixed errors plus the run's [draw]
  const Vec3 dr_e = C_n_e * Vec3(ie.position_ned_m[0], ie.position_ned_m[1], ie.position_ned_m[2]);
  const Vec3 dv_e = C_n_e * Vec3(ie.velocity_ned_mps[0], ie.velocity_ned_mps[1], ie.velocity_ned_mps[2]);
  const Vec3 psi_e = C_n_e * Vec3(ie.attitude_ned_rad[0], ie.attitude_ned_rad[1], ie.attitude_ned_rad[2]);
  for (int i = 0; i < 3; ++i) {
    c.r0_e[i] = t0.s.r_e(i) - dr_e(i);
    c.v0_e[i] = t0.s.v_e(i) - dv_e(i);
    c.g0_e[i] = t0.g_e(i);
  }
  Mat3 C_est = t0.s.C_b_e;
  if (psi_e.norm() > 0) C_est = Eigen::AngleAxis<Real>(-psi_e.norm(), psi_e / psi_e.norm()).toRotationMatrix() * C_est;
  const auto q = quat_from_dcm(C_est);
  for (int i = 0; i < 4; ++i) c.q0_b_e[i] = q[static_cast<size_t>(i)];
  // the Earth rate of the truth flown (nav3d.h: negative for a non-rotating Earth)
  const Real w_ie = g.trajectory().omega_ie();
  c.omega_ie = w_ie > 0 ? w_ie : -1.0L;
  c.f_max = s.firmware.f_max_mps2;
  c.asym_max = s.firmware.asym_max_ps2;
  c.fdi_parity_f_max = s.fdi_parity_f_max_mps2;
  c.acc_frozen_frames = static_cast<int32_t>(s.firmware.acc_frozen_frames);
  c.gravity_mode = s.nav_gravity == "model" ? GG_GRAVITY_MODEL : GG_GRAVITY_GRADIOMETER;
  if (s.gravity.model == "point-mass") {
    c.model.gm = s.gravity.gm_m3ps2;
    c.model.a_m = gravity::wgs84::kA;
  } else {  // the WGS-84 normal field's zonal series J2..J8
    const gravity::NormalField n;
    c.model.gm = n.params().gm;
    c.model.a_m = n.params().a;
    for (int k = 1; 2 * k <= 8 && 2 * k <= GG_GMODEL_MAX_DEGREE; ++k) c.model.j[2 * k] = n.j2n(k);
  }
  c.baro_enable = s.baro_loop_enabled() ? 1 : 0;
  const auto& l = s.nav_baro;
  truth::vchan_config(l, s.baro_period_s(), l.omega_s2 > 0 ? static_cast<Real>(l.omega_s2) : t0.g_e.norm() / t0.s.r_e.norm(),
                      c.baro);
  // the gyro as the filter knows it: the fixed values and the draw's values (one sigma or
  // magnitude per axis), never the draw's outcome
  GyroErrorParams known = s.gyro;
  const double dmax = *std::max_element(s.draw.gyro_bias_radps.begin(), s.draw.gyro_bias_radps.end());
  known.bias_sigma_radps = std::hypot(known.bias_sigma_radps, dmax);
  apply_aid_ukf(s.aid_ukf, s.rate_hz, known, s.baro.noise_sigma_m, c);  // [aid_ukf], aids3d.cpp
  PfImu imu;  // the same knowledge for the particle filter's model
  double bg = 0;  // the largest fixed gyro bias, magnitude
  for (const double b : s.gyro.bias_radps) bg = std::max(bg, std::fabs(b));
  imu.gyro_bias_radps = std::hypot(known.bias_sigma_radps, bg);
  imu.gyro_noise_radps = s.gyro.noise_sigma_radps;
  double ab2 = 0;  // the largest horizontal fixed bias of one accelerometer
  for (const auto& b : s.accel.bias_mps2) ab2 = std::max(ab2, b[0] * b[0] + b[1] * b[1]);
  const double da = std::hypot(s.draw.accel_common_bias_mps2[0], s.draw.accel_common_bias_mps2[1]);
  imu.accel_bias_mps2 = std::sqrt(ab2 + 2.0 * s.accel.bias_sigma_mps2 * s.accel.bias_sigma_mps2 + da * da);
  imu.accel_noise_mps2 = s.accel.noise_sigma_mps2;
  imu.rate_hz = s.rate_hz;
  apply_aid_pf(s.aid_pf, s.coldatom, imu, c);      // [aid_pf] with [coldatom], coldatom3d.cpp
  return c;
}

gg_nav3d_config_t config3d(const Scenario3& s) { return config3d(s, Generator3(s)); }

}  // namespace ggins::truth3d
