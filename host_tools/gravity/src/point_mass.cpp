#include "ggins/gravity/field.hpp"

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

}  // namespace ggins::gravity
