// Reference trajectories of the 3-D error analysis, on a
// rotating Earth. Frames (nav3d design, docs/design.md): ECEF `_e` (z to the north
// pole, x to Greenwich), ECI `_i` = ECEF at t = 0 turning as
// r_i = R3(theta) r_e, theta = omega_ie t, R3(theta) = [[c,-s,0],[s,c,0],[0,0,1]];
// body `_b`: x forward, y right, z down.
//
// Everything is analytic (no numerical integration) and evaluated in long
// double, so the same object drives the linear error model and the sensor
// frames of the Monte Carlo runs of the firmware (sim3d.hpp).
#pragma once

#include "ggins/gravity/field.hpp"

namespace ggins::covariance {

using gravity::Mat3;
using gravity::Real;
using gravity::Vec3;

enum class Platform { kStabilized, kStrapdown };

struct Traj3DPoint {
  Vec3 r_e = Vec3::Zero();      // position of the platform centre, ECEF, m
  Vec3 v_e = Vec3::Zero();      // Earth-relative velocity dr_e/dt, ECEF, m/s
  Vec3 a_e = Vec3::Zero();      // d2r_e/dt2, ECEF, m/s^2
  Mat3 C_b_e = Mat3::Identity();  // body -> ECEF
  Vec3 w_ib_b = Vec3::Zero();   // inertial angular rate of the body, body axes, rad/s
  Vec3 wdot_ib_b = Vec3::Zero();  // its time derivative (body axes), rad/s^2
};

class Trajectory3D {
 public:
  virtual ~Trajectory3D() = default;
  virtual Traj3DPoint at(Real t) const = 0;
  virtual Real omega_ie() const = 0;  // Earth rate used (0: non-rotating Earth), rad/s
};

// Great-circle flight at constant geocentric radius rho = R + h and constant
// speed V over a rotating Earth, starting at geocentric latitude lat0,
// longitude lon0, heading psi0 (from north, toward east):
//   r_e(t) = rho (cos(phi) u + sin(phi) w),  phi = V t / rho,
// u = r^_e(0), w = initial direction of flight, n = u x w (the circle's axis).
// V = 0 gives a platform at rest on the Earth.
// Body attitude:
//   strapdown:  x along the velocity (heading psi0 at t = 0 if V = 0), z down
//               (-r^), y = z x x; it turns with the circle (w_eb = (V/rho) n);
//               w_ib_b = C_e_b (omega_ie z^ + (V/rho) n),
//               wdot_ib_b = C_e_b (omega_ie (V/rho) z^ x n);
//   stabilized: C_b_i constant = C_b_e(0) (gyros read 0).
class GreatCircle3D final : public Trajectory3D {
 public:
  GreatCircle3D(Real radius_m, Real height_m, Real lat0_rad, Real lon0_rad, Real heading_rad,
                Real speed_mps, Platform platform, Real omega_ie);
  Traj3DPoint at(Real t) const override;
  Real omega_ie() const override { return wie_; }
  Real rho() const { return rho_; }
  Real speed() const { return v_; }
  Platform platform() const { return plat_; }

 private:
  Real rho_, v_, wie_;
  Platform plat_;
  Vec3 u_, w_, n_;
};

// R3(theta) (ECEF -> ECI at t = theta/omega_ie).
Mat3 R3(Real theta);
// Skew matrix [x x].
Mat3 skew(const Vec3& x);

}  // namespace ggins::covariance
