// 3-D truth trajectories over the rotating WGS-84 Earth, analytic end to end.
//
// Frames (firmware/include/ggins/nav3d.h): ECEF _e = WGS-84
// (z to the north pole, x to Greenwich); ECI _i coincides with ECEF at t = 0
// and the Earth turns about z at omega_ie = 7.292115e-5 rad/s:
//   r_i = R3(theta) r_e,  theta = omega_ie t,  R3(theta) = [[c,-s,0],[s,c,0],[0,0,1]].
// Local level _n = NED; body _b: x forward, y right, z down.
//
// Every trajectory defines the centre's ECEF position r_e(t) and the attitude
// C_b_i(t) as closed-form expressions evaluated on Taylor jets (jet.hpp), so
// r, v, a (ECI and ECEF), C_b_i and its first two derivatives, the body rate
// omega_b ([omega_b x] = C_b_i^T C_b_i') and omega_b' are exact derivatives
// of one another (to long-double rounding): nothing is integrated numerically.
//
// Trajectory kinds:
//  * Flight: geodetic lat(t), lon(t), h(t) with rates that switch smoothly
//      lat'(t) = (v_N0 + sum_k dv_N,k sigma((t - t_k)/tau_k)) / (M_0 + h_0)
//      lon'(t) = (v_E0 + sum_k dv_E,k sigma(...)) / ((N_0 + h_0) cos lat_0)
//      h'(t)   = -(v_D0 + sum_k dv_D,k sigma(...))
//    (sigma the logistic function; M_0, N_0 the meridian and prime-vertical
//    radii at the start point, so the dv are NED velocity changes in m/s there),
//    integrated in closed form: int sigma(u) = softplus(u). A turn is a
//    maneuver whose dv rotates the horizontal velocity, a climb one with dv_D.
//    Attitude:
//      - Coordinated (strapdown): body x along the Earth-relative velocity
//        v_e = r_e'; y0 = unit(d x x) (d = ellipsoid down), z0 = x × y0 (the
//        wings-level frame at the flight-path pitch); bank phi about x with
//        tan(phi) = a_lat / g0, a_lat = r_e'' . y0 (lateral Earth-relative
//        acceleration), g0 = 9.80665 m/s^2 (a coordinated turn: tan phi = V psi'/g);
//        y = cos(phi) y0 + sin(phi) z0, z = -sin(phi) y0 + cos(phi) z0;
//        C_b_e = [x y z] (columns), C_b_i = R3(theta) C_b_e.
//      - Stabilized: C_b_i constant = the coordinated attitude at t = 0 (the
//        space-stabilized platform; gyros read 0).
//  * Circle: a level circle of radius rho (m) at speed V about (lat_c, lon_c):
//      lat = lat_c + (rho / (M_c + h)) sin(w t),  lon = lon_c - (rho / ((N_c + h) cos lat_c)) cos(w t),
//    w = V / rho: starts at the west point north-bound and turns right (clockwise
//    seen from above); attitude as Flight.
//  * Tumble: a fixed Earth point (lat, lon, h) and a torque-free-like motion
//      C_b_i = R3(psi0 + w_p t) R1(nu(t)) R3(phi0 + w_s t),  nu(t) = nu0 + nu_a sin(w_n t)
//    (precession w_p about the inertial z, nutation nu, spin w_s about body z).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth3d/jet.hpp"

