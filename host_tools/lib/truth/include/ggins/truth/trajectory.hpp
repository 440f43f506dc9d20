// Analytic trajectories for the truth generator. Position, velocity and
// acceleration come from one closed-form expression, so they agree exactly
// (to long-double rounding), whatever the step of the consumer.
//
// Conventions (docs/design.md): SI units, inertial frame (_i), axis
// index 0 = x, 1 = y, 2 = z. In the 2-D case of Welker et al. the motion is in
// the (x, z) plane: x equatorial, z polar, y = 0.
#pragma once

#include <memory>
#include <string>

#include "ggins/gravity/field.hpp"

namespace ggins::truth {

using Real = gravity::Real;
using Vec3 = gravity::Vec3;
using Mat3 = gravity::Mat3;

// Kinematic state of the platform centre at one instant.
struct Kinematics {
  Vec3 r = Vec3::Zero();  // position, inertial, m
  Vec3 v = Vec3::Zero();  // velocity, inertial, m/s
  Vec3 a = Vec3::Zero();  // acceleration r'', inertial, m/s^2
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  // State at time t_s (s since the start of the run). Thread-safe (const).
  virtual Kinematics at(Real t_s) const = 0;
  virtual std::string name() const = 0;
};

// Flight due north over a non-rotating spherical Earth at constant speed V and
// height h, starting at latitude L0 (docs/design.md, "The 2-D case"):
//   L = L0 + V t / (R + h),  r = (R+h)(cos L, 0, sin L),
//   v = V(-sin L, 0, cos L), a = -(V^2/(R+h))(cos L, 0, sin L).
class NorthFlight final : public Trajectory {
 public:
  NorthFlight(Real speed_mps, Real height_m, Real lat0_rad, Real radius_m);
  Kinematics at(Real t_s) const override;
  std::string name() const override { return "north-flight"; }

 private:
  Real speed_, height_, lat0_, radius_;
};

}  // namespace ggins::truth
