#include "sim3d.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::montecarlo3d {

using covariance::skew;

Sim3D::Sim3D(const Cov3DScenario& s, double rate_hz) : s_(s) {
  field_ = covariance::make_field3d(s);
  traj_ = covariance::make_trajectory3d(s);
  model_ = covariance::make_model3d(s);
  dt_us_ = std::llround(1e6 / rate_hz);
  if (dt_us_ <= 0 || std::abs(1e6 / double(dt_us_) - rate_hz) > 1e-9 * rate_hz)
    throw std::invalid_argument("Sim3D: rate must give a whole number of microseconds");
}

static void quat_from_dcm(const Mat3& C, Real q[4]) {  // scalar first, C = C_b_e
  const Real tr = C.trace();
  if (tr > 0) {
    const Real S = std::sqrt(tr + 1) * 2;
    q[0] = S / 4;
    q[1] = (C(2, 1) - C(1, 2)) / S;
    q[2] = (C(0, 2) - C(2, 0)) / S;
    q[3] = (C(1, 0) - C(0, 1)) / S;
  } else if (C(0, 0) > C(1, 1) && C(0, 0) > C(2, 2)) {
    const Real S = std::sqrt(1 + C(0, 0) - C(1, 1) - C(2, 2)) * 2;
    q[0] = (C(2, 1) - C(1, 2)) / S;
    q[1] = S / 4;
    q[2] = (C(0, 1) + C(1, 0)) / S;
    q[3] = (C(0, 2) + C(2, 0)) / S;
  } else if (C(1, 1) > C(2, 2)) {
    const Real S = std::sqrt(1 + C(1, 1) - C(0, 0) - C(2, 2)) * 2;
    q[0] = (C(0, 2) - C(2, 0)) / S;
    q[1] = (C(0, 1) + C(1, 0)) / S;
    q[2] = S / 4;
    q[3] = (C(1, 2) + C(2, 1)) / S;
  } else {
    const Real S = std::sqrt(1 + C(2, 2) - C(0, 0) - C(1, 1)) * 2;
    q[0] = (C(1, 0) - C(0, 1)) / S;
    q[1] = (C(0, 2) + C(2, 0)) / S;
    q[2] = (C(1, 2) + C(2, 1)) / S;
    q[3] = S / 4;
  }
}

static Mat3 dcm_from_quat(const double q[4]) {
  const Real w = q[0], x = q[1], y = q[2], z = q[3];
  Mat3 C;
  C << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y), 2 * (x * y + w * z),
      1 - 2 * (x * x + z * z), 2 * (y * z - w * x), 2 * (x * z - w * y), 2 * (y * z + w * x),
      1 - 2 * (x * x + y * y);
  return C;
}

gg_nav3d_config_t Sim3D::config(const SensorErrors& e) const {
  gg_nav3d_config_t c{};
  const covariance::Traj3DPoint p = traj_->at(0);
  const gravity::FieldSample fs = field_->eval(p.r_e);
  for (int j = 0; j < 3; ++j) c.geometry.half_base_m[j] = s_.model.half_base_m[size_t(j)];
  c.platform = s_.platform == covariance::Platform::kStrapdown ? GG_PLATFORM_STRAPDOWN : GG_PLATFORM_STABILIZED;
  c.dt_us = dt_us_;
  c.dt_tol_us = dt_us_ / 10;
  for (int j = 0; j < 3; ++j) {
    c.r0_e[j] = p.r_e(j) + e.dr0[size_t(j)];
    c.v0_e[j] = p.v_e(j) + e.dv0[size_t(j)];
    c.g0_e[j] = fs.g(j) + e.dg0[size_t(j)];
  }
  const Vec3 psi(e.dpsi0[0], e.dpsi0[1], e.dpsi0[2]);
  Mat3 C0 = p.C_b_e;
  if (psi.norm() > 0) {  // C^ = exp(-[psi x]) C (exact rotation; the small-angle form to first order)
    const Real a = psi.norm();
    const Mat3 K = skew(psi / a);
    const Mat3 R = Mat3::Identity() - std::sin(a) * K + (1 - std::cos(a)) * K * K;
    C0 = R * C0;
  }
  quat_from_dcm(C0, c.q0_b_e);
  c.omega_ie = s_.omega_ie > 0 ? Real(s_.omega_ie) : -1.0L;
  c.f_max = 100.0;
  c.asym_max = 1.0;
  c.gravity_mode = GG_GRAVITY_GRADIOMETER;
  c.baro_enable = 0;
  if (s_.model.baro.on) {
    c.baro_enable = 1;
    for (int i = 0; i < 3; ++i) c.baro.poles[i] = s_.model.baro.poles_radps[size_t(i)];
    const double ws2 = s_.model.baro.omega_s2 > 0 ? s_.model.baro.omega_s2 : double(fs.g.norm() / p.r_e.norm());
    c.baro.omega_s2 = ws2;  // the model's default too (nav3d_model.cpp)
    c.baro.period_us = std::llround(s_.model.baro.period_s * 1e6);
    c.baro.max_age_us = c.baro.period_us;
    c.baro.coast_us = 10 * c.baro.period_us;
    c.baro.alt_min_m = -1000;
    c.baro.alt_max_m = 30000;
    c.baro.gate_m = 1e4;
    c.baro.max_rejects = 5;
  }
  return c;
}

