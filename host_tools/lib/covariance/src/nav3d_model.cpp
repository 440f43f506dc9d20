#include "ggins/covariance/nav3d_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::covariance {

namespace {

Eigen::Matrix3d md(const Mat3& m) { return m.cast<double>(); }
Eigen::Vector3d vd(const Vec3& v) { return v.cast<double>(); }
Eigen::Matrix3d sk(const Eigen::Vector3d& x) {
  Eigen::Matrix3d S;
  S << 0, -x(2), x(1), x(2), 0, -x(0), -x(1), x(0), 0;
  return S;
}

}  // namespace

Nav3DModel::Nav3DModel(std::shared_ptr<const gravity::Field> field, std::shared_ptr<const Trajectory3D> traj,
                       Platform platform, Nav3DModelConfig cfg)
    : field_(std::move(field)), traj_(std::move(traj)), plat_(platform), cfg_(cfg) {
  if (!field_ || !traj_) throw std::invalid_argument("Nav3DModel: null field or trajectory");
  for (double d : cfg_.half_base_m)
    if (!(d > 0)) throw std::invalid_argument("Nav3DModel: half-baselines must be > 0");
  n_ = 9 + (strapdown() ? 3 : 0) + (baro() ? 1 : 0);
  m_ = 18 + (strapdown() ? 3 : 0) + (baro() ? 2 : 0);
  if (baro()) {
    const auto& p = cfg_.baro.poles_radps;
    double ws2 = cfg_.baro.omega_s2;
    if (!(ws2 > 0)) {
      // the firmware's default (truth generators): |G(r0)| / |r0|
      const Vec3 r0 = traj_->at(0).r_e;
      ws2 = double(field_->eval(r0).g.norm() / r0.norm());
    }
    // vchan.h: k1 = p1+p2+p3, k2 = p1p2+p1p3+p2p3 + 2 w_s^2, k3 = p1p2p3.
    k1_ = p[0] + p[1] + p[2];
    k2_ = p[0] * p[1] + p[0] * p[2] + p[1] * p[2] + 2.0 * ws2;
    k3_ = p[0] * p[1] * p[2];
  }
}

std::vector<std::string> Nav3DModel::state_keys() const {
  std::vector<std::string> k = {"rx_m", "ry_m", "rz_m", "vx_mps", "vy_mps", "vz_mps",
                                "gx_mps2", "gy_mps2", "gz_mps2"};
  if (strapdown()) k.insert(k.end(), {"psix_rad", "psiy_rad", "psiz_rad"});
  if (baro()) k.emplace_back("ac_mps2");
  return k;
}

std::vector<std::string> Nav3DModel::dist_keys() const {
  std::vector<std::string> k;
  const char ax[3] = {'x', 'y', 'z'};
  for (int s = 0; s < 6; ++s)
    for (int j = 0; j < 3; ++j) k.push_back("b" + std::to_string(s) + ax[j] + "_mps2");
  if (strapdown()) k.insert(k.end(), {"gyro_bx_radps", "gyro_by_radps", "gyro_bz_radps"});
  if (baro()) k.insert(k.end(), {"baro_bias_m", "baro_gm_m"});
  return k;
}

Eigen::Vector3d Nav3DModel::up(double t) const {
  const Vec3 r = traj_->at(Real(t)).r_e;
  Real lat, lon, h;
  gravity::wgs84::ecef_to_geodetic(r, lat, lon, h);
  return Eigen::Vector3d(double(std::cos(lat) * std::cos(lon)), double(std::cos(lat) * std::sin(lon)),
                         double(std::sin(lat)));
}

Eigen::Matrix3d Nav3DModel::ned_to_ecef(double t) const {
  const Vec3 r = traj_->at(Real(t)).r_e;
  Real lat, lon, h;
  gravity::wgs84::ecef_to_geodetic(r, lat, lon, h);
  const Eigen::Matrix3d enu = md(gravity::wgs84::enu_to_ecef(lat, lon));
  Eigen::Matrix3d ned;
  ned.col(0) = enu.col(1);
  ned.col(1) = enu.col(0);
  ned.col(2) = -enu.col(2);
  return ned;
}

