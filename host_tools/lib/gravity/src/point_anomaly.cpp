#include "ggins/gravity/point_anomaly.hpp"

#include "ggins/gravity/wgs84.hpp"
#include "detail.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

namespace ggins::gravity {

PointMassAnomalyField::PointMassAnomalyField(std::vector<PointMass> masses, std::string label)
    : masses_(std::move(masses)), label_(std::move(label)) {}

FieldSample PointMassAnomalyField::eval(const Vec3& r) const {
  // Per mass: V = gm/rho, G = -gm d/rho^3, Gamma = gm/rho^3 (3 u u^T - I), d = r - r_i.
  Real v = 0, gx = 0, gy = 0, gz = 0, xx = 0, yy = 0, zz = 0, xy = 0, xz = 0, yz = 0;
  for (const PointMass& m : masses_) {
    const Real dx = r.x() - m.r_e.x(), dy = r.y() - m.r_e.y(), dz = r.z() - m.r_e.z();
    const Real r2 = dx * dx + dy * dy + dz * dz;
    if (!(r2 > 0)) throw std::domain_error("PointMassAnomalyField: evaluation at a mass");
    const Real ir2 = 1.0L / r2, ir = std::sqrt(ir2), k = m.gm * ir * ir2, k3 = 3.0L * k * ir2;
    v += m.gm * ir;
    gx -= k * dx; gy -= k * dy; gz -= k * dz;
    xx += k3 * dx * dx - k; yy += k3 * dy * dy - k; zz += k3 * dz * dz - k;
    xy += k3 * dx * dy; xz += k3 * dx * dz; yz += k3 * dy * dz;
  }
  FieldSample s;
  s.potential = v;
  s.g = Vec3(gx, gy, gz);
  s.gamma << xx, xy, xz, xy, yy, yz, xz, yz, zz;
  return s;
}

bool PointMassAnomalyField::third(const Vec3& r, Tensor3& t) const {
  for (Mat3& m : t) m.setZero();
  for (const PointMass& m : masses_) add_point_mass_third(m.gm, r - m.r_e, t);
  return true;
}

Vec3 PointMassAnomalyField::gravitation(const Vec3& r) const {
  // double: an anomaly (< 1e-2 m/s^2) needs no more; several times faster than x87.
  double gx = 0, gy = 0, gz = 0;
  const double x = static_cast<double>(r.x()), y = static_cast<double>(r.y()), z = static_cast<double>(r.z());
  for (const PointMass& m : masses_) {
    const double dx = x - static_cast<double>(m.r_e.x()), dy = y - static_cast<double>(m.r_e.y()), dz = z - static_cast<double>(m.r_e.z());
    const double r2 = dx * dx + dy * dy + dz * dz;
    const double k = static_cast<double>(m.gm) / (r2 * std::sqrt(r2));
    gx -= k * dx; gy -= k * dy; gz -= k * dz;
  }
  return Vec3(gx, gy, gz);
}

Real rw_corr_perp(Real d, Real p) {
  if (d < 1e-6L * p) return 1.0L - 0.75L * d * d / (p * p);  // series of 2p^2 (R-p)/(d^2 R)
  const Real R = std::sqrt(p * p + d * d);
  return 2.0L * p * p * (R - p) / (d * d * R);
}

Real rw_corr_par(Real d, Real p) {
  if (d < 1e-6L * p) return 1.0L - 2.25L * d * d / (p * p);
  const Real R = std::sqrt(p * p + d * d);
  return p * p * (2.0L * p / (R * R * R) - 2.0L * (R - p) / (d * d * R));
}

namespace {

// Lawson & Hanson (1974) NNLS, "Solving Least Squares Problems", ch. 23, algorithm NNLS.
Eigen::VectorXd nnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const int n = static_cast<int>(A.cols());
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> passive(n, false);
  for (int outer = 0; outer < 3 * n + 10; ++outer) {
    const Eigen::VectorXd w = A.transpose() * (b - A * x);
    int jmax = -1;
    double wmax = 1e-12 * b.norm() * A.norm();
    for (int j = 0; j < n; ++j)
      if (!passive[j] && w[j] > wmax) { wmax = w[j]; jmax = j; }
    if (jmax < 0) break;
    passive[jmax] = true;
    for (int inner = 0; inner < 3 * n + 10; ++inner) {
      std::vector<int> ps;
      for (int j = 0; j < n; ++j) if (passive[j]) ps.push_back(j);
      Eigen::MatrixXd Ap(A.rows(), ps.size());
      for (std::size_t k = 0; k < ps.size(); ++k) Ap.col(k) = A.col(ps[k]);
      const Eigen::VectorXd zp = Ap.colPivHouseholderQr().solve(b);
      Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
      for (std::size_t k = 0; k < ps.size(); ++k) z[ps[k]] = zp[k];
      bool feasible = true;
      for (int j : ps) if (z[j] <= 0) feasible = false;
      if (feasible) { x = z; break; }
      double alpha = 1.0;
      for (int j : ps)
        if (z[j] <= 0) alpha = std::min(alpha, x[j] / (x[j] - z[j]));
      x += alpha * (z - x);
      for (int j : ps) if (x[j] <= 1e-15) { passive[j] = false; x[j] = 0; }
    }
  }
  return x;
}

}  // namespace

