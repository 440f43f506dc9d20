#include "ggins/truth/trajectory.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::truth {

NorthFlight::NorthFlight(Real speed_mps, Real height_m, Real lat0_rad, Real radius_m)
    : speed_(speed_mps), height_(height_m), lat0_(lat0_rad), radius_(radius_m) {
  if (!std::isfinite(speed_) || !std::isfinite(height_) || !std::isfinite(lat0_) ||
      !std::isfinite(radius_))
    throw std::invalid_argument("north-flight: parameters must be finite");
  if (!(radius_ + height_ > 0)) throw std::invalid_argument("north-flight: radius + height must be > 0");
}

Kinematics NorthFlight::at(Real t) const {
  const Real rho = radius_ + height_;
  const Real lat = lat0_ + speed_ * t / rho;
  const Real c = std::cos(lat), s = std::sin(lat);
  Kinematics k;
  k.r = Vec3(rho * c, 0.0L, rho * s);
  k.v = Vec3(-speed_ * s, 0.0L, speed_ * c);
  const Real ac = speed_ * speed_ / rho;
  k.a = Vec3(-ac * c, 0.0L, -ac * s);
  return k;
}

}  // namespace ggins::truth
