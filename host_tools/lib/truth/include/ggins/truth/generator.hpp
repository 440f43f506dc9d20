// Truth generator: from a scenario's analytic trajectory and gravitation
// field, the sensor frame the firmware sees at step k and the truth it is
// judged against.
//
// Each accelerometer i sits at platform offset d_i (space-stabilized platform:
// platform axes = inertial axes). Its error-free reading is the specific force
//   f_i = a(t) - G(r(t) + d_i),
// with G evaluated by the field model *at the sensor's own position* (not by
// a Taylor expansion around the centre), in long double. The 2-D layout of
// Welker et al.: sensors 1..4 (frame index 0..3) at (x, z) offsets
// (+a, 0), (0, +b), (-a, 0), (0, -b); axis y reads 0.
// Sensor errors (each off by default): the accelerometer and barometer models
// of sensors.hpp (f_meas = (1 + s) f + b + n per measured axis; barometer
// bias + Gauss-Markov + noise, dropouts, outliers), counter-based, so frame k
// is the same whenever and however often it is generated (resends, replays,
// Monte Carlo runs with the same seed).
#pragma once

#include <array>
#include <cstdint>
#include <cmath>
#include <memory>
#include <vector>

#include "ggins/frame.h"
extern "C" {
#include "ggins/gmodel.h"
}
#include "ggins/gravity/field.hpp"
#include "ggins/truth/scenario.hpp"
#include "ggins/truth/sensors.hpp"
#include "ggins/truth/trajectory.hpp"

namespace ggins::truth {

// Truth at the platform centre at one step.
struct TruthState {
  int64_t seq = 0;
  int64_t utime = 0;           // microseconds since the start of the run
  Real t_s = 0;
  Kinematics kin;              // r, v, a of the centre
  Vec3 g = Vec3::Zero();       // gravitation at the centre, m/s^2
  Mat3 gamma = Mat3::Zero();   // gradient at the centre, s^-2
  Vec3 f_c = Vec3::Zero();     // error-free centre specific force a - G, m/s^2
};

std::unique_ptr<Trajectory> make_trajectory(const Scenario& s);
std::unique_ptr<gravity::Field> make_field(const Scenario& s);

class Generator {
 public:
  explicit Generator(const Scenario& s);
  // The same with another truth gravitation field in place of the scenario's [gravity]
  // (a tool's own model of the true field, e.g. rw-eq8's deflected point mass).
  Generator(const Scenario& s, std::shared_ptr<const gravity::Field> field);

  const Scenario& scenario() const { return sc_; }
  const Trajectory& trajectory() const { return *traj_; }
  const gravity::Field& field() const { return *field_; }
  int64_t n_steps() const { return n_steps_; }
  int64_t dt_us() const { return dt_us_; }
  Real time_of(int64_t k) const;  // t_k = k dt, s

  // Truth at the centre at step k.
  TruthState truth(int64_t k) const;
  // Sensor frame of step k (f rounded to double); optionally its truth too.
  void frame(int64_t k, gg_frame_t& out, TruthState* truth_out = nullptr) const;

  // Barometer sample of step k (given the truth of that step).
  BaroSample baro(int64_t k, const TruthState& t) const;
  // Altitude h = |r| - r_ref of a position, m.
  Real altitude(const Vec3& r) const;
  // The onboard zonal gravitation model the firmware is configured with
  // (Scenario::nav_model(); evaluated by the firmware's own gmodel.c).
  Vec3 model_g(const Vec3& r) const;

  // Platform offset of accelerometer i (inertial = platform axes), m.
  const Vec3& offset(int i) const { return offsets_[static_cast<size_t>(i)]; }
  // Total constant bias and scale factor of accelerometer i, axis j.
  double bias(int i, int j) const { return accel_.bias(i, j); }
  double scale(int i, int j) const { return accel_.scale(i, j); }

 private:
  Scenario sc_;
  std::unique_ptr<Trajectory> traj_;
  std::shared_ptr<const gravity::Field> field_;
  int64_t dt_us_;
  int64_t n_steps_;
  int n_acc_;
  std::array<Vec3, kMaxAcc> offsets_{};
  std::array<int, 3> axes_{};  // which axes are measured (2-D: x and z)
  int n_axes_ = 0;
  AccelModel accel_;  // the accelerometers' error model (sensors.hpp)
  BaroModel baro_;    // the barometer's (sensors.hpp)
  std::shared_ptr<gg_gmodel_t> model_;  // onboard model (null if it does not initialise)
  std::shared_ptr<gg_gmodel_config_t> model_cfg_;  // its configuration (zonal part only)
};

}  // namespace ggins::truth