RwDesign design_rubenstein_winter(const RwAnomalyConfig& cfg) {
  const Real L = cfg.corr_length;
  std::vector<Real> ps;
  for (Real c : cfg.depth_factors)
    if (c * L - cfg.ref_height >= cfg.min_depth) ps.push_back(2.0L * c * L);
  if (ps.empty()) throw std::invalid_argument("design_rubenstein_winter: no admissible layer depth");
  const int nd = 401;
  Eigen::MatrixXd A(nd, ps.size());
  Eigen::VectorXd b(nd);
  for (int i = 0; i < nd; ++i) {
    const Real d = 4.0L * L * i / (nd - 1);
    b[i] = static_cast<double>(std::exp(-d / L));
    for (std::size_t j = 0; j < ps.size(); ++j) A(i, j) = static_cast<double>(rw_corr_perp(d, ps[j]));
  }
  const Eigen::VectorXd w = nnls(A, b);
  const double wsum = w.sum();
  if (!(wsum > 0)) throw std::runtime_error("design_rubenstein_winter: fit failed");
  RwDesign des;
  des.fit_max_error = static_cast<Real>((A * (w / wsum) - b).cwiseAbs().maxCoeff());
  const Real var_g = std::pow(cfg.rms_deflection * cfg.g_ref, 2);  // (m/s^2)^2 per horizontal component
  for (std::size_t j = 0; j < ps.size(); ++j) {
    if (!(w[j] > 0)) continue;
    RwLayer l;
    l.p = ps[j];
    l.weight = static_cast<Real>(w[j] / wsum);
    l.depth = ps[j] / 2 - cfg.ref_height;
    l.spacing = cfg.spacing_factor * ps[j] / 2;
    // w var_g = pi n sigma^2 / p^2, n = 1/s^2
    l.sigma_gm = std::sqrt(l.weight * var_g * l.p * l.p * l.spacing * l.spacing / static_cast<Real>(M_PI));
    des.layers.push_back(l);
  }
  return des;
}

Real rw_model_cov_perp(const RwDesign& des, Real rms, Real d) {
  Real c = 0;
  for (const RwLayer& l : des.layers) c += l.weight * rw_corr_perp(d, l.p);
  return rms * rms * c;
}
Real rw_model_cov_par(const RwDesign& des, Real rms, Real d) {
  Real c = 0;
  for (const RwLayer& l : des.layers) c += l.weight * rw_corr_par(d, l.p);
  return rms * rms * c;
}

PointMassAnomalyField make_rubenstein_winter_field(const RwAnomalyConfig& cfg, RwDesign* out) {
  const RwDesign des = design_rubenstein_winter(cfg);
  std::mt19937_64 rng(cfg.seed);
  // Portable uniform and Gaussian draws (std::normal_distribution is not
  // specified bit-for-bit across standard libraries).
  auto uni = [&rng]() { return (static_cast<Real>(rng() >> 11) + 0.5L) / 9007199254740992.0L; };
  auto gauss = [&uni]() { return std::sqrt(-2.0L * std::log(uni())) * std::cos(2.0L * static_cast<Real>(M_PI) * uni()); };
  std::vector<PointMass> masses;
  const Real rm = wgs84::kA;  // spherical approximation for the cell layout only
  for (const RwLayer& l : des.layers) {
    const Real dlat = l.spacing / rm;
    const int nlat = static_cast<int>(std::ceil(2 * cfg.half_size / l.spacing));
    for (int i = 0; i < nlat; ++i) {
      const Real lat_lo = cfg.lat0 - cfg.half_size / rm + i * dlat;
      const Real clat = std::cos(lat_lo + 0.5L * dlat);
      const Real dlon = l.spacing / (rm * clat);
      const int nlon = static_cast<int>(std::ceil(2 * cfg.half_size / l.spacing));
      const Real lon_lo = cfg.lon0 - cfg.half_size / (rm * clat);
      for (int k = 0; k < nlon; ++k) {
        PointMass m;
        const Real lat = lat_lo + uni() * dlat, lon = lon_lo + (k + uni()) * dlon;
        m.r_e = wgs84::geodetic_to_ecef(lat, lon, -l.depth);
        m.gm = l.sigma_gm * gauss();
        masses.push_back(m);
      }
    }
  }
  if (out) *out = des;
  return PointMassAnomalyField(std::move(masses), "rubenstein-winter-point-masses(seed=" + std::to_string(cfg.seed) + ")");
}

}  // namespace ggins::gravity
