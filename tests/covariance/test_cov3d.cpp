// 3-D error model (nav3d_model.hpp) against closed forms that
// do not come from the model code:
//  1. non-rotating point-mass Earth: eig(F) = +-sqrt2 w_s, +-j w_s (twice),
//     0 (three times: the dead reckoning), w_s^2 = GM/r^3, at every point of a
//     great-circle flight (Welker et al. section VI in 3-D);
//  2. rotating Earth, platform at rest at the north pole: W commutes with
//     Gamma, so the nav block's eigenvalues are exactly +-sqrt2 w_s and
//     +-j(w_s + w_ie), +-j(w_s - w_ie) (Foucault splitting with sin L = 1);
//     the strapdown attitude block adds 0, +-j w_ie (eig of -W);
//  3. rotating Earth at 45 deg, moving: every non-zero eigenvalue s of the nav
//     block is a root of det((sI + W)^2 - Gamma_e) (the characteristic
//     polynomial derived by eliminating dG and dv by hand), and the Schuler
//     pair splits into w_s +- w_ie sin L to first order in w_ie/w_s;
//  4. propagation at rest, non-rotating, stabilized, 18 biases sigma:
//     centre force error sigma/sqrt6 per axis, so
//       sigma_down  = sigma/sqrt6 (cosh(sqrt2 w_s t) - 1) / (2 w_s^2),
//       sigma_north = sigma/sqrt6 (1 - cos(w_s t)) / w_s^2;
//  5. gyro bias dw about body x (north at rest), strapdown, non-rotating, at
//     rest: psi = -dw t north, f x psi = g dw t east (the computed up turns
//     toward east), so d_east'' = -w_s^2 d_east + g dw t:
//       d_east = g dw (t - sin(w_s t)/w_s) / w_s^2  (sign checked, one draw).
#include <cmath>
#include <complex>
#include <cstdio>

#include "ggins/covariance/cov3d.hpp"
#include "ggins/covariance/modes.hpp"
#include "ggins/covariance/propagate.hpp"

using namespace ggins::covariance;
using cdv = std::complex<double>;

static int g_fail = 0;
static void check(bool c, const char* what, double a, double b) {
  std::printf("%s %s: %.10g vs %.10g\n", c ? "ok  " : "FAIL", what, a, b);
  if (!c) ++g_fail;
}

// Greedy match of expected eigenvalues; returns max |dev|.
static double match(const std::vector<cdv>& ev, const std::vector<cdv>& ex) {
  std::vector<bool> used(ev.size(), false);
  double dev = 0;
  if (ev.size() != ex.size()) return INFINITY;
  for (const cdv& e : ex) {
    int b = -1;
    for (size_t i = 0; i < ev.size(); ++i)
      if (!used[i] && (b < 0 || std::abs(ev[i] - e) < std::abs(ev[size_t(b)] - e))) b = int(i);
    used[size_t(b)] = true;
    dev = std::max(dev, std::abs(ev[size_t(b)] - e));
  }
  return dev;
}

