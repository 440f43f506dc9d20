// The Welker et al. 2-D error model (welker2d.hpp) with the barometric
// vertical loop of the firmware (firmware/include/ggins/vchan.h), in
// its continuous-time form (the firmware's discrete loop has its poles at
// exp(-p_i T), so for p T << 1 the two agree; docs/vertical.md).
//
// u = up unit vector r/|r| in (x, z), Gamma = the 2x2 gradient block, and the
// innovation e = u^T dr - b - m - n (barometer error: constant bias b,
// first-order Gauss-Markov m, white noise n). With the loop's gains
//   k1 = p1 + p2 + p3, k2 = p1p2 + p1p3 + p2p3 + 2 w_s^2, k3 = p1 p2 p3:
//   dr' = dv - k1 e u
//   dv' = dG + (1/4) sum df - k2 e u - a_c u          (Welker eq. 9 rows + the loop)
//   dG' = Gamma dv + Gamma_d d - k1 e Gamma u         (nav2d corrects G by Gamma dr)
//   a_c' = k3 e
// states (dx, dz, dVx, dVz, dGx, dGz, a_c), disturbances (8 accelerometer
// biases, b, m) with m' = -m/tau + white noise of density 2 sigma_m^2 / tau;
// n is white with density sigma_n^2 T (T the barometer period) and enters
// through the same column as b.
#pragma once

#include <array>
#include <memory>

#include "ggins/covariance/welker2d.hpp"

namespace ggins::covariance {

struct BaroLoopParams {
  std::array<double, 3> poles_radps{0.01, 0.02, 0.03};
  double omega_s2 = 0;        // w_s^2 used in k2 (the firmware's configured value), s^-2
  double gm_tau_s = 600.0;    // barometer Gauss-Markov correlation time
  double gm_sigma_m = 0.0;    // its stationary sigma
  double noise_sigma_m = 0.0; // white noise per sample
  double period_s = 1.0;      // barometer sample period
};

class Welker2DBaroModel final : public LinearErrorModel {
 public:
  Welker2DBaroModel(std::shared_ptr<const Welker2DModel> base, BaroLoopParams p);
  int n_states() const override { return 7; }
  int n_dist() const override { return 10; }
  std::vector<std::string> state_keys() const override;
  std::vector<std::string> dist_keys() const override;
  void matrices(double t, MatrixXd& F, MatrixXd& Gam) const override;
  void dist_dynamics(double t, MatrixXd& D) const override;
  bool has_process_noise() const override { return true; }
  void process_noise(double t, MatrixXd& Qa) const override;

  // Up unit vector (x, z) of the reference trajectory at t.
  Eigen::Vector2d up(double t) const;
  double k1() const { return k1_; }
  double k2() const { return k2_; }
  double k3() const { return k3_; }
  enum { kAc = 6, kBaroBias = 8, kBaroGm = 9 };  // state / disturbance indices

 private:
  std::shared_ptr<const Welker2DModel> base_;
  BaroLoopParams p_;
  double k1_, k2_, k3_;
};

}  // namespace ggins::covariance