namespace ggins::truth3d {

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;

constexpr int kJetOrder = 4;  // r_e to order 4 -> attitude (uses r'') valid to order 2
using J = Jet<kJetOrder>;
using JV = JVec3<kJetOrder>;
using JM = JMat3<kJetOrder>;
// The attitude (from r'') and everything State3 needs are valid to order 2 and
// are evaluated on jets of that order (bit-identical coefficients 0..2: jet.hpp, resize).
constexpr int kAttOrder = 2;
using JA = Jet<kAttOrder>;
using JVA = JVec3<kAttOrder>;
using JMA = JMat3<kAttOrder>;

constexpr Real kOmegaIe = gravity::wgs84::kOmega;  // rad/s (WGS-84, NIMA TR8350.2 Table 3.1)
constexpr Real kG0 = 9.80665L;           // m/s^2, bank-angle reference (standard gravity)
constexpr Real kPi = 3.14159265358979323846264338327950288L;

// Truth at the body centre at one instant.
struct State3 {
  Real t = 0;
  Vec3 r_i = Vec3::Zero(), v_i = Vec3::Zero(), a_i = Vec3::Zero();  // ECI: r, r', r''
  Vec3 r_e = Vec3::Zero(), v_e = Vec3::Zero(), a_e = Vec3::Zero();  // ECEF: r, r', r'' (Earth-relative)
  Real lat = 0, lon = 0, h = 0;                                    // geodetic (WGS-84), rad, rad, m
  Mat3 C_b_i = Mat3::Identity(), C_b_i_dot = Mat3::Zero(), C_b_i_ddot = Mat3::Zero();
  Mat3 C_b_e = Mat3::Identity();  // = R3(theta)^T C_b_i
  Mat3 C_e_i = Mat3::Identity();  // R3(theta)
  Vec3 omega_b = Vec3::Zero();      // inertial angular rate, body axes, rad/s
  Vec3 omega_dot_b = Vec3::Zero();  // its time derivative (body axes), rad/s^2
  Real roll = 0, pitch = 0, yaw = 0;  // attitude w.r.t. NED (Z-Y-X Euler), rad
};

// Geodetic (lat, lon, h) -> ECEF on jets (WGS-84):
//   N = a / sqrt(1 - e^2 sin^2 lat), r_e = ((N+h) cos lat cos lon, (N+h) cos lat sin lon, (N (1-e^2) + h) sin lat).
JV geodetic_to_ecef(const J& lat, const J& lon, const J& h);
// Rotation C_n_e^T columns: north, east, down unit vectors at (lat, lon), as jets.
void ned_axes(const J& lat, const J& lon, JV& north, JV& east, JV& down);

class Trajectory3 {
 public:
  virtual ~Trajectory3() = default;
  // Jets at time t: r_e (valid to order kJetOrder) and C_b_i (valid to order >= 2;
  // at() reads orders 0..2, the kinds here compute exactly those).
  virtual void jets(Real t, JV& r_e, JM& C_b_i) const = 0;
  virtual std::string name() const = 0;
  // The Earth rate of the ECI <-> ECEF rotation R3(omega_ie t), rad/s
  // (WGS-84 unless a trajectory flies over a differently turning Earth).
  virtual Real omega_ie() const { return kOmegaIe; }
  // Everything at time t (from jets()).
  State3 at(Real t) const;
};

enum class Attitude { Coordinated, Stabilized };

struct Maneuver {
  Real t_s = 0;          // centre of the transition, s
  Real duration_s = 60;  // ~ 8 tau (sigma from 1.8 % to 98.2 %), s
  Real dv_ned[3] = {0, 0, 0};  // change of the NED velocity, m/s (at the start point's radii)
};

struct FlightParams {
  Real lat0 = 0, lon0 = 0, h0 = 0;    // rad, rad, m
  Real v_ned0[3] = {200, 0, 0};       // initial NED velocity, m/s
  std::vector<Maneuver> maneuvers;
};

// Coordinated-turn attitude C_b_e from ECEF position/velocity/acceleration jets (see top),
// on order-2 jets; the order-4 overload truncates its arguments and returns the
// same values with coefficients 3, 4 zero (unknown).
JMA coordinated_attitude_e(const JA& lat, const JA& lon, const JVA& v_e, const JVA& a_e);
JM coordinated_attitude_e(const J& lat, const J& lon, const JV& v_e, const JV& a_e);
// R3(omega_ie t) as a jet of order N (2 or 4).
template <int N = kJetOrder>
JMat3<N> earth_rotation(Real t, Real omega_ie = kOmegaIe);

class Flight3 final : public Trajectory3 {
 public:
  Flight3(const FlightParams& p, Attitude att);
  void jets(Real t, JV& r_e, JM& C_b_i) const override;
  std::string name() const override { return "flight"; }
  void geodetic(Real t, J& lat, J& lon, J& h) const;