void Nav3DModel::matrices(double t, MatrixXd& F, MatrixXd& Gam) const {
  const Traj3DPoint p = traj_->at(Real(t));
  const gravity::FieldSample fs = field_->eval(p.r_e);
  const Eigen::Matrix3d C = md(p.C_b_e), Ge = md(fs.gamma);
  const Eigen::Vector3d r = vd(p.r_e), v = vd(p.v_e), a = vd(p.a_e), G = vd(fs.g);
  const Eigen::Vector3d wb = vd(p.w_ib_b);
  const Eigen::Matrix3d W = sk(Eigen::Vector3d(0, 0, double(traj_->omega_ie())));
  const Eigen::Vector3d fe = a + 2.0 * W * v + W * W * r - G;  // centre specific force, ECEF

  F.setZero(n_, n_);
  Gam.setZero(n_, m_);
  const auto I3 = Eigen::Matrix3d::Identity();
  F.block<3, 3>(kR, kV) = I3;
  F.block<3, 3>(kV, kR) = -W * W;
  F.block<3, 3>(kV, kV) = -2.0 * W;
  F.block<3, 3>(kV, kG) = I3;
  F.block<3, 3>(kG, kV) = Ge;
  if (strapdown()) {
    F.block<3, 3>(kV, kPsi) = sk(fe);
    F.block<3, 3>(kG, kPsi) = sk(Ge * v) - Ge * sk(v);
    F.block<3, 3>(kPsi, kPsi) = -W;
  }
  // Accelerometer biases: centre force and the differenced gradient.
  const Eigen::Vector3d vb = C.transpose() * v;  // velocity in body axes
  for (int s = 0; s < 6; ++s) {
    const int k = s % 3;  // baseline axis of the pair
    const double sign = s < 3 ? 1.0 : -1.0;
    const double d = cfg_.half_base_m[size_t(k)];
    for (int j = 0; j < 3; ++j) {
      const int col = kAcc + 3 * s + j;
      Gam.block<3, 1>(kV, col) = C.col(j) / 6.0;
      Eigen::Matrix3d dM = Eigen::Matrix3d::Zero();
      dM(j, k) = sign / (2.0 * d);
      const Eigen::Matrix3d dGb = -0.5 * (dM + dM.transpose());
      Gam.block<3, 1>(kG, col) = C * (dGb * vb);
    }
  }
  if (strapdown()) {
    const Eigen::Matrix3d Wb = sk(wb);
    for (int j = 0; j < 3; ++j) {
      const int col = idx_gyro() + j;
      const Eigen::Matrix3d Wd = sk(Eigen::Vector3d::Unit(j));
      const Eigen::Matrix3d dGb = Wb * Wd + Wd * Wb;
      Gam.block<3, 1>(kG, col) = C * (dGb * vb);
      Gam.block<3, 1>(kPsi, col) = -C.col(j);
    }
  }
  if (baro()) {
    const Eigen::Vector3d u = up(t);
    const int ac = idx_ac(), bb = idx_baro_bias();
    // e = u^T dr - b - m (- n): -k1 e u in dr', -k2 e u - a_c u in dv', -k1 e Gamma u in dG'.
    F.block<3, 3>(kR, kR) += -k1_ * u * u.transpose();
    F.block<3, 3>(kV, kR) += -k2_ * u * u.transpose();
    // nav3d moves v_i by w x dr with each position correction dr, so the correction of the
    // Earth-relative velocity is along u only (nav3d.c baro step).
    F.block<3, 1>(kV, ac) = -u;
    F.block<3, 3>(kG, kR) += -k1_ * Ge * u * u.transpose();
    F.block<1, 3>(ac, kR) = k3_ * u.transpose();
    for (int c = bb; c < bb + 2; ++c) {  // bias and Gauss-Markov enter as -e
      Gam.block<3, 1>(kR, c) = k1_ * u;
      Gam.block<3, 1>(kV, c) = k2_ * u;
      Gam.block<3, 1>(kG, c) = k1_ * Ge * u;
      Gam(ac, c) = -k3_;
    }
  }
}

void Nav3DModel::dist_dynamics(double, MatrixXd& D) const {
  D.setZero(m_, m_);
  if (baro()) D(idx_baro_bias() + 1, idx_baro_bias() + 1) = -1.0 / cfg_.baro.gm_tau_s;
}

bool Nav3DModel::has_process_noise() const {
  return cfg_.acc_noise_sigma_mps2 > 0 || (strapdown() && cfg_.gyro_noise_sigma_radps > 0) ||
         (baro() && (cfg_.baro.gm_sigma_m > 0 || cfg_.baro.noise_sigma_m > 0));
}

void Nav3DModel::process_noise(double t, MatrixXd& Qa) const {
  const int N = n_ + m_;
  Qa.setZero(N, N);
  MatrixXd F, Gam;
  matrices(t, F, Gam);
  VectorXd S = VectorXd::Zero(m_);  // white-noise density on each disturbance column
  const double qa = cfg_.acc_noise_sigma_mps2 * cfg_.acc_noise_sigma_mps2 / cfg_.rate_hz;
  for (int i = 0; i < 18; ++i) S(i) = qa;
  if (strapdown())
    for (int j = 0; j < 3; ++j)
      S(idx_gyro() + j) = cfg_.gyro_noise_sigma_radps * cfg_.gyro_noise_sigma_radps / cfg_.rate_hz;
  if (baro()) S(idx_baro_bias()) = cfg_.baro.noise_sigma_m * cfg_.baro.noise_sigma_m * cfg_.baro.period_s;
  Qa.topLeftCorner(n_, n_) = Gam * S.asDiagonal() * Gam.transpose();
  if (baro()) {  // Gauss-Markov driving noise, density 2 sigma^2 / tau
    const int g = n_ + idx_baro_bias() + 1;
    Qa(g, g) = 2.0 * cfg_.baro.gm_sigma_m * cfg_.baro.gm_sigma_m / cfg_.baro.gm_tau_s;
  }
}

}  // namespace ggins::covariance
