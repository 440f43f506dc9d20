// 3-D truth generator: from a Scenario3 (or a trajectory + field), the
// sensor frame of step k that the 3-D firmware (nav3d.h) sees, and the truth
// it is judged against.
//
// Accelerometer j sits at body offset d_j (diff3d.h layout: 0 (+a,0,0),
// 1 (0,+b,0), 2 (0,0,+c), 3 (-a,0,0), 4 (0,-b,0), 5 (0,0,-c)). With the
// trajectory's exact C_b_i, C_b_i'' and a_i (trajectory3d.hpp):
//   r_j = r_i + C_b_i d_j,  a_j = a_i + C_b_i'' d_j,
//   f_j = C_b_i^T (a_j - G_i(r_j)) = C_b_i^T a_j - C_b_e^T G_e(r_e + C_b_e d_j)
// (G_i = R3 G_e(R3^T r) and C_b_i^T R3 = C_b_e^T), in long double; sent as a
// double plus its sub-ulp residual (f + f_lo). The six G_e(r_j) come from one
// gravity::Field::eval_pairs call at the centre (the pairs +-d_k): the normal
// field evaluates the + sensors and takes the - sensors from the central
// difference G(r - d) = G(r + d) - 2 Gamma(r) d, dropping <= 8 GM |d|^3 / r^5
// (3.8e-20 m/s^2 for 0.5 m at the surface; gravity/normal.hpp); anomalies
// (lattices) are evaluated at every sensor. accel_reference() evaluates the
// field at each sensor's own position (the independent check, tests/truth3d).
// Errors (off by default, seeded, counter-based like the 2-D generator so
// frame k is a pure function of (seed, k)): the sensor models of
// truth/sensors.hpp, the same code as the 2-D generator's:
//   accelerometer f_meas = (1 + s) f + b + n per sensor axis (scale, bias constant; n white);
//   gyro w_meas = (1 + s) w + b + n per axis (w = omega_b, the inertial body rate);
//   barometer on the geodetic height h_baro = h + bias + m_j + n_j (m_j Gauss-Markov).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

extern "C" {
#include "ggins/frame.h"
}
#include "ggins/gravity/field.hpp"
#include "ggins/truth/generator.hpp"
#include "ggins/truth3d/coldatom3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"
#include "ggins/truth3d/trajectory3d.hpp"

namespace ggins::truth3d {

struct Truth3 {
  int64_t seq = 0;
  int64_t utime = 0;
  Real t_s = 0;
  State3 s;                       // kinematics and attitude of the centre
  Vec3 g_e = Vec3::Zero();        // gravitation at the centre, ECEF, m/s^2
  Vec3 g_i = Vec3::Zero();        // same, ECI
  Mat3 gamma_e = Mat3::Zero();    // gradient at the centre, ECEF, s^-2
  Mat3 gamma_b = Mat3::Zero();    // same, body axes
  Vec3 f_b = Vec3::Zero();        // error-free centre specific force, body, m/s^2
};

// The pieces of a generator, for tests that build one without a scenario.
struct Generator3Options {
  std::array<Real, 3> half_base{0.5L, 0.5L, 0.5L};
  int64_t dt_us = 10000;
  int64_t n_steps = 1;
  truth::AccelErrorParams accel;
  GyroErrorParams gyro;
  truth::BaroParams baro;
  SensorFaults3 faults;  // injected sensor faults (faults3d.hpp)
};

std::unique_ptr<Trajectory3> make_trajectory3(const Scenario3& s);
std::unique_ptr<gravity::Field> make_field3(const Scenario3& s);
// The EGM96 coefficient file of [gravity] model "egm96" ([sh] path, or the data folder's).
std::string egm96_path(const Scenario3& s);
// Quaternion (w, x, y, z) of a rotation matrix (Shepperd's method), w >= 0.
std::array<Real, 4> quat_from_dcm(const Mat3& C);

class Generator3 {
 public:
  explicit Generator3(const Scenario3& s);
  Generator3(std::shared_ptr<const Trajectory3> traj, std::shared_ptr<const gravity::Field> field,
             const Generator3Options& opt);

  const Trajectory3& trajectory() const { return *traj_; }
  const gravity::Field& field() const { return *field_; }
  int64_t n_steps() const { return opt_.n_steps; }
  int64_t dt_us() const { return opt_.dt_us; }
  Real time_of(int64_t k) const { return static_cast<Real>(k) * static_cast<Real>(opt_.dt_us) * 1e-6L; }
  const Vec3& offset(int j) const { return d_[static_cast<size_t>(j)]; }

  Truth3 truth(int64_t k) const;
  Truth3 truth_at(Real t) const;  // at any time (utime/seq 0)
  // Error-free specific force of the six accelerometers (body axes) for a
  // truth state, as frame() sends them (one eval_pairs at the centre).
  std::array<Vec3, 6> accel_true(const Truth3& t) const;
  Vec3 accel_true(const Truth3& t, int j) const { return accel_true(t)[static_cast<size_t>(j)]; }
  // The same from the field at accelerometer j's own position (gravitation()
  // there): the slow reference the fast path is checked against.
  Vec3 accel_reference(const Truth3& t, int j) const;
  void frame(int64_t k, gg_frame_t& out, Truth3* truth_out = nullptr) const;
  truth::BaroSample baro(int64_t k, const Truth3& t) const;
  double accel_bias(int j, int ax) const { return accel_.bias(j, ax); }
  double gyro_bias(int ax) const { return gyro_.bias(ax); }
  double gyro_scale(int ax) const { return gyro_.scale(ax); }
  // The cold-atom gradiometer ([coldatom]; nullptr when off).
  const ColdAtomSensor3* coldatom() const { return ca_.get(); }

 private:
  void init_errors();
  // Truth at t (seq/utime 0) and the six specific forces (the path of frame()).
  Truth3 sensors_at(Real t, std::array<Vec3, 6>& f) const;
  // Truth3 of a state and the field sample at its centre.
  static Truth3 make_truth(Real t, const State3& s, const gravity::FieldSample& c);
  // f_j = C_b_i^T (a_i + C_b_i'' d_j) - C_b_e^T g_j for the field g_j at sensor j.
  Vec3 specific_force(const State3& s, size_t j, const Vec3& g_j) const;
  // The six f_j from G_e at the + and - sensors of the three pairs.
  std::array<Vec3, 6> specific_forces(const State3& s, const Vec3 g_plus[3], const Vec3 g_minus[3]) const;
  std::shared_ptr<const Trajectory3> traj_;
  std::shared_ptr<const gravity::Field> field_;
  Generator3Options opt_;
  std::array<Vec3, 6> d_{};
  truth::AccelModel accel_;  // sensor error models (truth/sensors.hpp)
  truth::GyroModel gyro_;
  truth::BaroModel baro_;
  std::shared_ptr<const ColdAtomSensor3> ca_;
};


}  // namespace ggins::truth3d