void Sim3D::frame(int64_t k, const SensorErrors& e, std::mt19937_64* rng, gg_frame_t* fr, double baro_extra_m) const {
  const Real t = Real(k) * Real(dt_us_) * 1e-6L;
  const covariance::Traj3DPoint p = traj_->at(t);
  const Real wie = traj_->omega_ie();
  const Mat3 W = skew(Vec3(0, 0, wie));
  const Vec3 a_ie = p.a_e + 2 * W * p.v_e + W * W * p.r_e;
  const Mat3 Ceb = p.C_b_e.transpose();
  const Mat3 rot = skew(p.wdot_ib_b) + skew(p.w_ib_b) * skew(p.w_ib_b);
  std::normal_distribution<double> nd(0.0, 1.0);
  *fr = gg_frame_t{};
  fr->utime = k * dt_us_;
  fr->seq = k;
  fr->n_acc = 6;
  for (int s = 0; s < 6; ++s) {
    Vec3 d = Vec3::Zero();
    d(s % 3) = (s < 3 ? 1 : -1) * Real(s_.model.half_base_m[size_t(s % 3)]);
    const Vec3 G = field_->eval(p.r_e + p.C_b_e * d).g;
    const Vec3 f = Ceb * (a_ie - G) + rot * d;
    for (int j = 0; j < 3; ++j) {
      Real fj = f(j) + Real(e.acc_bias[size_t(3 * s + j)]);
      if (rng && e.acc_noise > 0) fj += Real(e.acc_noise * nd(*rng));
      fr->f[s][j] = double(fj);
      fr->f_lo[s][j] = double(fj - Real(fr->f[s][j]));
    }
    fr->acc_status[s] = GG_SENSOR_OK;
  }
  for (int j = 0; j < 3; ++j) {
    double w = 0;
    if (s_.platform == covariance::Platform::kStrapdown) {
      w = double(p.w_ib_b(j)) + e.gyro_bias[size_t(j)];
      if (rng && e.gyro_noise > 0) w += e.gyro_noise * nd(*rng);
    }
    fr->omega_b[j] = w;
  }
  fr->gyro_status = GG_SENSOR_OK;
  fr->baro_status = GG_SENSOR_ABSENT;
  if (s_.model.baro.on) {
    const int64_t every = std::max<int64_t>(1, std::llround(s_.model.baro.period_s * 1e6 / double(dt_us_)));
    if (k % every == 0) {
      Real lat, lon, h;
      gravity::wgs84::ecef_to_geodetic(p.r_e, lat, lon, h);
      fr->baro_alt_m = double(h) + e.baro_bias_m + baro_extra_m;
      fr->baro_utime = fr->utime;
      fr->baro_status = GG_SENSOR_OK;
    }
  }
}

std::vector<ErrSample> Sim3D::fly(const SensorErrors& e, double duration_s, double output_dt_s) const {
  gg_nav3d_t nav;
  const gg_nav3d_config_t cfg = config(e);
  if (gg_nav3d_init(&nav, &cfg) != GG_OK) throw std::runtime_error("gg_nav3d_init failed");
  std::mt19937_64 rng(e.noise_seed), brng(e.noise_seed ^ 0x9e3779b97f4a7c15ULL);
  const bool noisy = e.acc_noise > 0 || e.gyro_noise > 0;
  std::normal_distribution<double> nd(0.0, 1.0);
  const int64_t baro_every =
      s_.model.baro.on ? std::max<int64_t>(1, std::llround(s_.model.baro.period_s * 1e6 / double(dt_us_))) : 0;
  const double phi = std::exp(-s_.model.baro.period_s / e.baro_gm_tau_s);
  double gm = e.baro_gm_sigma_m > 0 ? e.baro_gm_sigma_m * nd(brng) : 0.0;  // stationary start
  const int64_t K = std::llround(duration_s * 1e6 / double(dt_us_));
  const int64_t every = std::max<int64_t>(1, std::llround(output_dt_s * 1e6 / double(dt_us_)));
  std::vector<ErrSample> out;
  gg_frame_t fr;
  gg_nav3d_output_t o;
  for (int64_t k = 0; k <= K; ++k) {
    double extra = 0;
    if (baro_every > 0 && k % baro_every == 0) {
      if (k > 0 && e.baro_gm_sigma_m > 0) gm = phi * gm + std::sqrt(1 - phi * phi) * e.baro_gm_sigma_m * nd(brng);
      extra = gm + (e.baro_noise_m > 0 ? e.baro_noise_m * nd(brng) : 0.0);
    }
    frame(k, e, noisy ? &rng : nullptr, &fr, extra);
    const gg_status_t st = gg_nav3d_step(&nav, &fr, nullptr, &o);
    if (st != GG_OK) throw std::runtime_error("gg_nav3d_step failed at step " + std::to_string(k));
    if (k % every == 0 || k == K) {
      const Real t = Real(k) * Real(dt_us_) * 1e-6L;
      const covariance::Traj3DPoint p = traj_->at(t);
      const gravity::FieldSample fs = field_->eval(p.r_e);
      ErrSample s;
      s.t = double(t);
      for (int j = 0; j < 3; ++j) {
        s.dr(j) = double((Real(o.r_e[j]) + Real(o.r_e_lo[j])) - p.r_e(j));
        s.dv(j) = double(Real(o.v_e[j]) - p.v_e(j));
        s.dg(j) = double((Real(o.g_e[j]) + Real(o.g_e_lo[j])) - fs.g(j));
      }
      const Mat3 A = dcm_from_quat(o.q_b_e) * p.C_b_e.transpose();  // = I - [psi x]
      const Mat3 Psi = (A.transpose() - A) / 2;
      s.psi = Eigen::Vector3d(double(Psi(2, 1)), double(Psi(0, 2)), double(Psi(1, 0)));
      s.a_c = o.g_up_corr;
      out.push_back(s);
    }
  }
  return out;
}

}  // namespace ggins::montecarlo3d
