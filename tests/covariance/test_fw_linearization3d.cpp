// The 3-D error model (nav3d_model.hpp) is the firmware's
// model. The real firmware (gg_nav3d_step, direct calls) is flown along the
// rotating-Earth great-circle flight (45 deg, heading 45 deg, 300 m/s, WGS-84
// normal field, 10 Hz, 300 s) with one error at a time - each of the 18
// accelerometer biases, each gyro bias (strapdown), each initial position,
// velocity, gravity and attitude error - at +eps and -eps; the central
// difference of the firmware's errors (ECEF dr, dv, dG, psi) over 2 eps is one
// column of the firmware's flow-map Jacobian, compared with the same column of
// the model's transition matrix Phi(T, 0) (RK4 on [F Gamma; 0 0]). Sign or
// factor errors in F or Gamma (Coriolis, f x psi, the rotated gradient, the
// differencing of the 18 readings, the gyro terms of Gamma_b) fail here.
// The third case flies the 3-D truth generator's maneuvering strapdown flight
// (scenarios/3d-strapdown-1h.toml, barometer off) through its first turn: body
// rates and angular accelerations are then non-zero, which exercises the gyro
// terms of Gamma_b ([w x][dw x] + [dw x][w x]) and the time-varying C_b_e.
// Tolerance per column: 2e-3 of the column's largest entry in each block
// (the firmware's discretization at 10 Hz and the model's frozen-trajectory
// coefficients), measured ratios printed.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <complex>
#include <cstdio>
#include <string>

#include "ggins/covariance/propagate.hpp"
#include "sim3d.hpp"
#ifdef GGINS_HAVE_TRUTH3D
#include "ggins/covariance/cov3d_truth3d.hpp"
#endif

using namespace ggins::covariance;
using namespace ggins::montecarlo3d;

static int g_fail = 0;

static Eigen::VectorXd state_of(const ErrSample& e, bool sd, bool baro) {
  Eigen::VectorXd x(9 + (sd ? 3 : 0) + (baro ? 1 : 0));
  x.segment<3>(0) = e.dr;
  x.segment<3>(3) = e.dv;
  x.segment<3>(6) = e.dg;
  if (sd) x.segment<3>(9) = e.psi;
  if (baro) x(x.size() - 1) = e.a_c;
  return x;
}

static void run(Cov3DScenario s, const char* label, double rel_tol = 2e-3) {
  const bool sd = s.platform == Platform::kStrapdown, baro = s.model.baro.on;
  const double T = s.duration_s, rate = 10.0;
  const Sim3D sim(s, rate);
  const Nav3DModel& m = sim.model();
  const int n = m.n_states(), nd = m.n_dist();
  const MatrixXd Phi = transition_matrix(m, T, 0.5);
  // Columns: disturbances (18 acc, 3 gyro) then initial states.
  struct Col {
    std::string name;
    int phi_col;
    double eps;
    int kind, idx;  // kind 0 acc, 1 gyro, 2 dr0, 3 dv0, 4 dg0, 5 psi0, 6 baro bias
  };
  std::vector<Col> cols;
  for (int i = 0; i < 18; ++i) cols.push_back({"acc bias " + std::to_string(i), n + i, 1e-8, 0, i});
  if (sd)
    for (int j = 0; j < 3; ++j) cols.push_back({"gyro bias " + std::to_string(j), n + m.idx_gyro() + j, 1e-8, 1, j});
  if (baro) cols.push_back({"baro bias", n + m.idx_baro_bias(), 1.0, 6, 0});
  for (int j = 0; j < 3; ++j) cols.push_back({"dr0 " + std::to_string(j), Nav3DModel::kR + j, 1.0, 2, j});
  for (int j = 0; j < 3; ++j) cols.push_back({"dv0 " + std::to_string(j), Nav3DModel::kV + j, 1e-3, 3, j});
  for (int j = 0; j < 3; ++j) cols.push_back({"dg0 " + std::to_string(j), Nav3DModel::kG + j, 1e-8, 4, j});
  if (sd)
    for (int j = 0; j < 3; ++j) cols.push_back({"psi0 " + std::to_string(j), Nav3DModel::kPsi + j, 1e-7, 5, j});
  double worst = 0;
  std::string worst_name;
  int bad = 0;
  for (const Col& c : cols) {
    Eigen::VectorXd xp, xm;
    for (int sign = -1; sign <= 1; sign += 2) {
      SensorErrors e;
      const double v = sign * c.eps;
      switch (c.kind) {
        case 0: e.acc_bias[size_t(c.idx)] = v; break;
        case 1: e.gyro_bias[size_t(c.idx)] = v; break;
        case 2: e.dr0[size_t(c.idx)] = v; break;
        case 3: e.dv0[size_t(c.idx)] = v; break;
        case 4: e.dg0[size_t(c.idx)] = v; break;
        case 6: e.baro_bias_m = v; break;
        default: e.dpsi0[size_t(c.idx)] = v; break;
      }
      const auto out = sim.fly(e, T, T);
      (sign > 0 ? xp : xm) = state_of(out.back(), sd, baro);
    }
    const Eigen::VectorXd fw = (xp - xm) / (2 * c.eps);
    const Eigen::VectorXd md = Phi.col(c.phi_col).head(n);
    // per block (r, v, G, psi): error relative to the block's scale (largest of fw, model)
    double ratio = 0;
    for (int b = 0; b < (n + 2) / 3; ++b) {  // blocks r, v, G, (psi), (a_c alone)
      const int i0 = 3 * b, len = std::min(3, n - i0);
      const double scale = std::max(fw.segment(i0, len).cwiseAbs().maxCoeff(), md.segment(i0, len).cwiseAbs().maxCoeff());
      if (scale == 0) continue;
      const double d = (fw.segment(i0, len) - md.segment(i0, len)).cwiseAbs().maxCoeff();
      // floor: block entries far below the column's dominant response (relative 1e-9 of the largest block)
      ratio = std::max(ratio, d / (rel_tol * scale + 1e-9 * fw.cwiseAbs().maxCoeff()));
    }
    if (ratio > worst) {
      worst = ratio;
      worst_name = c.name;
    }
    if (ratio > 1) {
      ++bad;
      std::printf("FAIL %s: firmware vs model column (ratio to tolerance %.3g)\n", c.name.c_str(), ratio);
      for (int i = 0; i < n; ++i) std::printf("    %2d fw %+.9e model %+.9e\n", i, fw(i), md(i));
    }
  }
  (void)nd;
  std::printf("%s %s: %zu columns, worst |fw - model| / tolerance = %.3g (%s)\n", bad ? "FAIL" : "ok  ", label,
              cols.size(), worst, worst_name.c_str());
  if (bad) ++g_fail;
}

