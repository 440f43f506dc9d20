#include "ggins/covariance/welker2d_baro.hpp"

#include <stdexcept>

namespace ggins::covariance {

Welker2DBaroModel::Welker2DBaroModel(std::shared_ptr<const Welker2DModel> base, BaroLoopParams p)
    : base_(std::move(base)), p_(p) {
  if (!base_) throw std::invalid_argument("Welker2DBaroModel: null base model");
  const auto& q = p_.poles_radps;
  if (!(q[0] > 0 && q[1] > 0 && q[2] > 0) || !(p_.omega_s2 > 0) || !(p_.gm_tau_s > 0) || !(p_.period_s > 0))
    throw std::invalid_argument("Welker2DBaroModel: poles, omega_s2, gm_tau_s and period_s must be > 0");
  k1_ = q[0] + q[1] + q[2];
  k2_ = q[0] * q[1] + q[0] * q[2] + q[1] * q[2] + 2 * p_.omega_s2;  // vchan.h
  k3_ = q[0] * q[1] * q[2];
}

std::vector<std::string> Welker2DBaroModel::state_keys() const {
  auto k = base_->state_keys();
  k.emplace_back("a_c_mps2");
  return k;
}

std::vector<std::string> Welker2DBaroModel::dist_keys() const {
  auto k = base_->dist_keys();
  k.emplace_back("baro_bias_m");
  k.emplace_back("baro_gm_m");
  return k;
}

Eigen::Vector2d Welker2DBaroModel::up(double t) const {
  const TrajectoryPoint pt = base_->trajectory().at(t);
  return Eigen::Vector2d(pt.r(0), pt.r(2)).normalized();
}

void Welker2DBaroModel::matrices(double t, MatrixXd& F, MatrixXd& Gam) const {
  MatrixXd F6, G6;
  base_->matrices(t, F6, G6);
  const Eigen::Vector2d u = up(t);
  const Eigen::Matrix2d grad = base_->gradient(t);
  const Eigen::Matrix2d uu = u * u.transpose();
  const Eigen::Vector2d gu = grad * u;
  F.setZero(7, 7);
  F.topLeftCorner(6, 6) = F6;
  F.block<2, 2>(0, 0) += -k1_ * uu;               // dr' = dv - k1 e u
  F.block<2, 2>(2, 0) += -k2_ * uu;               // dv' = ... - k2 e u - a_c u
  F.block<2, 1>(2, kAc) = -u;
  F.block<2, 2>(4, 0) += -k1_ * gu * u.transpose();  // dG' = ... - k1 e Gamma u
  F.block<1, 2>(kAc, 0) = k3_ * u.transpose();    // a_c' = k3 e
  Gam.setZero(7, 10);
  Gam.topLeftCorner(6, 8) = G6;
  for (int c : {kBaroBias, kBaroGm}) {             // e contains -(b + m)
    Gam.block<2, 1>(0, c) = k1_ * u;
    Gam.block<2, 1>(2, c) = k2_ * u;
    Gam.block<2, 1>(4, c) = k1_ * gu;
    Gam(kAc, c) = -k3_;
  }
}

void Welker2DBaroModel::dist_dynamics(double, MatrixXd& D) const {
  D.setZero(10, 10);
  D(kBaroGm, kBaroGm) = -1.0 / p_.gm_tau_s;
}

void Welker2DBaroModel::process_noise(double t, MatrixXd& Qa) const {
  Qa.setZero(17, 17);
  MatrixXd F, Gam;
  matrices(t, F, Gam);
  if (base_->has_process_noise()) {
    MatrixXd Qb;
    base_->process_noise(t, Qb);  // accelerometer white noise: 6x6 block of the 14x14
    Qa.topLeftCorner(6, 6) = Qb.topLeftCorner(6, 6);
  }
  const VectorXd g = Gam.col(kBaroBias);  // white barometer noise enters like the bias
  Qa.topLeftCorner(7, 7) += g * g.transpose() * (p_.noise_sigma_m * p_.noise_sigma_m * p_.period_s);
  Qa(7 + kBaroGm, 7 + kBaroGm) = 2 * p_.gm_sigma_m * p_.gm_sigma_m / p_.gm_tau_s;
}

}  // namespace ggins::covariance
