#include "sim3d.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "ggins/covariance/cov3d_truth3d.hpp"
#include "ggins/truth3d/config3d.hpp"
extern "C" {
#include "ggins/quat.h"
}

namespace ggins::montecarlo3d {

using covariance::skew;

namespace {

// The firmware settings of a run as a 3-D scenario, for the one scenario -> configuration
// mapping (truth3d::config3d): the covariance scenario's platform, half-baselines, rate and
// barometric loop (its poles, period and omega_s2; the gate wide open at 1e4 m, a sample valid for
// one period, coasting for ten), gravity from the gradiometers; accelerometer range 100 m/s^2,
// parity flag threshold 1 s^-2 and the pair-mean fault detection off (the seeded biases raise no
// flag), the step tolerance a tenth of the step. omega_s2 = 0 takes the model's value
// |G(r0)| / |r0| in double (nav3d_model.cpp), so that firmware and model run the same loop.
truth3d::Scenario3 firmware_scenario(const Cov3DScenario& s, double rate_hz, int64_t dt_us, const truth3d::Truth3& t0) {
  truth3d::Scenario3 f;
  f.name = s.name;
  f.source = s.source;
  f.platform = s.platform == covariance::Platform::kStrapdown ? "strapdown" : "stabilized";
  f.a_m = s.model.half_base_m[0];
  f.b_m = s.model.half_base_m[1];
  f.c_m = s.model.half_base_m[2];
  f.rate_hz = rate_hz;
  f.duration_s = s.duration_s;
  f.nav_gravity = "gradiometer";
  if (s.field == "point-mass") f.gravity.model = "point-mass";
  f.firmware.f_max_mps2 = 100.0;
  f.firmware.asym_max_ps2 = 1.0;
  f.firmware.asym_max_set = true;  // given (not derived), and so written in the scenario it prints
  f.firmware.dt_tol_us = dt_us / 10;
  f.fdi_parity_f_max_mps2 = 0;  // off, and so written in the scenario it prints
  f.fdi_parity_f_max_set = true;
  f.nav_baro.enable = s.model.baro.on ? 1 : 0;
  if (s.model.baro.on) {
    auto& l = f.nav_baro;
    l.poles_radps = s.model.baro.poles_radps;
    l.period_s = s.model.baro.period_s;
    l.omega_s2 = s.model.baro.omega_s2 > 0 ? s.model.baro.omega_s2 : double(t0.g_e.norm() / t0.s.r_e.norm());
    l.max_age_s = l.period_s;
    l.coast_s = 10 * l.period_s;
    l.alt_min_m = -1000;
    l.alt_max_m = 30000;
    l.gate_m = 1e4;
    l.max_rejects = 5;
  }
  return f;
}

}  // namespace

Sim3D::Sim3D(const Cov3DScenario& s, double rate_hz) : s_(s) {
  field_ = covariance::make_field3d(s);
  model_ = covariance::make_model3d(s);
  dt_us_ = std::llround(1e6 / rate_hz);
  if (dt_us_ <= 0 || std::abs(1e6 / double(dt_us_) - rate_hz) > 1e-9 * rate_hz)
    throw std::invalid_argument("Sim3D: rate must give a whole number of microseconds");
  // the truth trajectory of the frames: a truth3d scenario's own, or the great circle of the built-ins
  traj_ = covariance::truth3d_trajectory(s);
  if (!traj_) {
    truth3d::GreatCircleParams g;
    g.radius_m = s.radius_m;
    g.height_m = s.height_m;
    g.lat0 = Real(s.lat0_deg) * (truth3d::kPi / 180.0L);
    g.lon0 = Real(s.lon0_deg) * (truth3d::kPi / 180.0L);
    g.heading = Real(s.heading_deg) * (truth3d::kPi / 180.0L);
    g.speed_mps = s.speed_mps;
    g.omega_ie = s.omega_ie;
    traj_ = std::make_shared<truth3d::GreatCircle3>(
        g, s.platform == covariance::Platform::kStrapdown ? truth3d::Attitude::Coordinated : truth3d::Attitude::Stabilized);
  }
  fw_ = firmware_scenario(s, rate_hz, dt_us_, generator(SensorErrors{}, 1).truth(0));
}

truth3d::Generator3 Sim3D::generator(const SensorErrors& e, int64_t n_steps) const {
  truth3d::Generator3Options o;
  for (size_t j = 0; j < 3; ++j) o.half_base[j] = Real(s_.model.half_base_m[j]);
  o.dt_us = dt_us_;
  o.n_steps = n_steps;
  // the drawn errors as the sensor models' fixed values (truth/sensors.hpp), noise seeded per run
  for (size_t i = 0; i < 6; ++i)
    for (size_t j = 0; j < 3; ++j) o.accel.bias_mps2[i][j] = e.acc_bias[3 * i + j];
  o.accel.noise_sigma_mps2 = e.acc_noise;
  o.accel.seed = e.noise_seed;
  const bool sd = s_.platform == covariance::Platform::kStrapdown;
  if (sd) {
    o.gyro.bias_radps = e.gyro_bias;
    o.gyro.noise_sigma_radps = e.gyro_noise;
  }
  o.gyro.seed = e.noise_seed;
  if (s_.model.baro.on) {
    o.baro.enable = true;
    o.baro.rate_hz = 1.0 / s_.model.baro.period_s;
    o.baro.seed = e.noise_seed;
    o.baro.bias_m = e.baro_bias_m;
    o.baro.gm_sigma_m = e.baro_gm_sigma_m;
    o.baro.gm_tau_s = e.baro_gm_tau_s;
    o.baro.noise_sigma_m = e.baro_noise_m;
  }
  return truth3d::Generator3(traj_, field_, o);
}

gg_nav3d_config_t Sim3D::config(const SensorErrors& e) const {
  const truth3d::Generator3 g0 = generator(SensorErrors{}, 1);
  const truth3d::Truth3 t0 = g0.truth(0);
  gg_nav3d_config_t c = truth3d::config3d(fw_, g0);
  for (int j = 0; j < 3; ++j) {
    c.r0_e[j] += e.dr0[size_t(j)];
    c.v0_e[j] += e.dv0[size_t(j)];
    c.g0_e[j] += e.dg0[size_t(j)];
  }
  const Vec3 psi(e.dpsi0[0], e.dpsi0[1], e.dpsi0[2]);
  if (psi.norm() > 0) {  // C^ = exp(-[psi x]) C (exact rotation; the small-angle form to first order)
    const Real a = psi.norm();
    const Mat3 K = skew(psi / a);
    const Mat3 R = Mat3::Identity() - std::sin(a) * K + (1 - std::cos(a)) * K * K;
    const std::array<Real, 4> q = truth3d::quat_from_dcm(Mat3(R * t0.s.C_b_e));
    for (int i = 0; i < 4; ++i) c.q0_b_e[i] = q[size_t(i)];
  }
  return c;
}

std::vector<ErrSample> Sim3D::fly(const SensorErrors& e, double duration_s, double output_dt_s,
                                  FlyCounts* counts, const std::function<bool()>& stop) const {
  gg_nav3d_t nav;
  const gg_nav3d_config_t cfg = config(e);
  if (gg_nav3d_init(&nav, &cfg) != GG_OK) throw std::runtime_error("gg_nav3d_init failed");
  const int64_t K = std::llround(duration_s * 1e6 / double(dt_us_));
  const int64_t every = std::max<int64_t>(1, std::llround(output_dt_s * 1e6 / double(dt_us_)));
  const truth3d::Generator3 gen = generator(e, K + 1);
  std::vector<ErrSample> out;
  gg_frame_t fr;
  gg_nav3d_output_t o;
  for (int64_t k = 0; k <= K; ++k) {
    if (stop && k % 256 == 0 && stop()) {
      if (counts) counts->stopped = true;
      break;
    }
    truth3d::Truth3 t;
    gen.frame(k, fr, &t);
    const gg_status_t st = gg_nav3d_step(&nav, &fr, nullptr, &o);
    if (st != GG_OK) throw std::runtime_error("gg_nav3d_step failed at step " + std::to_string(k));
    if (counts) {
      ++counts->steps;
      counts->health_or |= o.health;
      for (size_t b = 0; b < 32; ++b)
        if (o.health & (1u << b)) ++counts->health_count[b];
    }
    if (k % every == 0 || k == K) {
      ErrSample s;
      s.t = double(t.t_s);
      for (int j = 0; j < 3; ++j) {
        s.dr(j) = double((Real(o.r_e[j]) + Real(o.r_e_lo[j])) - t.s.r_e(j));
        s.dv(j) = double(Real(o.v_e[j]) - t.s.v_e(j));
        s.dg(j) = double((Real(o.g_e[j]) + Real(o.g_e_lo[j])) - t.g_e(j));
      }
      gg_real_t q[4] = {o.q_b_e[0], o.q_b_e[1], o.q_b_e[2], o.q_b_e[3]}, c[3][3];
      gg_quat_to_dcm(q, c);  // firmware quat.h
      Mat3 Cq;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) Cq(i, j) = c[i][j];
      const Mat3 A = Cq * t.s.C_b_e.transpose();  // = I - [psi x]
      const Mat3 Psi = (A.transpose() - A) / 2;
      s.psi = Eigen::Vector3d(double(Psi(2, 1)), double(Psi(0, 2)), double(Psi(1, 0)));
      s.a_c = o.g_up_corr;
      out.push_back(s);
    }
  }
  return out;
}

}  // namespace ggins::montecarlo3d