 private:
  JM attitude(Real t, const J& lat, const J& lon, const JV& r_e) const;  // coordinated C_b_i
  FlightParams p_;
  Attitude att_;
  Real rate_scale_[3];  // 1/(M0+h0), 1/((N0+h0) cos lat0), -1
  std::vector<Real> sp0_;  // softplus(-t_k / tau_k) of each maneuver (the value at t = 0)
  JM c0_;               // stabilized: C_b_i at t = 0
};

struct CircleParams {
  Real lat_c = 0, lon_c = 0, h = 0;  // centre, rad, rad, m
  Real radius_m = 5000, speed_mps = 200;
};

class Circle3 final : public Trajectory3 {
 public:
  Circle3(const CircleParams& p, Attitude att);
  void jets(Real t, JV& r_e, JM& C_b_i) const override;
  std::string name() const override { return "circle"; }

 private:
  CircleParams p_;
  Attitude att_;
  Real alat_, alon_, w_;
  JM c0_;
};

// Great circle at constant geocentric radius rho = R + h and speed V over an
// Earth turning at omega_ie (0: non-rotating), from geocentric latitude lat0,
// longitude lon0, heading psi0 (from north toward east); the reference flight
// of the 3-D error analysis (covariance/trajectory3d.hpp, GreatCircle3D):
//   r_e(t) = rho (cos(phi) u + sin(phi) w),  phi = V t / rho,
// u = r^_e(0), w = the initial direction of flight, n = u x w.
// Strapdown: body x along the flight direction, y = -n, z = -r^
// (C_b_i = R3(omega_ie t) C_b_e); stabilized: C_b_i = C_b_e(0) = [w, -n, -u].
struct GreatCircleParams {
  Real radius_m = gravity::wgs84::kA, height_m = 0;
  Real lat0 = 0, lon0 = 0, heading = 0;  // rad
  Real speed_mps = 200;
  Real omega_ie = kOmegaIe;  // rad/s
};
class GreatCircle3 final : public Trajectory3 {
 public:
  GreatCircle3(const GreatCircleParams& p, Attitude att);
  void jets(Real t, JV& r_e, JM& C_b_i) const override;
  std::string name() const override { return "great-circle"; }
  Real omega_ie() const override { return p_.omega_ie; }

 private:
  GreatCircleParams p_;
  Attitude att_;
  Real rho_ = 0;
  Vec3 u_, w_, n_;
};

struct TumbleParams {
  Real lat = 0, lon = 0, h = 0;        // fixed point, rad, rad, m
  Real spin_radps = 1.0;               // w_s about body z
  Real precession_radps = 0.2;         // w_p about inertial z
  Real nutation0 = 0.5;                // nu0, rad
  Real nutation_amp = 0.1;             // nu_a, rad
  Real nutation_radps = 0.05;          // w_n
  Real psi0 = 0, phi0 = 0;             // initial precession and spin angles, rad
};

class Tumble3 final : public Trajectory3 {
 public:
  explicit Tumble3(const TumbleParams& p);
  void jets(Real t, JV& r_e, JM& C_b_i) const override;
  std::string name() const override { return "tumble"; }

 private:
  TumbleParams p_;
  Vec3 r_e_;
};

// Helpers on plain values.
template <int N>
Mat3 deriv_value(const JMat3<N>& m, int k) {  // k-th time derivative
  Mat3 r;
  for (std::size_t i = 0; i < 3; ++i)
    for (std::size_t j = 0; j < 3; ++j) r(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m[i][j].d(k);
  return r;
}
template <int N>
Vec3 deriv_value(const JVec3<N>& v, int k) {
  return Vec3(v[0].d(k), v[1].d(k), v[2].d(k));
}
template <int N>
Mat3 value(const JMat3<N>& m) {
  return deriv_value(m, 0);
}
template <int N>
Vec3 value(const JVec3<N>& v) {
  return deriv_value(v, 0);
}
Mat3 ned_to_ecef(Real lat, Real lon);  // columns north, east, down: C_n_e
// Body -> NED Z-Y-X Euler angles of C_b_n.
void euler_zyx(const Mat3& C_b_n, Real& roll, Real& pitch, Real& yaw);

}  // namespace ggins::truth3d
