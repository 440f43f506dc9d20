#include "ggins/covariance/welker2d.hpp"

#include <stdexcept>

namespace ggins::covariance {

Welker2DModel::Welker2DModel(std::shared_ptr<const gravity::Field> field,
                             std::shared_ptr<const Trajectory> traj, double a_m, double b_m,
                             GradientSource src)
    : field_(std::move(field)), traj_(std::move(traj)), a_(a_m), b_(b_m), src_(src) {
  if (!field_ || !traj_) throw std::invalid_argument("Welker2DModel: null field or trajectory");
  if (!(a_ > 0) || !(b_ > 0)) throw std::invalid_argument("Welker2DModel: half-baselines must be > 0");
}

std::vector<std::string> Welker2DModel::state_keys() const {
  return {"x_m", "z_m", "vx_mps", "vz_mps", "gx_mps2", "gz_mps2"};
}

std::vector<std::string> Welker2DModel::dist_keys() const {
  return {"b1x_mps2", "b2x_mps2", "b3x_mps2", "b4x_mps2",
          "b1z_mps2", "b2z_mps2", "b3z_mps2", "b4z_mps2"};
}

Eigen::Matrix2d Welker2DModel::gradient(double t) const {
  using gravity::Real;
  using gravity::Vec3;
  const TrajectoryPoint p = traj_->at(t);
  const Vec3 r = p.r.cast<Real>();
  Eigen::Matrix2d g;
  if (src_ == GradientSource::kCentre) {
    const gravity::Mat3 gam = field_->eval(r).gamma;
    g << double(gam(0, 0)), double(gam(0, 2)), double(gam(2, 0)), double(gam(2, 2));
  } else {
    // What the differenced accelerometers measure (Welker et al., section III):
    // f_i = a - G(r + offset_i), dGx/dx = (f3x - f1x)/2a = (G(r+a e_x) - G(r-a e_x))_x / 2a, ...
    const Vec3 ex(Real(a_), 0, 0), ez(0, 0, Real(b_));
    const Vec3 g1 = field_->eval(r + ex).g, g3 = field_->eval(r - ex).g;
    const Vec3 g2 = field_->eval(r + ez).g, g4 = field_->eval(r - ez).g;
    const Vec3 dx = (g1 - g3) / Real(2 * a_), dz = (g2 - g4) / Real(2 * b_);
    g << double(dx(0)), double(dz(0)), double(dx(2)), double(dz(2));
  }
  return g;
}

void Welker2DModel::matrices(double t, MatrixXd& F, MatrixXd& Gam) const {
  const TrajectoryPoint p = traj_->at(t);
  const double vx = p.v(0), vz = p.v(2);
  const Eigen::Matrix2d g = gradient(t);

  // F, Welker et al. eq. (9), with the sign fix (docs/design.md): dV' = 1/4 sum df + dG.
  F.setZero(6, 6);
  F(kX, kVx) = 1.0;
  F(kZ, kVz) = 1.0;
  F(kVx, kGx) = 1.0;
  F(kVz, kGz) = 1.0;
  F.block<2, 2>(kGx, kVx) = g;  // dG' = grad * dV (+ Gamma d)

  // Gamma, Welker et al. eq. (10); d = (f1x f2x f3x f4x f1z f2z f3z f4z).
  Gam.setZero(6, 8);
  for (int i = 0; i < 4; ++i) {
    Gam(kVx, i) = 0.25;
    Gam(kVz, 4 + i) = 0.25;
  }
  const double ka = vx / (2 * a_), kb = vz / (2 * b_);
  for (int axis = 0; axis < 2; ++axis) {
    const int row = axis == 0 ? kGx : kGz, c0 = 4 * axis;
    Gam(row, c0 + 0) = -ka;
    Gam(row, c0 + 1) = -kb;
    Gam(row, c0 + 2) = ka;
    Gam(row, c0 + 3) = kb;
  }
}

void Welker2DModel::set_white_noise_psd(const VectorXd& psd) {
  if (psd.size() != 8 || (psd.array() < 0).any()) throw std::invalid_argument("Welker2DModel: psd needs 8 values >= 0");
  psd_ = psd;
  noise_ = (psd_.array() > 0).any();
}

void Welker2DModel::process_noise(double t, MatrixXd& Qa) const {
  Qa.setZero(14, 14);
  if (!noise_) return;
  MatrixXd F, Gam;
  matrices(t, F, Gam);
  Qa.topLeftCorner(6, 6) = Gam * psd_.asDiagonal() * Gam.transpose();
}

}  // namespace ggins::covariance
