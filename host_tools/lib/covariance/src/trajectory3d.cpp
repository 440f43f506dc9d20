#include "ggins/covariance/trajectory3d.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::covariance {

Mat3 R3(Real theta) {
  const Real c = std::cos(theta), s = std::sin(theta);
  Mat3 R;
  R << c, -s, 0, s, c, 0, 0, 0, 1;
  return R;
}

Mat3 skew(const Vec3& x) {
  Mat3 S;
  S << 0, -x(2), x(1), x(2), 0, -x(0), -x(1), x(0), 0;
  return S;
}

GreatCircle3D::GreatCircle3D(Real radius_m, Real height_m, Real lat0, Real lon0, Real heading,
                             Real speed_mps, Platform platform, Real omega_ie)
    : rho_(radius_m + height_m), v_(speed_mps), wie_(omega_ie), plat_(platform) {
  if (!(rho_ > 0) || !(v_ >= 0)) throw std::invalid_argument("GreatCircle3D: radius > 0, speed >= 0");
  const Real cl = std::cos(lat0), sl = std::sin(lat0), co = std::cos(lon0), so = std::sin(lon0);
  u_ = Vec3(cl * co, cl * so, sl);
  const Vec3 north(-sl * co, -sl * so, cl), east(-so, co, 0);
  w_ = std::cos(heading) * north + std::sin(heading) * east;
  n_ = u_.cross(w_);
}

Traj3DPoint GreatCircle3D::at(Real t) const {
  const Real wg = v_ / rho_;  // angular rate of the circle, rad/s
  const Real phi = wg * t, c = std::cos(phi), s = std::sin(phi);
  const Vec3 rh = c * u_ + s * w_;  // r^
  const Vec3 th = -s * u_ + c * w_;  // direction of flight
  Traj3DPoint p;
  p.r_e = rho_ * rh;
  p.v_e = v_ * th;
  p.a_e = -v_ * wg * rh;
  // Strapdown body axes: x = th, z = -r^, y = z x x = -n.
  Mat3 Cs;
  Cs.col(0) = th;
  Cs.col(1) = -n_;
  Cs.col(2) = -rh;
  const Vec3 zh(0, 0, 1);
  if (plat_ == Platform::kStrapdown) {
    p.C_b_e = Cs;
    p.w_ib_b = Cs.transpose() * (wie_ * zh + wg * n_);
    p.wdot_ib_b = Cs.transpose() * (wie_ * wg * zh.cross(n_));
  } else {
    // C_b_i = C_b_e(0) = [w, -n, -u]; C_b_e(t) = R3(-theta) C_b_i.
    Mat3 C0;
    C0.col(0) = w_;
    C0.col(1) = -n_;
    C0.col(2) = -u_;
    p.C_b_e = R3(-wie_ * t) * C0;
  }
  return p;
}

}  // namespace ggins::covariance
