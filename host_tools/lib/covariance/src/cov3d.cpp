#include "ggins/covariance/cov3d.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "ggins/covariance/modes.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/wgs84.hpp"

namespace ggins::covariance {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
}

std::vector<std::string> builtin_names3d() {
  return {"gc3d-stabilized", "gc3d-strapdown", "gc3d-nonrotating", "gc3d-baro"};
}

std::optional<Cov3DScenario> builtin_scenario3d(const std::string& name) {
  Cov3DScenario s;
  s.name = name;
  if (name == "gc3d-stabilized") return s;
  if (name == "gc3d-strapdown") {
    s.platform = Platform::kStrapdown;
    s.gyro_bias_sigma_radps = 4.8481368e-9;  // 0.001 deg/h
    return s;
  }
  if (name == "gc3d-nonrotating") {  // the setting of Welker et al. in 3-D: closed-form eigenvalues
    s.field = "point-mass";
    s.omega_ie = 0.0;
    return s;
  }
  if (name == "gc3d-baro") {
    s.model.baro.on = true;
    s.baro_bias_sigma_m = 2.0;
    s.model.baro.gm_sigma_m = 1.0;
    s.model.baro.noise_sigma_m = 0.5;
    return s;
  }
  return std::nullopt;
}

std::shared_ptr<const gravity::Field> make_field3d(const Cov3DScenario& s) {
  if (s.field_override) return s.field_override;
  if (s.field == "point-mass") return std::make_shared<gravity::PointMassField>();
  if (s.field == "normal") return std::make_shared<gravity::NormalField>();
  throw std::invalid_argument("unknown field '" + s.field + "' (point-mass, normal)");
}

std::shared_ptr<const Trajectory3D> make_trajectory3d(const Cov3DScenario& s) {
  if (s.traj_override) return s.traj_override;
  return std::make_shared<GreatCircle3D>(s.radius_m, s.height_m, s.lat0_deg * kDeg, s.lon0_deg * kDeg,
                                         s.heading_deg * kDeg, s.speed_mps, s.platform, s.omega_ie);
}

std::shared_ptr<const Nav3DModel> make_model3d(const Cov3DScenario& s) {
  return std::make_shared<Nav3DModel>(make_field3d(s), make_trajectory3d(s), s.platform, s.model);
}

MatrixXd initial_covariance3d(const Cov3DScenario& s, const Nav3DModel& m) {
  const int n = m.n_states(), N = n + m.n_dist();
  MatrixXd P0 = MatrixXd::Zero(N, N);
  for (int i = 0; i < 3; ++i) {
    P0(Nav3DModel::kR + i, Nav3DModel::kR + i) = s.r0_sigma_m * s.r0_sigma_m;
    P0(Nav3DModel::kV + i, Nav3DModel::kV + i) = s.v0_sigma_mps * s.v0_sigma_mps;
    P0(Nav3DModel::kG + i, Nav3DModel::kG + i) = s.g0_sigma_mps2 * s.g0_sigma_mps2;
    if (m.strapdown()) P0(Nav3DModel::kPsi + i, Nav3DModel::kPsi + i) = s.psi0_sigma_rad * s.psi0_sigma_rad;
  }
  for (int i = 0; i < 18; ++i) P0(n + i, n + i) = s.acc_bias_sigma_mps2 * s.acc_bias_sigma_mps2;
  if (m.strapdown())
    for (int j = 0; j < 3; ++j)
      P0(n + m.idx_gyro() + j, n + m.idx_gyro() + j) = s.gyro_bias_sigma_radps * s.gyro_bias_sigma_radps;
  if (m.baro()) {
    const int b = n + m.idx_baro_bias(), g = b + 1;  // constant bias; Gauss-Markov (stationary)
    P0(b, b) = s.baro_bias_sigma_m * s.baro_bias_sigma_m;
    P0(g, g) = s.model.baro.gm_sigma_m * s.model.baro.gm_sigma_m;
  }
  return P0;
}

Eigen::Vector3d ned_sigma(const MatrixXd& P, int i0, const Eigen::Matrix3d& C_n_e) {
  const Eigen::Matrix3d Pe = P.block<3, 3>(i0, i0);
  const Eigen::Matrix3d Pn = C_n_e.transpose() * Pe * C_n_e;
  return Pn.diagonal().cwiseMax(0.0).cwiseSqrt();
}

Eigen3D eigen3d(const Nav3DModel& m, double t) {
  Eigen3D e;
  MatrixXd F, Gam;
  m.matrices(t, F, Gam);
  e.ev = sorted_eigenvalues(F);
  const MatrixXd Fn = F.topLeftCorner(9, 9);
  e.nav_ev = sorted_eigenvalues(Fn);
  const Eigen::Matrix3d Ge = F.block<3, 3>(Nav3DModel::kG, Nav3DModel::kV);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Ge);
  const Eigen::Vector3d gl = es.eigenvalues();  // ascending: two horizontal (< 0), radial (> 0)
  e.gamma_up = gl(2);
  e.omega_s = std::sqrt(-0.5 * (gl(0) + gl(1)));
  const Traj3DPoint p = m.trajectory().at(Real(t));
  const Eigen::Vector3d r = p.r_e.cast<double>();
  e.lat_gc = std::asin(r(2) / r.norm());
  const double wie = double(m.trajectory().omega_ie());
  e.foucault = wie * std::sin(e.lat_gc);
  Eigen::Matrix3d W;
  W << 0, -wie, 0, wie, 0, 0, 0, 0, 0;
  using C3 = Eigen::Matrix<std::complex<double>, 3, 3>;
  if (m.baro()) {  // the loop closes on dr: the open-loop polynomial does not apply
    e.max_charpoly_residual = std::nan("");
    return e;
  }
  for (const auto& s : e.nav_ev) {
    if (std::abs(s) < 1e-3 * e.omega_s) continue;  // the zeros of the dead reckoning
    C3 A = (s * C3::Identity() + W.cast<std::complex<double>>());
    A = A * A - Ge.cast<std::complex<double>>();
    const double res = std::abs(A.determinant()) / std::pow(std::abs(s), 6);
    e.max_charpoly_residual = std::max(e.max_charpoly_residual, res);
  }
  return e;
}

}  // namespace ggins::covariance
