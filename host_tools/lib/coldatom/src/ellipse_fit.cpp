#include "ggins/coldatom/ellipse_fit.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace ggins::coldatom {

EllipseFit fit_ellipse(const std::vector<double>& x, const std::vector<double>& y) {
  EllipseFit out;
  const std::size_t n = x.size();
  if (n < 6 || y.size() != n) return out;
  // Centre and scale the data (conditioning); A, B, C keep their ratios under
  // translation and uniform scaling, so dphi needs no back-transformation.
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) { mx += x[i]; my += y[i]; }
  mx /= static_cast<double>(n); my /= static_cast<double>(n);
  double sc = 0;
  for (std::size_t i = 0; i < n; ++i) sc += (x[i] - mx) * (x[i] - mx) + (y[i] - my) * (y[i] - my);
  sc = std::sqrt(sc / static_cast<double>(n));
  if (!(sc > 0)) return out;
  Eigen::MatrixXd D1(n, 3), D2(n, 3);
  for (std::size_t i = 0; i < n; ++i) {
    const double u = (x[i] - mx) / sc, v = (y[i] - my) / sc;
    const Eigen::Index r = static_cast<Eigen::Index>(i);
    D1(r, 0) = u * u; D1(r, 1) = u * v; D1(r, 2) = v * v;
    D2(r, 0) = u; D2(r, 1) = v; D2(r, 2) = 1.0;
  }
  // Halir & Flusser 1998, section 3.
  const Eigen::Matrix3d S1 = D1.transpose() * D1, S2 = D1.transpose() * D2, S3 = D2.transpose() * D2;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(S3);
  if (!lu.isInvertible()) return out;
  const Eigen::Matrix3d T = -lu.solve(S2.transpose());
  const Eigen::Matrix3d M = S1 + S2 * T;
  Eigen::Matrix3d Mc;  // C1^{-1} M, C1 = [[0,0,2],[0,-1,0],[2,0,0]]
  Mc.row(0) = M.row(2) / 2.0;
  Mc.row(1) = -M.row(1);
  Mc.row(2) = M.row(0) / 2.0;
  Eigen::EigenSolver<Eigen::Matrix3d> es(Mc);
  int best = -1;
  double best_c = 0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = es.eigenvectors().col(k).real();
    const double c = 4.0 * a(0) * a(2) - a(1) * a(1);
    if (c > 0 && std::fabs(es.eigenvalues()(k).imag()) < 1e-12 * (1.0 + std::fabs(es.eigenvalues()(k).real()))) {
      if (best < 0 || c > best_c) { best = k; best_c = c; }
    }
  }
  if (best < 0) return out;
  Eigen::Vector3d a1 = es.eigenvectors().col(best).real();
  a1 /= std::sqrt(4.0 * a1(0) * a1(2) - a1(1) * a1(1));
  if (a1(0) < 0) a1 = -a1;  // A, C > 0: the sign of B then gives the sign of cos(dphi)
  const Eigen::Vector3d a2 = T * a1;
  // Back to the caller's coordinates: u = (x - mx)/sc.
  const double A = a1(0), B = a1(1), C = a1(2), Du = a2(0), Ev = a2(1), Fu = a2(2);
  Conic k;
  k.A = A / (sc * sc); k.B = B / (sc * sc); k.C = C / (sc * sc);
  k.D = -2 * A * mx / (sc * sc) - B * my / (sc * sc) + Du / sc;
  k.E = -2 * C * my / (sc * sc) - B * mx / (sc * sc) + Ev / sc;
  k.F = A * mx * mx / (sc * sc) + B * mx * my / (sc * sc) + C * my * my / (sc * sc) - Du * mx / sc - Ev * my / sc + Fu;
  const double s4 = 4.0 * k.A * k.C - k.B * k.B;  // rescale to 4AC - B^2 = 1
  const double f = 1.0 / std::sqrt(s4);
  k.A *= f; k.B *= f; k.C *= f; k.D *= f; k.E *= f; k.F *= f;
  out.conic = k;
  double c = -B / (2.0 * std::sqrt(A * C));
  if (c > 1) c = 1;
  if (c < -1) c = -1;
  out.dphi = std::acos(c);
  // centre: gradient of the conic vanishes
  const double det = 4 * k.A * k.C - k.B * k.B;
  out.x0 = (k.B * k.E - 2 * k.C * k.D) / det;
  out.y0 = (k.B * k.D - 2 * k.A * k.E) / det;
  out.ok = std::isfinite(out.dphi);
  return out;
}

}  // namespace ggins::coldatom
