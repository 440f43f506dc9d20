#include "ggins/covariance/model.hpp"

#include <stdexcept>

#include "ggins/covariance/trajectory.hpp"

namespace ggins::covariance {

// Fa = [F Gamma; 0 D]   (Welker et al., eq. 11; D = 0 for constant biases).
MatrixXd LinearErrorModel::augmented(double t) const {
  const int n = n_states(), m = n_dist();
  MatrixXd F, Gam, D;
  matrices(t, F, Gam);
  dist_dynamics(t, D);
  if (F.rows() != n || F.cols() != n || Gam.rows() != n || Gam.cols() != m || D.rows() != m ||
      D.cols() != m)
    throw std::logic_error("LinearErrorModel: matrix dimensions do not match n_states/n_dist");
  MatrixXd Fa = MatrixXd::Zero(n + m, n + m);
  Fa.topLeftCorner(n, n) = F;
  Fa.topRightCorner(n, m) = Gam;
  Fa.bottomRightCorner(m, m) = D;
  return Fa;
}

// Welker et al., section VI: L = L0 + V t/(R_e+h), Vx = -V sin L, Vz = V cos L;
// position (R_e+h)(cos L, sin L) in the (x, z) plane (docs/design.md).
TrajectoryPoint NorthGreatCircle2D::at(double t) const {
  const double r = re_ + h_;
  const double w = v_ / r;
  const double L = l0_ + w * t;
  const double c = std::cos(L), s = std::sin(L);
  TrajectoryPoint p;
  p.r = Eigen::Vector3d(r * c, 0.0, r * s);
  p.v = Eigen::Vector3d(-v_ * s, 0.0, v_ * c);
  p.a = Eigen::Vector3d(-v_ * w * c, 0.0, -v_ * w * s);
  return p;
}

}  // namespace ggins::covariance
