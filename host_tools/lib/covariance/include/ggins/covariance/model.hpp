// Linear error models for covariance analysis.
//
// A model is data + two time-varying matrices: the navigation-error dynamics
// F(t) (n x n) and the disturbance input matrix Gamma(t) (n x m) of
//     d/dt dx = F(t) dx + Gamma(t) d                (Welker et al., eq. 7)
// The disturbances d are themselves states of the augmented system
//     d/dt [dx; d] = Fa(t) [dx; d] + w,  Fa = [F Gamma; 0 D(t)]   (eq. 11 with D = 0)
// D(t) (m x m) is zero for constant random biases (the paper's model) and can
// be -1/tau for Gauss-Markov errors (a barometer). w is optional
// continuous white noise with spectral density Qa(t) ((n+m) x (n+m)).
// State and disturbance dimensions are run-time data so the same propagator
// serves the 2-D model of the paper, a baro-augmented model and the 3-D one.
//
// Naming: in code `Gam` is the paper's disturbance input matrix Gamma (eq. 10);
// the gravitation gradient (also written Gamma in docs/design.md) is `grad`.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace ggins::covariance {

using Eigen::MatrixXd;
using Eigen::VectorXd;

class LinearErrorModel {
 public:
  virtual ~LinearErrorModel() = default;
  virtual int n_states() const = 0;  // n: navigation error states
  virtual int n_dist() const = 0;    // m: disturbance (augmented) states
  // Output keys with units, e.g. "x_m"; used as CSV columns and JSON keys.
  virtual std::vector<std::string> state_keys() const = 0;
  virtual std::vector<std::string> dist_keys() const = 0;
  // F(t) (n x n) and Gamma(t) (n x m). Must be thread-safe for const calls.
  virtual void matrices(double t, MatrixXd& F, MatrixXd& Gam) const = 0;
  // Disturbance dynamics D(t) (m x m); constant biases: zero.
  virtual void dist_dynamics(double /*t*/, MatrixXd& D) const { D.setZero(n_dist(), n_dist()); }
  // Continuous white noise on the augmented state; none by default.
  virtual bool has_process_noise() const { return false; }
  virtual void process_noise(double /*t*/, MatrixXd& Qa) const {
    Qa.setZero(n_states() + n_dist(), n_states() + n_dist());
  }

  // Augmented dynamics Fa(t) = [F Gamma; 0 D]   (Welker et al., eq. 11).
  MatrixXd augmented(double t) const;
};

}  // namespace ggins::covariance
