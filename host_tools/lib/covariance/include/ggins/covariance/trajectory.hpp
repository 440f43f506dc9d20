// Reference trajectories along which an error model is linearized.
// Positions in the Earth-fixed/inertial frame of the gravity Field interface
// (host_tools/lib/gravity); the 2-D plane of Welker et al. is (x, z) = components
// 0 and 2 of the 3-D vector, y = 0.
#pragma once

#include <Eigen/Dense>
#include <memory>

namespace ggins::covariance {

struct TrajectoryPoint {
  Eigen::Vector3d r = Eigen::Vector3d::Zero();  // position, m
  Eigen::Vector3d v = Eigen::Vector3d::Zero();  // velocity, m/s
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  // kinematic acceleration, m/s^2
};

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  virtual TrajectoryPoint at(double t) const = 0;
};

// Flight due north at constant speed V and height h from latitude L0 over a
// spherical Earth of radius R, in the (x, z) plane (Welker et al., section VI;
// docs/design.md): L = L0 + V t/(R+h), r = (R+h)(cos L, sin L), v = V(-sin L, cos L).
class NorthGreatCircle2D final : public Trajectory {
 public:
  NorthGreatCircle2D(double speed_mps, double height_m, double lat0_rad, double radius_m)
      : v_(speed_mps), h_(height_m), l0_(lat0_rad), re_(radius_m) {}
  TrajectoryPoint at(double t) const override;
  double latitude(double t) const { return l0_ + v_ * t / (re_ + h_); }

 private:
  double v_, h_, l0_, re_;
};

}  // namespace ggins::covariance
