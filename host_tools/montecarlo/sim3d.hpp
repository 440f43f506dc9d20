// Direct-call simulation of the 3-D firmware (gg_nav3d_step, no LCM) along
// the analytic trajectories of the 3-D error analysis (trajectory3d.hpp),
// with seeded sensor errors (Monte Carlo and the firmware
// linearization test). The truth is computed in long double and handed to
// the firmware as hi/lo double pairs:
//   f_s = C_e_b (a_i,e - G_e(r_e + C_b_e d_s)) + ([wdot x] + [w x]^2) d_s   (Gao et al. eq. 22)
// with a_i,e = a_e + 2 W v_e + W^2 r_e the inertial acceleration of the
// centre resolved in ECEF, plus the constant biases and white noise;
// gyros (strapdown) w_ib_b + bias + noise; with the scenario's barometric loop
// on, a barometer sample every baro period: the true geodetic height + bias
// + first-order Gauss-Markov (exact recursion, stationary start) + white noise.
#pragma once

#include <array>
#include <memory>
#include <random>
#include <vector>

#include "ggins/covariance/cov3d.hpp"

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
  uint64_t noise_seed = 0;
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
  // Flies [0, duration] and returns the errors every output_dt. Throws on a firmware error.
  std::vector<ErrSample> fly(const SensorErrors& e, double duration_s, double output_dt_s) const;
  gg_nav3d_config_t config(const SensorErrors& e) const;
  // baro_extra_m: the Gauss-Markov + noise part of this step's barometer sample (fly() draws it).
  void frame(int64_t k, const SensorErrors& e, std::mt19937_64* rng, gg_frame_t* fr, double baro_extra_m = 0) const;
  const covariance::Nav3DModel& model() const { return *model_; }

 private:
  Cov3DScenario s_;
  std::shared_ptr<const gravity::Field> field_;
  std::shared_ptr<const covariance::Trajectory3D> traj_;
  std::shared_ptr<const covariance::Nav3DModel> model_;
  int64_t dt_us_;
};

}  // namespace ggins::montecarlo3d
