// Covariance propagation of an augmented linear error model.
//
//   P' = Fa P + P Fa^T (+ Qa)                       (Welker et al., eq. 11)
//
// Two fixed-step fourth-order methods:
//   kTransition: Phi' = Fa(t) Phi, Phi(0) = I by classical RK4, then
//                P(t) = Phi(t) P0 Phi(t)^T (exact for the noise-free model of
//                the paper; P stays symmetric positive semidefinite by form);
//   kLyapunov:   RK4 directly on the matrix Lyapunov equation (allows Qa).
// The two are independent implementations; their agreement and step halving
// are the accuracy evidence (tests/covariance, docs/error-analysis.md).
#pragma once

#include <functional>
#include <vector>

#include "ggins/covariance/model.hpp"

namespace ggins::covariance {

enum class Method { kTransition, kLyapunov };

struct PropagationOptions {
  double t_end = 3600.0;   // s
  double dt = 1.0;         // integration step, s
  double output_dt = 10.0; // sample spacing, s (rounded to a multiple of dt)
  Method method = Method::kTransition;
};

struct Sample {
  double t = 0;
  MatrixXd P;  // augmented covariance, (n+m) x (n+m)
};

// Propagates P0 (augmented) over [0, t_end]; samples at t = 0, output_dt, ..., t_end.
// Throws std::invalid_argument on bad options or dimensions.
std::vector<Sample> propagate(const LinearErrorModel& model, const MatrixXd& P0,
                              const PropagationOptions& opt);

// Transition matrix Phi(t_end, 0) of the augmented model (RK4 on Phi' = Fa Phi,
// steps of at most dt).
MatrixXd transition_matrix(const LinearErrorModel& model, double t_end, double dt);

// One-sigma values (sqrt of the diagonal) of the first k states of P.
VectorXd sigmas(const MatrixXd& P, int k);

}  // namespace ggins::covariance
