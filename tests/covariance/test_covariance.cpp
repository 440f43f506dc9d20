// Tests of ggins-covariance: propagator on closed-form cases, the Welker et al.
// error model (eqs. 9-10 against the section VI closed forms, eigenvalues,
// signs against a nonlinear mechanization), Table I and the CLI's JSON.
#include <cmath>
#include <complex>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <unistd.h>

#include "ggins/covariance/modes.hpp"
#include "ggins/covariance/propagate.hpp"
#include "ggins/covariance/scenario.hpp"
#include "ggins/covariance/welker2d.hpp"
#include "ggins/gravity/field.hpp"

// CMocka last: its fail() macro would clash with std::basic_ios::fail().
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
extern "C" {
#include <cmocka.h>
}

using namespace ggins::covariance;
using ggins::gravity::PointMassField;

namespace {

// |got - want| <= rel * |want| (or <= abs when want == 0), with a message.
void check_rel(const char* what, double got, double want, double rel, double abs_tol = 0) {
  const double tol = std::max(rel * std::abs(want), abs_tol);
  if (!(std::abs(got - want) <= tol)) {
    print_error("%s: got %.17g, want %.17g (|diff| %.3g > tol %.3g)\n", what, got, want, std::abs(got - want), tol);
    fail();
  }
}

// x' = v, v' = d: a constant bias d ~ N(0, s^2) through a double integrator.
class DoubleIntegrator final : public LinearErrorModel {
 public:
  int n_states() const override { return 2; }
  int n_dist() const override { return 1; }
  std::vector<std::string> state_keys() const override { return {"x", "v"}; }
  std::vector<std::string> dist_keys() const override { return {"d"}; }
  void matrices(double, MatrixXd& F, MatrixXd& G) const override {
    F.setZero(2, 2);
    F(0, 1) = 1;
    G.setZero(2, 1);
    G(1, 0) = 1;
  }
};

// x' = lambda x + c(t) d with c(t) = cos(w t) (time-varying input) or 1.
class Scalar final : public LinearErrorModel {
 public:
  Scalar(double lambda, double w) : l_(lambda), w_(w) {}
  int n_states() const override { return 1; }
  int n_dist() const override { return 1; }
  std::vector<std::string> state_keys() const override { return {"x"}; }
  std::vector<std::string> dist_keys() const override { return {"d"}; }
  void matrices(double t, MatrixXd& F, MatrixXd& G) const override {
    F.setConstant(1, 1, l_);
    G.setConstant(1, 1, w_ > 0 ? std::cos(w_ * t) : 1.0);
  }

 private:
  double l_, w_;
};

// x' = w, white noise of density q: random walk, P = q t.  With a Gauss-Markov
// disturbance (D = -1/tau) it also exercises dist_dynamics.
class RandomWalk final : public LinearErrorModel {
 public:
  explicit RandomWalk(double q) : q_(q) {}
  int n_states() const override { return 1; }
  int n_dist() const override { return 1; }
  std::vector<std::string> state_keys() const override { return {"x"}; }
  std::vector<std::string> dist_keys() const override { return {"b"}; }
  void matrices(double, MatrixXd& F, MatrixXd& G) const override {
    F.setZero(1, 1);
    G.setZero(1, 1);
  }
  bool has_process_noise() const override { return true; }
  void process_noise(double, MatrixXd& Q) const override {
    Q.setZero(2, 2);
    Q(0, 0) = q_;
  }

