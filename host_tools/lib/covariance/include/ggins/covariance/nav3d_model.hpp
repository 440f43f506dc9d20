// Linear error model of the 3-D gradiometer-integrated INS on a rotating
// Earth, the firmware design of nav3d.h: mechanization
// r''_i = f_i + G_i in ECI, gravity dead reckoning dG_e = Gamma_e dr_e in
// ECEF, Gamma_b from the six tri-axis accelerometers (diff3d.h: Gamma_b =
// [w x]^2 - (M + M^T)/2, Gao et al. eqs. 24-27), attitude from the gyros
// (strapdown) or fixed (space-stabilized platform).
//
// Error states, all resolved in ECEF (Earth-relative velocity; the frame in
// which the field is static, so that the frozen-time eigenvalues describe the
// error modes):
//   dr_e (3), dv_e (3) = error of dr_e/dt, dG_e (3) = G^_e - G_e(r_true),
//   psi_e (3, strapdown only): C^_b_e = (I - [psi x]) C_b_e,
//   a_c (1, baro loop only): the vertical loop's integral state.
// Disturbances: 18 accelerometer biases b(k, j) (sensor k of diff3d.h, body
// axis j, index 3k + j), 3 gyro biases (strapdown), baro bias and baro
// Gauss-Markov (baro loop).
//
//   dr'   = dv                                                     (- k1 e u)
//   dv'   = -W^2 dr - 2 W dv + dG + [f_e x] psi + C_b_e df_c       (- k2 e u + k1 e W u - a_c u)
//   dG'   = Gamma_e dv + ([(Gamma_e v) x] - Gamma_e [v x]) psi
//           + C_b_e dGamma_b C_e_b v                              (- k1 e Gamma_e u)
//   psi'  = -W psi - C_b_e dw
//   a_c'  = k3 e,     e = u^T dr - b - m - n
// with W = [omega_ie z^ x], f_e = a_e + 2 W v + W^2 r - G_e the centre
// specific force, df_c = (1/6) sum_k b_k (diff3d.h: mean of the six),
// dM[:, k] = (b_k - b_{k+3}) / (2 d_k),
// dGamma_b = [w x][dw x] + [dw x][w x] - (dM + dM^T)/2,
// u the up unit vector (ellipsoid normal). The k1 e W u term: nav3d applies
// the loop's position correction to r_i at fixed v_i (nav3d.c baro_step), which
// changes the Earth-relative velocity by -w x dr. Welker et al. eq. (9)-(10) is the
// non-rotating, planar, stabilized special case (tests/covariance).
// Derivation: docs/error-analysis.md, "3-D".
#pragma once

#include <array>
#include <memory>

#include "ggins/covariance/model.hpp"
#include "ggins/covariance/trajectory3d.hpp"

namespace ggins::covariance {

struct Nav3DBaro {
  bool on = false;
  std::array<double, 3> poles_radps{0.01, 0.02, 0.03};
  double omega_s2 = 0;         // w_s^2 in k2 (firmware's configured value); 0: |G(r0)|/|r0| from the field
  double gm_tau_s = 600.0;     // baro Gauss-Markov correlation time
  double gm_sigma_m = 0.0;
  double noise_sigma_m = 0.0;  // white noise per sample
  double period_s = 1.0;
};

struct Nav3DModelConfig {
  std::array<double, 3> half_base_m{0.5, 0.5, 0.5};  // a, b, c
  // White noise: per-sample sigma at rate_hz on each of the 18 readings, and
  // on each gyro axis (rad/s per sample); density sigma^2 / rate_hz.
  double acc_noise_sigma_mps2 = 0.0;
  double gyro_noise_sigma_radps = 0.0;
  double rate_hz = 100.0;
  Nav3DBaro baro;
};

class Nav3DModel final : public LinearErrorModel {
 public:
  Nav3DModel(std::shared_ptr<const gravity::Field> field, std::shared_ptr<const Trajectory3D> traj,
             Platform platform, Nav3DModelConfig cfg);

  int n_states() const override { return n_; }
  int n_dist() const override { return m_; }
  std::vector<std::string> state_keys() const override;
  std::vector<std::string> dist_keys() const override;
  void matrices(double t, MatrixXd& F, MatrixXd& Gam) const override;
  void dist_dynamics(double t, MatrixXd& D) const override;
  bool has_process_noise() const override;
  void process_noise(double t, MatrixXd& Qa) const override;

  bool strapdown() const { return plat_ == Platform::kStrapdown; }
  bool baro() const { return cfg_.baro.on; }
  double k1() const { return k1_; }
  double k2() const { return k2_; }
  double k3() const { return k3_; }
  const Trajectory3D& trajectory() const { return *traj_; }
  const gravity::Field& field() const { return *field_; }
  // Up unit vector (WGS-84 ellipsoid normal) at the trajectory point.
  Eigen::Vector3d up(double t) const;
  // C_n_e (columns north, east, down in ECEF; geodetic) at the trajectory point.
  Eigen::Matrix3d ned_to_ecef(double t) const;

  // State indices.
  static constexpr int kR = 0, kV = 3, kG = 6, kPsi = 9;
  int idx_ac() const { return strapdown() ? 12 : 9; }
  // Disturbance indices.
  static constexpr int kAcc = 0;  // 18
  int idx_gyro() const { return 18; }
  int idx_baro_bias() const { return strapdown() ? 21 : 18; }

 private:
  std::shared_ptr<const gravity::Field> field_;
  std::shared_ptr<const Trajectory3D> traj_;
  Platform plat_;
  Nav3DModelConfig cfg_;
  int n_ = 9, m_ = 18;
  double k1_ = 0, k2_ = 0, k3_ = 0;
};

}  // namespace ggins::covariance
