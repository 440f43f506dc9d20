#include "ggins/covariance/propagate.hpp"

#include <cmath>
#include <stdexcept>

namespace ggins::covariance {

namespace {

// Lyapunov right-hand side, Welker et al. eq. (11) (+ Qa if the model has noise).
MatrixXd lyap_rhs(const MatrixXd& Fa, const MatrixXd& P, const MatrixXd* Qa) {
  MatrixXd d = Fa * P;
  d += d.transpose().eval();
  if (Qa) d += *Qa;
  return d;
}

}  // namespace

MatrixXd transition_matrix(const LinearErrorModel& model, double t_end, double dt) {
  const int N = model.n_states() + model.n_dist();
  if (!(dt > 0) || !(t_end >= 0)) throw std::invalid_argument("transition_matrix: dt must be > 0, t_end >= 0");
  const long nsteps = std::lround(std::ceil(t_end / dt - 1e-9));
  const double h = nsteps > 0 ? t_end / double(nsteps) : dt;
  MatrixXd Phi = MatrixXd::Identity(N, N);
  for (long k = 0; k < nsteps; ++k) {
    const double t = k * h;
    const MatrixXd F0 = model.augmented(t), F1 = model.augmented(t + 0.5 * h), F2 = model.augmented(t + h);
    const MatrixXd k1 = F0 * Phi;
    const MatrixXd k2 = F1 * (Phi + 0.5 * h * k1);
    const MatrixXd k3 = F1 * (Phi + 0.5 * h * k2);
    const MatrixXd k4 = F2 * (Phi + h * k3);
    Phi += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  return Phi;
}

VectorXd sigmas(const MatrixXd& P, int k) {
  VectorXd s(k);
  for (int i = 0; i < k; ++i) s(i) = std::sqrt(std::max(0.0, P(i, i)));
  return s;
}

std::vector<Sample> propagate(const LinearErrorModel& model, const MatrixXd& P0,
                              const PropagationOptions& opt) {
  const int N = model.n_states() + model.n_dist();
  if (P0.rows() != N || P0.cols() != N) throw std::invalid_argument("propagate: P0 has the wrong size");
  if (!(opt.dt > 0) || !(opt.t_end >= 0) || !(opt.output_dt > 0))
    throw std::invalid_argument("propagate: dt, output_dt must be > 0 and t_end >= 0");
  const bool noise = model.has_process_noise();
  if (noise && opt.method == Method::kTransition)
    throw std::invalid_argument("propagate: the transition-matrix method needs a noise-free model; use kLyapunov");

  const long nsteps = std::lround(std::ceil(opt.t_end / opt.dt - 1e-9));
  const double h = nsteps > 0 ? opt.t_end / double(nsteps) : opt.dt;  // exact end time
  long every = std::max(1L, std::lround(opt.output_dt / h));

  std::vector<Sample> out;
  out.reserve(size_t(nsteps / every + 2));
  MatrixXd Phi = MatrixXd::Identity(N, N);
  MatrixXd P = P0;
  MatrixXd Qa0, Qa1, Qa2;
  auto emit = [&](double t) {
    Sample s;
    s.t = t;
    if (opt.method == Method::kTransition) {
      s.P = Phi * P0 * Phi.transpose();
    } else {
      s.P = P;
    }
    s.P = 0.5 * (s.P + s.P.transpose());
    out.push_back(std::move(s));
  };
  emit(0.0);
  for (long k = 0; k < nsteps; ++k) {
    const double t = k * h;
    // Fa at t, t + h/2, t + h: classical RK4 nodes.
    const MatrixXd F0 = model.augmented(t);
    const MatrixXd F1 = model.augmented(t + 0.5 * h);
    const MatrixXd F2 = model.augmented(t + h);
    if (opt.method == Method::kTransition) {
      const MatrixXd k1 = F0 * Phi;
      const MatrixXd k2 = F1 * (Phi + 0.5 * h * k1);
      const MatrixXd k3 = F1 * (Phi + 0.5 * h * k2);
      const MatrixXd k4 = F2 * (Phi + h * k3);
      Phi += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    } else {
      const MatrixXd* q0 = nullptr;
      const MatrixXd* q1 = nullptr;
      const MatrixXd* q2 = nullptr;
      if (noise) {
        model.process_noise(t, Qa0);
        model.process_noise(t + 0.5 * h, Qa1);
        model.process_noise(t + h, Qa2);
        q0 = &Qa0;
        q1 = &Qa1;
        q2 = &Qa2;
      }
      const MatrixXd k1 = lyap_rhs(F0, P, q0);
      const MatrixXd k2 = lyap_rhs(F1, P + 0.5 * h * k1, q1);
      const MatrixXd k3 = lyap_rhs(F1, P + 0.5 * h * k2, q1);
      const MatrixXd k4 = lyap_rhs(F2, P + h * k3, q2);
      P += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      P = 0.5 * (P + P.transpose()).eval();
    }
    if ((k + 1) % every == 0 || k + 1 == nsteps) emit((k + 1) * h);
  }
  return out;
}

}  // namespace ggins::covariance