// Eigenvalues of the firmware itself: its flow-map Jacobian J over h = 20 s (columns: the
// nine initial-state perturbations dr0, dv0, dG0, and psi0 for the strapdown platform), lambda_fw = log(eig J) / h, against the
// eigenvalues of the model's F at t = h/2 (frozen). Bound: 1e-3 w_s per eigenvalue, a tenth of
// the Foucault splitting 2 w_ie sin L (0.083 w_s at 45 deg), so the firmware's Schuler pair must
// show the split.
static void firmware_eigenvalues(Platform plat) {
  Cov3DScenario s = *builtin_scenario3d("gc3d-stabilized");
  s.platform = plat;
  const bool sd = plat == Platform::kStrapdown;
  const int n = sd ? 12 : 9;
  const double h = 20.0;
  s.duration_s = h;
  const Sim3D sim(s, 10.0);
  Eigen::MatrixXd J(n, n);
  for (int c = 0; c < n; ++c) {
    Eigen::VectorXd xp, xm;
    const double eps = c < 3 ? 1.0 : c < 6 ? 1e-3 : c < 9 ? 1e-6 : 1e-7;
    for (int sign = -1; sign <= 1; sign += 2) {
      SensorErrors e;
      (c < 3 ? e.dr0 : c < 6 ? e.dv0 : c < 9 ? e.dg0 : e.dpsi0)[size_t(c % 3)] = sign * eps;
      (sign > 0 ? xp : xm) = state_of(sim.fly(e, h, h).back(), sd, false);
    }
    J.col(c) = (xp - xm) / (2 * eps);
  }
  Eigen::EigenSolver<Eigen::MatrixXd> es(J);
  std::vector<std::complex<double>> lf;
  for (int i = 0; i < n; ++i) lf.push_back(std::log(es.eigenvalues()(i)) / h);
  const Eigen3D e = eigen3d(sim.model(), h / 2);
  std::vector<bool> used(size_t(n), false);
  double worst = 0;
  for (const auto& z : e.ev) {
    int b = -1;
    for (int i = 0; i < n; ++i)
      if (!used[size_t(i)] && (b < 0 || std::abs(lf[size_t(i)] - z) < std::abs(lf[size_t(b)] - z))) b = i;
    used[size_t(b)] = true;
    worst = std::max(worst, std::abs(lf[size_t(b)] - z) / e.omega_s);
    std::printf("    model %+.7e %+.7ej   firmware %+.7e %+.7ej\n", z.real(), z.imag(), lf[size_t(b)].real(),
                lf[size_t(b)].imag());
  }
  const bool ok = worst < 1e-3;
  std::printf("%s firmware eigenvalues (%s, log eig J / h, h = 20 s) vs model: max |diff| = %.3g w_s (bound 1e-3)\n",
              ok ? "ok  " : "FAIL", sd ? "strapdown" : "stabilized", worst);
  if (!ok) ++g_fail;
}

int main() {
  firmware_eigenvalues(Platform::kStabilized);
  firmware_eigenvalues(Platform::kStrapdown);  // + the attitude block: 0, +-j w_ie
  for (int sd = 0; sd < 2; ++sd) {
    Cov3DScenario s = *builtin_scenario3d("gc3d-stabilized");
    s.platform = sd ? Platform::kStrapdown : Platform::kStabilized;
    s.duration_s = 300.0;
    run(s, sd ? "great circle, strapdown" : "great circle, stabilized");
  }
  {  // the barometric loop (10 Hz barometer): the discrete loop of vchan.h (poles exactly at exp(-p T),
     // corrections once per sample) against the continuous loop of the model; a priori tolerance 1e-2:
     // sample-and-correct acts like a delay of ~T/2 on the loop, k1 T/2 = 0.06 x 0.05 = 3e-3
    Cov3DScenario s = *builtin_scenario3d("gc3d-baro");
    s.model.baro.gm_sigma_m = s.model.baro.noise_sigma_m = 0;
    s.model.baro.period_s = 0.1;
    s.duration_s = 300.0;
    run(s, "great circle, stabilized, barometric loop (10 Hz barometer)", 1e-2);
  }
#ifdef GGINS_HAVE_TRUTH3D
  {  // the truth generator's maneuvering flight, through its first turn (t = 240..360 s) and into the climb
    Cov3DScenario s = load_truth3d_scenario("3d-strapdown-1h", {GGINS_SOURCE_DIR "/scenarios"}, nullptr);
    s.model.baro.on = false;
    s.duration_s = 420.0;
    run(s, "3d-strapdown-1h (truth3d), first 420 s: turn north -> east");
  }
#endif
  std::printf("%s\n", g_fail ? "FAILED" : "all passed");
  return g_fail ? 1 : 0;
}