 private:
  double q_;
};

constexpr double kGM = 3.986004418e14, kRe = 6378137.0;

std::shared_ptr<Welker2DModel> welker(double V, double h, double L0, double a = 0.5, double b = 0.5,
                                      Welker2DModel::GradientSource src = Welker2DModel::GradientSource::kCentre) {
  return std::make_shared<Welker2DModel>(std::make_shared<PointMassField>(kGM),
                                         std::make_shared<NorthGreatCircle2D>(V, h, L0, kRe), a, b, src);
}

MatrixXd welker_p0(double sa, double sg0) {
  MatrixXd P0 = MatrixXd::Zero(14, 14);
  P0(4, 4) = P0(5, 5) = sg0 * sg0;
  for (int i = 6; i < 14; ++i) P0(i, i) = sa * sa;
  return P0;
}

VectorXd final_sigmas(const LinearErrorModel& m, const MatrixXd& P0, double T, double dt, Method meth) {
  PropagationOptions o;
  o.t_end = T;
  o.dt = dt;
  o.output_dt = T;
  o.method = meth;
  const auto s = propagate(m, P0, o);
  if (std::abs(s.back().t - T) > 1e-9) {
    print_error("propagate ended at t = %.17g, want %.17g\n", s.back().t, T);
    fail();
  }
  return sigmas(s.back().P, m.n_states());
}

// ---------------------------------------------------------------------------

// Constant bias through a double integrator: sigma_x = s t^2/2, sigma_v = s t,
// cov(x, v) = s^2 t^3/2. Phi is quadratic in t, so RK4 is exact
// up to round-off even with a coarse, non-dividing step (T/dt not an integer).
void test_double_integrator(void**) {
  DoubleIntegrator m;
  const double s = 2e-12;
  MatrixXd P0 = MatrixXd::Zero(3, 3);
  P0(2, 2) = s * s;
  for (Method meth : {Method::kTransition, Method::kLyapunov}) {
    PropagationOptions o;
    o.t_end = 3600;
    o.dt = 7.0;
    o.output_dt = 100;
    o.method = meth;
    const auto out = propagate(m, P0, o);
    for (const auto& smp : out) {
      const double t = smp.t;
      check_rel("sigma_x = s t^2/2", std::sqrt(smp.P(0, 0)), s * t * t / 2, 1e-12, 1e-300);
      check_rel("sigma_v = s t", std::sqrt(smp.P(1, 1)), s * t, 1e-12, 1e-300);
      check_rel("cov(x,v) = s^2 t^3/2", smp.P(0, 1), s * s * t * t * t / 2, 1e-12, 1e-300);
    }
    check_rel("end time", out.back().t, 3600.0, 0, 1e-9);
  }
}

// x' = lambda x + d (the unstable mode's scalar model): sigma_x = s (e^{lt} - 1)/l,
// with l = sqrt(2) w_s. And a time-varying input cos(w t): x = d sin(w t)/w.
void test_scalar_exponential_and_time_varying(void**) {
  const double l = std::sqrt(2.0) * std::sqrt(kGM / (kRe * kRe * kRe)), s = 1.0, T = 3600;
  Scalar m(l, 0);
  MatrixXd P0 = MatrixXd::Zero(2, 2);
  P0(1, 1) = s * s;
  for (Method meth : {Method::kTransition, Method::kLyapunov})
    check_rel("s (e^{lT}-1)/l", final_sigmas(m, P0, T, 1.0, meth)(0), s * std::expm1(l * T) / l, 1e-11);
  const double w = 2 * M_PI / 600.0, T2 = 1000;  // input changes sign within the run
  Scalar mv(0.0, w);
  for (Method meth : {Method::kTransition, Method::kLyapunov})
    check_rel("s |sin(wT)|/w", final_sigmas(mv, P0, T2, 1.0, meth)(0), s * std::abs(std::sin(w * T2)) / w, 1e-9);
}

// White noise: random walk P = q t (Lyapunov method with Qa); the transition
// method must refuse a noisy model instead of silently dropping the noise.
void test_white_noise_random_walk(void**) {
  RandomWalk m(3e-4);
  MatrixXd P0 = MatrixXd::Zero(2, 2);
  check_rel("P = q t", std::pow(final_sigmas(m, P0, 500, 3.0, Method::kLyapunov)(0), 2), 3e-4 * 500, 1e-12);
  PropagationOptions o;
  o.method = Method::kTransition;
  bool threw = false;
  try {
    propagate(m, P0, o);
  } catch (const std::invalid_argument&) {
    threw = true;
  }
  assert_true(threw);
}

// F (eq. 9, with the +1 sign fix) and Gamma (eq. 10) built from the Field on the
// trajectory against the closed forms of Welker et al. section VI, off the
// paper's special case (L0 != 0, h != 0, a != b) so every entry is exercised.
void test_welker_matrices_closed_form(void**) {
  const double V = 250, h = 9000, L0 = 0.4, a = 0.5, b = 0.3;
  auto m = welker(V, h, L0, a, b);
  const double ws2 = kGM / std::pow(kRe + h, 3);  // w_s^2 = g/R at radius R_e + h
  MatrixXd F, G;
  for (double t : {0.0, 1234.5, 3600.0, 20000.0}) {
    m->matrices(t, F, G);
    const double L = L0 + V / (kRe + h) * t, c = std::cos(L), s = std::sin(L);
    const double Vx = -V * s, Vz = V * c;
    // Section VI closed forms (spherical Earth).
    const double gxx = ws2 * (2 * c * c - s * s), gxz = 3 * ws2 * c * s, gzz = ws2 * (2 * s * s - c * c);
    MatrixXd Fw = MatrixXd::Zero(6, 6);
    Fw(0, 2) = Fw(1, 3) = 1;
    Fw(2, 4) = Fw(3, 5) = +1;  // dV' = 1/4 sum df + dG (docs/design.md sign fix)
    Fw(4, 2) = gxx;
    Fw(4, 3) = gxz;
    Fw(5, 2) = gxz;
    Fw(5, 3) = gzz;
    MatrixXd Gw = MatrixXd::Zero(6, 8);
    for (int i = 0; i < 4; ++i) Gw(2, i) = Gw(3, 4 + i) = 0.25;
    const double row[4] = {-Vx / (2 * a), -Vz / (2 * b), Vx / (2 * a), Vz / (2 * b)};
    for (int i = 0; i < 4; ++i) Gw(4, i) = Gw(5, 4 + i) = row[i];
    for (int i = 0; i < 6; ++i) {
      for (int j = 0; j < 6; ++j) check_rel("F entry", F(i, j), Fw(i, j), 1e-12, 1e-12 * ws2);
      for (int j = 0; j < 8; ++j) check_rel("Gamma entry", G(i, j), Gw(i, j), 1e-12, 1e-12);
    }
  }
  // The baseline gradient (what the differenced accelerometers measure) agrees
  // with the centre gradient to O((a/R)^2).
  auto mb = welker(V, h, L0, a, b, Welker2DModel::GradientSource::kBaseline);
  const Eigen::Matrix2d d = mb->gradient(777.0) - m->gradient(777.0);
  check_rel("baseline vs centre gradient", d.norm(), 0.0, 0, 1e-9 * ws2);
}

// Eigenvalues of the reduced 6x6 F along the flight: +-sqrt(2) w_s, +-j w_s
// (Welker et al. section VI) and the double zero of the position rows.
void test_eigenvalues_closed_form(void**) {
  auto m = welker(300, 0, 0);
  const double ws = std::sqrt(kGM / (kRe * kRe * kRe));
  MatrixXd F, G;
  for (double t = 0; t <= 3600; t += 450) {
    m->matrices(t, F, G);
    const auto ev = sorted_eigenvalues(F);
    assert_int_equal(ev.size(), 6);
    check_rel("+sqrt2 w_s", ev[0].real(), std::sqrt(2.0) * ws, 1e-9);
    check_rel("+sqrt2 w_s imag", ev[0].imag(), 0, 0, 1e-9 * ws);
    check_rel("-sqrt2 w_s", ev[5].real(), -std::sqrt(2.0) * ws, 1e-9);
    int n_imag = 0, n_zero = 0;
    for (int i = 1; i < 5; ++i) {
      check_rel("middle eigenvalues real part 0", ev[size_t(i)].real(), 0, 0, 1e-9 * ws);
      if (std::abs(std::abs(ev[size_t(i)].imag()) - ws) < 1e-9 * ws) ++n_imag;
      if (std::abs(ev[size_t(i)]) < 1e-9 * ws) ++n_zero;
    }
    assert_int_equal(n_imag, 2);
    assert_int_equal(n_zero, 2);
    double lu = 0;
    const MatrixXd Pi = unstable_projector(F, &lu);
    check_rel("unstable eigenvalue", lu, std::sqrt(2.0) * ws, 1e-9);
    check_rel("projector idempotent", (Pi * Pi - Pi).norm(), 0, 0, 1e-9 * Pi.norm());
    check_rel("projector commutes with F", (F * Pi - Pi * F).norm(), 0, 0, 1e-9 * ws * Pi.norm());
  }
}

// Table I of Welker et al. (one sigma after 1 h): all six within 3% with
// a = b = 0.5 m, g = GM/R_e^2; dG(0) = 2e-12 (eq. 8) or 0 makes no visible difference.
void test_table1(void**) {
  auto m = welker(300, 0, 0);
  const double ref[6] = {41.41, 5.08, 7.37e-2, 0.98e-2, 0.1291e-3, 0.0208e-3};
  const VectorXd s = final_sigmas(*m, welker_p0(2e-12, 2e-12), 3600, 1.0, Method::kTransition);
  for (int i = 0; i < 6; ++i) {
    print_message("Table I state %d: %.6g vs %.6g (%+.2f%%)\n", i, s(i), ref[i], 100 * (s(i) / ref[i] - 1));
    check_rel("Table I within 3%", s(i), ref[i], 0.03);
  }
  const VectorXd s0 = final_sigmas(*m, welker_p0(2e-12, 0), 3600, 1.0, Method::kTransition);
  for (int i = 0; i < 6; ++i) check_rel("dG(0) negligible", s0(i), s(i), 1e-6);
}

// Accuracy: step halving changes nothing above round-off at dt = 1 s; the two
// independent RK4 implementations agree; and on a coarse grid the error falls
// by ~2^4 per halving (fourth order, so the dt = 1 s figure is no accident).
void test_step_halving_and_order(void**) {
  auto m = welker(300, 0, 0);
  const MatrixXd P0 = welker_p0(2e-12, 2e-12);
  const VectorXd s1 = final_sigmas(*m, P0, 3600, 1.0, Method::kTransition);
  const VectorXd s05 = final_sigmas(*m, P0, 3600, 0.5, Method::kTransition);
  const VectorXd sl = final_sigmas(*m, P0, 3600, 1.0, Method::kLyapunov);
  for (int i = 0; i < 6; ++i) {
    check_rel("halving dt = 1 s", s1(i), s05(i), 1e-9);
    check_rel("transition vs Lyapunov", sl(i), s05(i), 1e-9);
  }
  const VectorXd s120 = final_sigmas(*m, P0, 3600, 120.0, Method::kTransition);
  const VectorXd s60 = final_sigmas(*m, P0, 3600, 60.0, Method::kTransition);
  const double e120 = std::abs(s120(0) / s05(0) - 1), e60 = std::abs(s60(0) / s05(0) - 1);
  print_message("coarse-step errors: dt 120 s %.3g, dt 60 s %.3g, ratio %.2f\n", e120, e60, e120 / e60);
  assert_true(e60 > 0);
  assert_true(e120 / e60 > 12.0 && e120 / e60 < 20.0);
}

// Signs: the linear model against the nonlinear mechanization of Welker et al.
// section V (docs/design.md: r'' = f + G, G' = Gamma_measured v) flown on simulated
// accelerometers with biases d. nav(d) - nav(0) must equal Phi_xd(T) d to first
// order; a sign error in F or Gamma (e.g. the paper's printed -dG) fails this.
struct Nav {
  long double r[2], v[2], g[2];
};

void test_linear_model_vs_mechanization(void**) {
  using LD = long double;
  const double V = 300, T = 3600, a = 0.5, b = 0.5;
  PointMassField field(kGM);
  NorthGreatCircle2D traj(V, 0, 0, kRe);
  auto sensors = [&](double t, const double d[8], LD fbar[2], LD grad[2][2]) {
    const TrajectoryPoint p = traj.at(t);
    using ggins::gravity::Vec3;
    const Vec3 r = p.r.cast<LD>();
    const Vec3 off[4] = {Vec3(a, 0, 0), Vec3(0, 0, b), Vec3(-a, 0, 0), Vec3(0, 0, -b)};
    LD f[4][2];
    for (int i = 0; i < 4; ++i) {  // f_i = a - G(r_i) + bias (specific force)
      const Vec3 gi = field.eval(r + off[i]).g;
      f[i][0] = LD(p.a(0)) - gi(0) + LD(d[i]);
      f[i][1] = LD(p.a(2)) - gi(2) + LD(d[4 + i]);
    }
    for (int k = 0; k < 2; ++k) {
      fbar[k] = (f[0][k] + f[1][k] + f[2][k] + f[3][k]) / 4;
      grad[k][0] = (f[2][k] - f[0][k]) / LD(2 * a);  // dG_k/dx = (f3 - f1)/2a
      grad[k][1] = (f[3][k] - f[1][k]) / LD(2 * b);  // dG_k/dz = (f4 - f2)/2b
    }
  };
  auto deriv = [&](double t, const Nav& s, const double d[8]) {
    LD fbar[2], grad[2][2];
    sensors(t, d, fbar, grad);
    Nav k;
    for (int i = 0; i < 2; ++i) {
      k.r[i] = s.v[i];
      k.v[i] = fbar[i] + s.g[i];
      k.g[i] = grad[i][0] * s.v[0] + grad[i][1] * s.v[1];
    }
    return k;
  };
  auto fly = [&](const double d[8]) {
    const TrajectoryPoint p0 = traj.at(0);
    const auto g0 = field.eval(p0.r.cast<LD>()).g;
    Nav s{{p0.r(0), p0.r(2)}, {p0.v(0), p0.v(2)}, {g0(0), g0(2)}};
    const double h = 1.0;
    auto axpy = [](const Nav& x, LD c, const Nav& k) {
      Nav y;
      for (int i = 0; i < 2; ++i) {
        y.r[i] = x.r[i] + c * k.r[i];
        y.v[i] = x.v[i] + c * k.v[i];
        y.g[i] = x.g[i] + c * k.g[i];
      }
      return y;
    };
    for (int n = 0; n < int(T / h); ++n) {
      const double t = n * h;
      const Nav k1 = deriv(t, s, d), k2 = deriv(t + h / 2, axpy(s, h / 2, k1), d);
      const Nav k3 = deriv(t + h / 2, axpy(s, h / 2, k2), d), k4 = deriv(t + h, axpy(s, h, k3), d);
      for (int i = 0; i < 2; ++i) {
        s.r[i] += h / 6 * (k1.r[i] + 2 * k2.r[i] + 2 * k3.r[i] + k4.r[i]);
        s.v[i] += h / 6 * (k1.v[i] + 2 * k2.v[i] + 2 * k3.v[i] + k4.v[i]);
        s.g[i] += h / 6 * (k1.g[i] + 2 * k2.g[i] + 2 * k3.g[i] + k4.g[i]);
      }
    }
    return s;
  };
  const double zero[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  const Nav n0 = fly(zero);
  auto m = welker(V, 0, 0, a, b);
  const MatrixXd Phi = transition_matrix(*m, T, 1.0);
  // Biases of paper size (x10) with mixed signs, then each axis alone.
  const double cases[3][8] = {{2e-11, -1e-11, 3e-11, -2.5e-11, 1.5e-11, 2e-11, -3e-11, 1e-11},
                              {0, 2e-11, 0, 0, 0, 0, 0, 0},
                              {0, 0, 0, 0, 0, 0, 2e-11, 0}};
  for (const auto& d : cases) {
    const Nav nd = fly(d);
    VectorXd err(6);
    for (int i = 0; i < 2; ++i) {
      err(i) = double(nd.r[i] - n0.r[i]);
      err(2 + i) = double(nd.v[i] - n0.v[i]);
      err(4 + i) = double(nd.g[i] - n0.g[i]);
    }
    const VectorXd lin = Phi.topRightCorner(6, 8) * Eigen::Map<const VectorXd>(d, 8);
    for (int i = 0; i < 6; ++i) {
      print_message("state %d: mechanization %+.6e  linear model %+.6e\n", i, err(i), lin(i));
      // each component to 1e-3 of the largest component of its own kind (r, v or G)
      const double scale = std::max(std::abs(lin(i & ~1)), std::abs(lin(i | 1)));
      check_rel("nonlinear vs linear error", err(i), lin(i), 0, 1e-3 * scale);
    }
  }
}

// The TOML loader reads the keys shared with the truth generator, and the
// repository's scenarios/welker-table1.toml describes the built-in scenario.
void test_scenario_toml(void**) {
  const std::string path = (std::filesystem::temp_directory_path() / ("ggins_cov_test_" + std::to_string(getpid()) + ".toml")).string();
  {
    std::ofstream f(path);
    f << "name = \"t\"\n[trajectory]\ntype = \"north-flight\"\nspeed_mps = 250.0\nheight_m = 100.0\n"
         "lat0_deg = 30.0\nradius_m = 6.4e6\n[gravity]\nmodel = \"point-mass\"\ngm_m3ps2 = 4e14\n"
         "[platform]\na_m = 0.4\nb_m = 0.6\n[time]\nduration_s = 600.0\nrate_hz = 50.0\n"
         "[accel]\nbias_sigma_mps2 = [1e-12, 2e-12, 3e-12, 4e-12, 5e-12, 6e-12, 7e-12, 8e-12]\n"
         "noise_sigma_mps2 = 1e-10\n[initial]\ngravity_sigma_mps2 = [1e-12, 3e-12]\n";
  }
  const CovScenario s = load_scenario_toml(path);
  check_rel("speed", s.speed_mps, 250, 0, 0);
  check_rel("height", s.height_m, 100, 0, 0);
  check_rel("lat0", s.lat0_rad, M_PI / 6, 1e-15);
  check_rel("radius", s.radius_m, 6.4e6, 0, 0);
  check_rel("gm", s.gm_m3ps2, 4e14, 0, 0);
  check_rel("a", s.a_m, 0.4, 0, 0);
  check_rel("b", s.b_m, 0.6, 0, 0);
  check_rel("duration", s.duration_s, 600, 0, 0);
  check_rel("rate", s.rate_hz, 50, 0, 0);
  check_rel("bias[7]", s.bias_sigma_mps2[7], 8e-12, 0, 0);
  check_rel("noise[3]", s.noise_sigma_mps2[3], 1e-10, 0, 0);
  check_rel("dGz(0)", s.gravity0_sigma_z_mps2, 3e-12, 0, 0);
  {
    std::ofstream f(path);
    f << "[trajectory]\ntype = \"figure-eight\"\n";
  }
  bool threw = false;
  try {
    load_scenario_toml(path);
  } catch (const std::runtime_error&) {
    threw = true;
  }
  assert_true(threw);
  std::filesystem::remove(path);

  const std::string repo = std::string(GGINS_SOURCE_DIR) + "/scenarios/welker-table1.toml";
  if (!std::filesystem::exists(repo)) skip();
  const CovScenario r = load_scenario_toml(repo), bi = *builtin_scenario("welker-table1");
  check_rel("repo toml speed", r.speed_mps, bi.speed_mps, 0, 0);
  check_rel("repo toml height", r.height_m, bi.height_m, 0, 0);
  check_rel("repo toml lat0", r.lat0_rad, bi.lat0_rad, 0, 0);
  check_rel("repo toml radius", r.radius_m, bi.radius_m, 0, 0);
  check_rel("repo toml gm", r.gm_m3ps2, bi.gm_m3ps2, 0, 0);
  check_rel("repo toml a", r.a_m, bi.a_m, 0, 0);
  check_rel("repo toml b", r.b_m, bi.b_m, 0, 0);
  check_rel("repo toml duration", r.duration_s, bi.duration_s, 0, 0);
  for (int i = 0; i < 8; ++i) check_rel("repo toml bias", r.bias_sigma_mps2[size_t(i)], bi.bias_sigma_mps2[size_t(i)], 0, 0);
}

// The judged command: `ggins-covariance --scenario welker-table1 --json` holds
// the six keys, each within 3% of Table I.
void test_cli_json(void**) {
  const std::string out = (std::filesystem::temp_directory_path() / ("ggins_cov_cli_test_" + std::to_string(getpid()))).string();
  const std::string cmd = std::string("'") + GGINS_COVARIANCE_EXE + "' --scenario welker-table1 --json --no-plot --out '" +
                          out + "'";
  FILE* p = popen(cmd.c_str(), "r");
  assert_non_null(p);
  std::string text;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) text.append(buf, n);
  assert_int_equal(pclose(p), 0);
  const auto j = nlohmann::json::parse(text);
  const char* keys[6] = {"x_m", "z_m", "vx_mps", "vz_mps", "gx_mps2", "gz_mps2"};
  const double ref[6] = {41.41, 5.08, 7.37e-2, 0.98e-2, 0.1291e-3, 0.0208e-3};
  for (int i = 0; i < 6; ++i) {
    assert_true(j.contains(keys[i]));
    check_rel(keys[i], j[keys[i]].get<double>(), ref[i], 0.03);
  }
  check_rel("t_s", j["t_s"].get<double>(), 3600, 0, 1e-9);
  assert_true(j["integration"]["max_rel_diff_half_step"].get<double>() < 1e-6);
  assert_true(std::filesystem::exists(out + "/covariance.csv"));
  std::filesystem::remove_all(out);
}

}  // namespace

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_double_integrator),
      cmocka_unit_test(test_scalar_exponential_and_time_varying),
      cmocka_unit_test(test_white_noise_random_walk),
      cmocka_unit_test(test_welker_matrices_closed_form),
      cmocka_unit_test(test_eigenvalues_closed_form),
      cmocka_unit_test(test_table1),
      cmocka_unit_test(test_step_halving_and_order),
      cmocka_unit_test(test_linear_model_vs_mechanization),
      cmocka_unit_test(test_scenario_toml),
      cmocka_unit_test(test_cli_json),
  };
  return cmocka_run_group_tests_name("covariance", tests, NULL, NULL);
}
