// Sensor error models of the simulation library: the accelerometers, the
// gyros and the barometer, as every frame generator (2-D truth/generator.hpp,
// 3-D truth3d/generator3d.hpp) applies them. A change of an error model is an
// edit of this header and sensors.cpp only.
//
// Random numbers come from a counter-based generator keyed by
// (seed, stream, k, i, j): splitmix64 hashing and Box-Muller, so the error of
// step k is a pure function of the seed and k (frames can be regenerated in
// any order, resent, replayed). Each model owns its streams; the 2-D and 3-D
// accelerometers and gyros draw from distinct streams (AccelStreams), the
// barometer from the same ones in both.
//
// Accelerometer, sensor i, axis j (measured axes only):
//   f_meas = (1 + s_ij) f + b_ij + n_ij(k)
//   b_ij = bias_mps2[i][j] + bias_sigma w,  s_ij = scale[i][j] + scale_sigma w  (constant per run)
//   n_ij(k) white, sigma noise_sigma_mps2;  w standard normal deviates.
// Gyro, axis j:  w_meas = (1 + s_j) w + b_j + n_j(k), likewise.
// Barometer, sample j (every `every` steps):
//   h_baro = h_true + bias + m_j + n_j (+ -outlier_m),
//   m_0 = sigma w_0,  m_{j+1} = phi m_j + sigma sqrt(1 - phi^2) w_{j+1},  phi = exp(-T/tau)
//   (first-order Gauss-Markov by its exact discrete recursion, stationary from the start),
//   n_j white; optional dropouts (probability or windows), outliers, NaN samples flagged OK.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "ggins/frame.h"
#include "ggins/truth/scenario.hpp"
#include "ggins/truth/trajectory.hpp"

namespace ggins::truth {

// Standard normal deviate number `stream` of generator `seed`, element
// (k, i, j): a pure function (splitmix64 hashing + Box-Muller), portable.
double counter_normal(uint64_t seed, uint64_t stream, uint64_t k, uint64_t i, uint64_t j);
// Uniform deviate in [0, 1) from the same construction.
double counter_uniform(uint64_t seed, uint64_t stream, uint64_t k, uint64_t i, uint64_t j);

// Gyro error parameters ([gyro] of a 3-D scenario).
struct GyroErrorParams {
  uint64_t seed = 2;
  double bias_sigma_radps = 0, noise_sigma_radps = 0, scale_sigma = 0;
  std::array<double, 3> bias_radps{0, 0, 0};
  std::array<double, 3> scale{0, 0, 0};
};

// Counter-based streams of a triad's constant bias, constant scale factor and white noise.
struct SensorStreams {
  uint64_t bias, scale, noise;
};
constexpr SensorStreams kAccelStreams2D{1, 2, 3};
constexpr SensorStreams kAccelStreams3D{31, 32, 33};
constexpr SensorStreams kGyroStreams3D{41, 42, 43};

// The accelerometers of one platform: n sensors, the measured axes of each.
class AccelModel {
 public:
  AccelModel() = default;
  // measured[j]: axis j is read (an unmeasured axis has no bias or scale error).
  AccelModel(const AccelErrorParams& p, int n_sensors, std::array<bool, 3> measured, SensorStreams streams);
  // Reading of sensor i, axis j at step k from its error-free specific force f, m/s^2.
  Real read(int64_t k, int i, int j, Real f) const;
  double bias(int i, int j) const { return bias_[static_cast<size_t>(i)][static_cast<size_t>(j)]; }
  double scale(int i, int j) const { return scale_[static_cast<size_t>(i)][static_cast<size_t>(j)]; }

 private:
  AccelErrorParams p_;
  SensorStreams st_{kAccelStreams2D};
  std::array<std::array<double, 3>, kMaxAcc> bias_{}, scale_{};
};

// A gyro triad (body axes).
class GyroModel {
 public:
  GyroModel() = default;
  GyroModel(const GyroErrorParams& p, SensorStreams streams);
  // Reading of axis j at step k from the true inertial body rate w, rad/s.
  Real read(int64_t k, int j, Real w) const;
  double bias(int j) const { return bias_[static_cast<size_t>(j)]; }
  double scale(int j) const { return scale_[static_cast<size_t>(j)]; }

 private:
  GyroErrorParams p_;
  SensorStreams st_{kGyroStreams3D};
  std::array<double, 3> bias_{}, scale_{};
};

// Barometer of step k. A sample is due every `every` steps (sample j at step j * every).
struct BaroSample {
  bool due = false;       // a sample time
  bool dropped = false;   // due but not sent (dropout: probability or scheduled window)
  bool outlier = false;   // +-outlier_m added
  bool invalid = false;   // sent as NaN with status OK
  double alt_m = NAN;     // what the frame carries (NaN when none)
  int32_t status = GG_SENSOR_ABSENT;
  double true_alt_m = 0;  // h_true at the sample time, m
  double error_m = 0;     // bias + m_j + n_j (+ outlier), m (0 when not due)
  double gm_m = 0;        // m_j, m
};

class BaroModel {
 public:
  BaroModel() = default;
  // The Gauss-Markov sequence of every sample of a run of n_steps steps of dt_us.
  BaroModel(const BaroParams& p, int64_t every, int64_t n_steps, int64_t dt_us);
  int64_t every() const { return every_; }
  // Sample of step k at time t_s given the true altitude at the sample time.
  BaroSample sample(int64_t k, double t_s, double true_alt_m) const;

 private:
  BaroParams p_;
  int64_t every_ = 1;
  std::vector<double> gm_;  // m_j per sample j
};

// A reading sent as a double and its sub-ulp residual (frame f + f_lo).
inline void encode_hilo(Real x, double& hi, double& lo) {
  hi = static_cast<double>(x);
  lo = static_cast<double>(x - static_cast<Real>(hi));
}

}  // namespace ggins::truth
