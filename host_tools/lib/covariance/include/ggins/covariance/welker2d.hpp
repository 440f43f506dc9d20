// The 2-D gradiometer-integrated INS error model of Welker, Pachter & Huffman
// (seed welker-pachter-huffman-ggi-integrated-ins.txt), section V:
//   states  dx = (dx, dz, dVx, dVz, dGx, dGz)                       (6)
//   biases  d  = (df1x, df2x, df3x, df4x, df1z, df2z, df3z, df4z)   (8)
//   d/dt dx = F(t) dx + Gamma(t) d                                  (eq. 7)
// F from eq. (9), Gamma from eq. (10), with the sign fix of docs/design.md: the
// printed "-dG" in the velocity error equations is a typo, dV' = 1/4 sum df + dG
// (the +1 entries of F in eq. 9, consistent with r'' = f + G).
//
// The time-varying entries are NOT the paper's closed forms: the gradient
// block of F is the Field's gradient tensor evaluated on the trajectory and the
// V/(2a) entries of Gamma use the trajectory's velocity, so any field and any
// planar trajectory work. tests/covariance checks them against the closed
// forms of section VI for the spherical Earth.
#pragma once

#include <memory>

#include "ggins/covariance/model.hpp"
#include "ggins/covariance/trajectory.hpp"
#include "ggins/gravity/field.hpp"

namespace ggins::covariance {

class Welker2DModel final : public LinearErrorModel {
 public:
  enum class GradientSource {
    kCentre,    // Field gradient tensor at the platform centre (the paper's model)
    kBaseline,  // (G(r - a e_x) ... ) central differences over the accelerometer
                // baseline: what the differenced accelerometers of Fig. 2 measure
  };
  // a, b: half-baselines (m) of accelerometers 1:(+a,0) 2:(0,+b) 3:(-a,0) 4:(0,-b).
  Welker2DModel(std::shared_ptr<const gravity::Field> field, std::shared_ptr<const Trajectory> traj,
                double a_m, double b_m, GradientSource src = GradientSource::kCentre);

  int n_states() const override { return 6; }
  int n_dist() const override { return 8; }
  std::vector<std::string> state_keys() const override;
  std::vector<std::string> dist_keys() const override;
  void matrices(double t, MatrixXd& F, MatrixXd& Gam) const override;

  // Optional white noise on the eight accelerometer axes, two-sided spectral
  // density psd_i ((m/s^2)^2/Hz = sigma_i^2 / sample rate). It enters through
  // the same Gamma(t): Qa = [Gamma S Gamma^T 0; 0 0]. Zero in the paper.
  void set_white_noise_psd(const VectorXd& psd);
  bool has_process_noise() const override { return noise_; }
  void process_noise(double t, MatrixXd& Qa) const override;

  // The 2x2 gradient block (dGx/dx dGx/dz; dGz/dx dGz/dz) used in F at time t.
  Eigen::Matrix2d gradient(double t) const;
  const Trajectory& trajectory() const { return *traj_; }
  const gravity::Field& field() const { return *field_; }

  // Indices into the state vector.
  enum { kX = 0, kZ = 1, kVx = 2, kVz = 3, kGx = 4, kGz = 5 };

 private:
  std::shared_ptr<const gravity::Field> field_;
  std::shared_ptr<const Trajectory> traj_;
  double a_, b_;
  GradientSource src_;
  VectorXd psd_ = VectorXd::Zero(8);
  bool noise_ = false;
};

}  // namespace ggins::covariance
