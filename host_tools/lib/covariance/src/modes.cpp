#include "ggins/covariance/modes.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <stdexcept>

namespace ggins::covariance {

std::vector<cd> sorted_eigenvalues(const MatrixXd& F) {
  Eigen::EigenSolver<MatrixXd> es(F, false);
  if (es.info() != Eigen::Success) throw std::runtime_error("eigenvalues: EigenSolver failed");
  std::vector<cd> ev(es.eigenvalues().data(), es.eigenvalues().data() + es.eigenvalues().size());
  double scale = 0;
  for (const cd& z : ev) scale = std::max(scale, std::abs(z));
  const double tol = 1e-9 * scale;  // real parts equal up to round-off sort by imaginary part
  std::sort(ev.begin(), ev.end(), [tol](const cd& a, const cd& b) {
    if (std::abs(a.real() - b.real()) > tol) return a.real() > b.real();
    return a.imag() > b.imag();
  });
  return ev;
}

MatrixXd unstable_projector(const MatrixXd& F, double* lambda) {
  Eigen::EigenSolver<MatrixXd> es(F, true);
  if (es.info() != Eigen::Success) throw std::runtime_error("unstable_projector: EigenSolver failed");
  const auto& ev = es.eigenvalues();
  int iu = 0;
  for (int i = 1; i < ev.size(); ++i)
    if (ev(i).real() > ev(iu).real()) iu = i;
  if (std::abs(ev(iu).imag()) > 1e-12 * std::max(1.0, std::abs(ev(iu))))
    throw std::runtime_error("unstable_projector: the dominant eigenvalue is complex");
  const Eigen::MatrixXcd V = es.eigenvectors();
  const Eigen::MatrixXcd W = V.inverse();  // rows: left eigenvectors with W V = I
  const Eigen::MatrixXcd Pi = V.col(iu) * W.row(iu);
  if (lambda) *lambda = ev(iu).real();
  return Pi.real();
}

}  // namespace ggins::covariance