int main() {
  const double GM = 3.986004418e14, R = 6378137.0, wie = 7.292115e-5;

  {  // 1. non-rotating point mass, moving, stabilized and strapdown
    for (int sd = 0; sd < 2; ++sd) {
      Cov3DScenario s = *builtin_scenario3d("gc3d-nonrotating");
      s.platform = sd ? Platform::kStrapdown : Platform::kStabilized;
      s.height_m = 9000;
      const auto m = make_model3d(s);
      const double r = R + 9000, ws = std::sqrt(GM / (r * r * r));
      double dev = 0;
      for (double t : {0.0, 700.0, 1900.0, 3600.0}) {
        MatrixXd F, G;
        m->matrices(t, F, G);
        std::vector<cdv> ex = {cdv(std::sqrt(2) * ws, 0), cdv(-std::sqrt(2) * ws, 0), cdv(0, ws), cdv(0, ws),
                               cdv(0, -ws), cdv(0, -ws), 0, 0, 0};
        if (sd) ex.insert(ex.end(), {0, 0, 0});  // psi' = -C dw: free integrators in a non-rotating frame
        dev = std::max(dev, match(sorted_eigenvalues(F), ex) / ws);
      }
      check(dev < 1e-6, sd ? "1. non-rotating strapdown: max |eig - closed form|/w_s"
                           : "1. non-rotating stabilized: max |eig - closed form|/w_s",
            dev, 1e-6);
    }
  }
  {  // 2. rotating, at rest at the pole
    for (int sd = 0; sd < 2; ++sd) {
      Cov3DScenario s = *builtin_scenario3d("gc3d-stabilized");
      s.field = "point-mass";
      s.lat0_deg = 90.0;
      s.speed_mps = 0.0;
      s.platform = sd ? Platform::kStrapdown : Platform::kStabilized;
      const auto m = make_model3d(s);
      const double ws = std::sqrt(GM / (R * R * R));
      MatrixXd F, G;
      m->matrices(100.0, F, G);
      std::vector<cdv> ex = {cdv(std::sqrt(2) * ws, 0), cdv(-std::sqrt(2) * ws, 0), cdv(0, ws + wie),
                             cdv(0, -(ws + wie)), cdv(0, ws - wie), cdv(0, -(ws - wie)), 0, 0, 0};
      if (sd) ex.insert(ex.end(), {0, cdv(0, wie), cdv(0, -wie)});
      const double dev = match(sorted_eigenvalues(F), ex) / ws;
      check(dev < 1e-6, sd ? "2. pole, strapdown: Foucault +-j(w_s +- w_ie), attitude 0, +-j w_ie"
                           : "2. pole, stabilized: +-sqrt2 w_s, +-j(w_s +- w_ie), 0 x3", dev, 1e-6);
    }
  }
  {  // 3. rotating, 45 deg, moving, WGS-84 normal field
    const Cov3DScenario s = *builtin_scenario3d("gc3d-stabilized");
    const auto m = make_model3d(s);
    double res = 0, split = 0, sp_ref = 0;
    for (double t : {0.0, 1800.0, 3600.0}) {
      const Eigen3D e = eigen3d(*m, t);
      res = std::max(res, e.max_charpoly_residual);
      // split of the two positive-imaginary Schuler roots vs 2 w_ie sin L
      std::vector<double> im;
      for (const auto& z : e.nav_ev)
        if (z.imag() > 0.5 * e.omega_s) im.push_back(z.imag());
      if (im.size() == 2) {
        const double d = std::abs(im[0] - im[1]);
        split = std::max(split, std::abs(d - 2 * e.foucault) / (2 * e.foucault));
        sp_ref = 2 * e.foucault;
      } else {
        split = INFINITY;
      }
    }
    check(res < 1e-9, "3. charpoly det((sI+W)^2 - Gamma) residual at the eigenvalues", res, 1e-9);
    check(split < 0.01, "3. Schuler split vs 2 w_ie sin L (relative)", split, sp_ref);
  }
  {  // 4. biases at rest, closed form
    Cov3DScenario s = *builtin_scenario3d("gc3d-nonrotating");
    s.speed_mps = 0.0;
    s.lat0_deg = 30.0;
    s.duration_s = 3000.0;
    const auto m = make_model3d(s);
    PropagationOptions o;
    o.t_end = s.duration_s;
    o.dt = 1.0;
    o.output_dt = 1000.0;
    const auto run = propagate(*m, initial_covariance3d(s, *m), o);
    const double ws = std::sqrt(GM / (R * R * R)), sa = s.acc_bias_sigma_mps2 / std::sqrt(6.0);
    double worst = 0;
    for (const auto& smp : run) {
      if (smp.t == 0) continue;
      // geocentric local frame of the point-mass sphere (north, east, down = -r^)
      const Eigen::Vector3d rh = m->trajectory().at(smp.t).r_e.cast<double>().normalized();
      const Eigen::Vector3d east = Eigen::Vector3d::UnitZ().cross(rh).normalized();
      Eigen::Matrix3d Cgc;
      Cgc.col(0) = rh.cross(east);
      Cgc.col(1) = east;
      Cgc.col(2) = -rh;
      const Eigen::Vector3d sg = ned_sigma(smp.P, Nav3DModel::kR, Cgc);
      const double down = sa * (std::cosh(std::sqrt(2) * ws * smp.t) - 1) / (2 * ws * ws);
      const double hor = sa * (1 - std::cos(ws * smp.t)) / (ws * ws);
      worst = std::max({worst, std::abs(sg(2) / down - 1), std::abs(sg(0) / hor - 1), std::abs(sg(1) / hor - 1)});
      if (smp.t == 3000.0) check(true, "4. sigma_down at 3000 s (model vs closed form)", sg(2), down);
    }
    check(worst < 1e-6, "4. biases at rest: max relative |sigma - closed form| (N, E, D)", worst, 1e-6);
  }
  {  // 5. one gyro bias, strapdown at rest, non-rotating: sign and size of f x psi
    Cov3DScenario s = *builtin_scenario3d("gc3d-nonrotating");
    s.platform = Platform::kStrapdown;
    s.speed_mps = 0.0;
    s.lat0_deg = 0.0;
    s.heading_deg = 0.0;  // body x = north
    const auto m = make_model3d(s);
    const double T = 1500.0, dw = 1e-9;
    const MatrixXd Phi = transition_matrix(*m, T, 1.0);
    const int n = m->n_states();
    Eigen::VectorXd x0 = Eigen::VectorXd::Zero(n + m->n_dist());
    x0(n + m->idx_gyro() + 0) = dw;
    const Eigen::VectorXd x = Phi * x0;
    const Eigen::Matrix3d Cne = m->ned_to_ecef(T);
    const Eigen::Vector3d dr_n = Cne.transpose() * x.segment<3>(Nav3DModel::kR);
    const double ws = std::sqrt(GM / (R * R * R)), g = GM / (R * R);
    const double ex = g * dw * (T - std::sin(ws * T) / ws) / (ws * ws);
    check(std::abs(dr_n(1) / ex - 1) < 1e-6, "5. gyro bias about north: east error (sign and size)", dr_n(1), ex);
    const Eigen::Vector3d psi_n = Cne.transpose() * x.segment<3>(Nav3DModel::kPsi);
    check(std::abs(psi_n(0) / (-dw * T) - 1) < 1e-9, "5. psi_north = -dw t", psi_n(0), -dw * T);
  }
  std::printf("%s\n", g_fail ? "FAILED" : "all passed");
  return g_fail ? 1 : 0;
}
