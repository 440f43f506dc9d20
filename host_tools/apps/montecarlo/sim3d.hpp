// Direct-call simulation of the 3-D firmware (gg_nav3d_step, no LCM) along
// the trajectories of the 3-D error analysis, with seeded sensor errors
// (Monte Carlo and the firmware linearization test). The frames and the truth
// come from the simulation library's 3-D generator (truth3d/generator3d.hpp:
// Taylor-jet trajectories, the six specific forces in long double as hi/lo
// pairs, the sensor error models of truth/sensors.hpp): the built-in
// scenarios fly its great circle (truth3d::GreatCircle3, the same closed form
// as the covariance's GreatCircle3D), truth3d scenarios their own trajectory.
// The errors drawn per run (18 accelerometer biases, gyro biases, barometer
// bias) are handed to the sensor models as fixed values; white noise and the
// barometer's Gauss-Markov error come from the models' counter-based streams
// under the run's noise seed. The firmware configuration is the simulation
// library's one mapping (truth3d::config3d) of the firmware settings the
// covariance scenario implies, plus the run's initial-state errors.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ggins/covariance/cov3d.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

extern "C" {
#include "ggins/frame.h"
#include "ggins/nav3d.h"
}

namespace ggins::montecarlo3d {

using covariance::Cov3DScenario;
using covariance::Mat3;
using covariance::Real;
using covariance::Vec3;

struct SensorErrors {
  std::array<double, 18> acc_bias{};   // sensor s, body axis j: 3 s + j, m/s^2
  std::array<double, 3> gyro_bias{};   // rad/s
  double acc_noise = 0, gyro_noise = 0;  // per-sample sigma
  uint64_t noise_seed = 0;  // seed of the white noise and the barometer's Gauss-Markov error
  // Initial-state errors handed to the firmware configuration (ECEF; psi: C^ = (I - [psi x]) C).
  std::array<double, 3> dr0{}, dv0{}, dg0{}, dpsi0{};
  // Barometer (when the scenario's loop is on): constant bias, m (the model's baro_bias_m column).
  double baro_bias_m = 0;
  double baro_gm_sigma_m = 0, baro_gm_tau_s = 600, baro_noise_m = 0;  // Gauss-Markov, white noise per sample
};

// Errors of the firmware against the truth at one time (ECEF).
struct ErrSample {
  double t = 0;
  Eigen::Vector3d dr, dv, dg, psi;
  double a_c = 0;  // the vertical loop's integral state (g_up_corr), m/s^2
};

class Sim3D {
 public:
  Sim3D(const Cov3DScenario& s, double rate_hz);
  // What a flight counted: steps flown, the OR of every output's health word and, per
  // bit, the outputs that had it set.
  struct FlyCounts {
    int64_t steps = 0;
    uint32_t health_or = 0;
    std::array<int64_t, 32> health_count{};
    bool stopped = false;  // `stop` answered true: the flight ended before its last step
  };
  // Flies [0, duration] and returns the errors every output_dt. Throws on a firmware error.
  // `stop` (when given) is asked every few hundred steps; true ends the flight there, with
  // the samples taken so far and counts->stopped set.
  std::vector<ErrSample> fly(const SensorErrors& e, double duration_s, double output_dt_s,
                             FlyCounts* counts = nullptr, const std::function<bool()>& stop = {}) const;
  // Steps of a flight of duration_s (steps 0..K: K + 1 outputs).
  int64_t steps(double duration_s) const { return std::llround(duration_s * 1e6 / double(dt_us_)) + 1; }
  gg_nav3d_config_t config(const SensorErrors& e) const;
  // The frame generator of a run with errors e over n_steps steps.
  truth3d::Generator3 generator(const SensorErrors& e, int64_t n_steps) const;
  const covariance::Nav3DModel& model() const { return *model_; }

 private:
  Cov3DScenario s_;
  std::shared_ptr<const gravity::Field> field_;
  std::shared_ptr<const truth3d::Trajectory3> traj_;
  std::shared_ptr<const covariance::Nav3DModel> model_;
  int64_t dt_us_;
  truth3d::Scenario3 fw_;  // the firmware settings, for truth3d::config3d
};

}  // namespace ggins::montecarlo3d
