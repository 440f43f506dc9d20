#include "ggins/gravity/field.hpp"

#include "detail.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::gravity {

FieldSample PointMassField::eval(const Vec3& r_e) const {
  const Real r2 = r_e.squaredNorm();
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("PointMassField: position at the centre or not finite");
  const Real r = std::sqrt(r2);
  const Real gm_r3 = gm_ / (r2 * r);
  const Vec3 u = r_e / r;
  FieldSample s;
  s.potential = gm_ / r;
  s.g = -gm_r3 * r_e;
  s.gamma = gm_r3 * (3.0L * u * u.transpose() - Mat3::Identity());
  return s;
}

// d^3(1/r)/dx_i dx_j dx_k = 3 (delta_ij x_k + delta_ik x_j + delta_jk x_i)/r^5 - 15 x_i x_j x_k / r^7
void add_point_mass_third(Real gm, const Vec3& d, Tensor3& t) {
  const Real r2 = d.squaredNorm(), r = std::sqrt(r2), i5 = gm / (r2 * r2 * r), i7 = i5 / r2;
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const Real dd = (i == j ? d[k] : 0) + (i == k ? d[j] : 0) + (j == k ? d[i] : 0);
        t[k](i, j) += 3 * dd * i5 - 15 * d[i] * d[j] * d[k] * i7;
      }
}

bool PointMassField::third(const Vec3& r_e, Tensor3& t) const {
  const Real r2 = r_e.squaredNorm();
  if (!(r2 > 0) || !std::isfinite(r2)) throw std::domain_error("PointMassField: position at the centre or not finite");
  for (Mat3& m : t) m.setZero();
  add_point_mass_third(gm_, r_e, t);
  return true;
}

}  // namespace ggins::gravity
