// Post-mission gravimetry (host_tools/lib/gravimetry/survey.hpp) against independent truth:
// the filter against its analytic response, the adjustment against the Brownian bridge's
// closed form and against a Monte Carlo of the error model it assumes, crossovers against
// the geometry of two straight tracks, lines found on a drawn pattern, the record read back.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <vector>

extern "C" {
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>
}

#include "ggins/gravimetry/survey.hpp"

namespace gv = ggins::gravimetry;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A record on a flat patch near 60 N: samples at 1 Hz along a polyline of (east, north) points
// flown at v m/s; enu filled directly (read_record computes it from lat/lon for a file).
gv::Record track(const std::vector<std::pair<double, double>>& pts, double v, double q_rw) {
  gv::Record r;
  r.rate_hz = 1;
  double t = 0, tau = 0;
  for (size_t k = 0; k + 1 < pts.size(); ++k) {
    const double dx = pts[k + 1].first - pts[k].first, dy = pts[k + 1].second - pts[k].second;
    const double L = std::hypot(dx, dy);
    const int n = static_cast<int>(std::floor(L / v));
    for (int i = 0; i < n; ++i) {
      gv::Sample s;
      s.t = t;
      s.seq = static_cast<int64_t>(t * 100);
      s.enu = {pts[k].first + dx * i * v / L, pts[k].second + dy * i * v / L, 0};
      s.true_enu = s.enu;
      s.lat_deg = 60 + s.enu[1] / 111e3;
      s.lon_deg = 10 + s.enu[0] / 55.6e3;
      s.h_m = 1000;
      s.speed_mps = v;
      s.var_rw = {tau, tau, tau};
      s.g_abs = 9.81;
      r.s.push_back(s);
      t += 1;
      tau += q_rw;
    }
  }
  return r;
}

// 1. A sinusoid through the zero-phase filter comes out scaled by |H(f)|^2 and not shifted.
void test_lowpass_response(void**) {
  const double dt = 1, fc = 0.02;
  for (double f : {0.005, 0.01, 0.02, 0.03}) {
    std::vector<double> x(4000);
    for (size_t i = 0; i < x.size(); ++i) x[i] = std::sin(2 * kPi * f * static_cast<double>(i) * dt + 0.3);
    const auto y = gv::lowpass(x, dt, fc, 4);
    // the bilinear transform maps f to tan(pi f dt) / tan(pi fc dt)
    const double r = std::tan(kPi * f * dt) / std::tan(kPi * fc * dt);
    const double g = 1 / (1 + std::pow(r, 8));
    double worst = 0;
    for (size_t i = 1000; i < 3000; ++i) worst = std::max(worst, std::fabs(y[i] - g * x[i]));
    std::printf("  f = %.3f Hz: gain %.4f, worst deviation %.2e\n", f, g, worst);
    assert_true(worst < 2e-3);
  }
  assert_true(std::fabs(gv::lowpass_gain(0.02, 0.02) - 0.5) < 1e-15);
  std::vector<double> c(300, 4.25);  // a constant passes unchanged, edges included
  for (double y : gv::lowpass(c, 1, 0.01)) assert_true(std::fabs(y - 4.25) < 1e-9);
}

// 2. One closing observation of a Brownian motion: the posterior is the bridge,
//    mean (tau / tau_c) y and variance tau (tau_c - tau) / tau_c before it, tau - tau_c after.
void test_bridge(void**) {
  const double q = 1e-14;
  gv::Record r = track({{0, 0}, {50000, 0}}, 100, q);
  const size_t c = 300;
  gv::Observation o;
  o.kind = "closing";
  o.coef = {{c, 1.0}};
  o.y = {3e-6, -2e-6, 1e-6};
  o.var = 1e-30;
  const gv::Adjusted a = gv::adjust(r, {o});
  const double tc = r.s[c].var_rw[0];
  double worst_m = 0, worst_s = 0;
  for (size_t i = 0; i < r.s.size(); ++i) {
    const double tau = r.s[i].var_rw[0];
    const double m = tau <= tc ? tau / tc : 1.0;
    const double v = tau <= tc ? tau * (tc - tau) / tc : tau - tc;
    worst_m = std::max(worst_m, std::fabs(a.value[i][0] - (0 - m * o.y[0])));
    worst_s = std::max(worst_s, std::fabs(a.sigma[i][0] - std::sqrt(v)));
  }
  std::printf("  bridge: mean worst %.2e, sigma worst %.2e (sigma at the middle %.2e)\n", worst_m, worst_s,
              std::sqrt(tc / 4));
  assert_true(worst_m < 1e-15);
  assert_true(worst_s < 1e-12);
}

// 2b. A constant body-axis gradient error (no random walk): its share is dGamma B(t) with B the
//     path integral (on a strapdown body flying forward: the path length). One exact closing
//     observation of it fixes the error everywhere, before and after, and the sigma goes to 0.
void test_bias_from_closing(void**) {
  gv::Record r = track({{0, 0}, {20000, 0}, {20000, 3000}, {0, 3000}}, 100, 0);
  r.sigma_gamma_bias_ps2 = 3e-12;
  double len = 0;
  for (size_t i = 0; i < r.s.size(); ++i) {
    if (i) len += std::hypot(r.s[i].enu[0] - r.s[i - 1].enu[0], r.s[i].enu[1] - r.s[i - 1].enu[1]);
    for (auto& b : r.s[i].bias_coef) b[6] = len;  // the zx entry
    const double e = 5e-12 * len;                   // the drawn constant: 5e-12 s^-2
    r.s[i].est = {e, e, e};
  }
  gv::Observation o;
  o.kind = "closing";
  o.coef = {{r.s.size() - 1, 1.0}};
  o.y = r.s.back().est;
  o.var = 1e-30;
  const gv::Adjusted a = gv::adjust(r, {o});
  double worst = 0, worst_s = 0, prior_end = 3e-12 * len;
  for (size_t i = 0; i < r.s.size(); ++i) {
    worst = std::max(worst, std::fabs(a.value[i][2]));
    worst_s = std::max(worst_s, a.sigma[i][2]);
  }
  std::printf("  bias: prior sigma at the end %.2e, residual worst %.2e, posterior sigma worst %.2e\n", prior_end, worst,
              worst_s);
  assert_true(worst < 1e-14 && worst_s < 1e-12);
}

// 2c. Rubenstein & Winter's loop output -a_c = H_g(s) dg (a third-order low-pass, poles p_i),
//     simulated by integrating its ODE (RK4, 10 ms steps) on a sinusoidal disturbance of 900 s
//     period, is undone by the product within its band: the result against the filtered truth.
void test_loop_inverse(void**) {
  gv::Record r = track({{0, 0}, {300000, 0}}, 100, 0);
  r.mode = "model";
  r.loop_poles = {0.01, 0.02, 0.03};
  const double A = 2e-4, T = 900, w = 2 * kPi / T;
  const double p1 = 0.01, p2 = 0.02, p3 = 0.03;
  // H_g as three first-order lags in series: x1' = p1 (u - x1), x2' = p2 (x1 - x2), x3' = p3 (x2 - x3)
  double x[3] = {0, 0, 0}, t = 0;
  const double h = 0.01;
  auto f = [&](double tt, const double* s0, double* d) {
    const double u = A * std::sin(w * tt);
    d[0] = p1 * (u - s0[0]);
    d[1] = p2 * (s0[0] - s0[1]);
    d[2] = p3 * (s0[1] - s0[2]);
  };
  for (size_t k = 0; k < r.s.size(); ++k) {
    gv::Sample& smp = r.s[k];
    for (; t < static_cast<double>(k) * 100; t += 1) {  // t counts the 10 ms steps
      const double ts = t * h;
      double k1[3], k2[3], k3[3], k4[3], y[3];
      f(ts, x, k1);
      for (int i = 0; i < 3; ++i) y[i] = x[i] + h / 2 * k1[i];
      f(ts + h / 2, y, k2);
      for (int i = 0; i < 3; ++i) y[i] = x[i] + h / 2 * k2[i];
      f(ts + h / 2, y, k3);
      for (int i = 0; i < 3; ++i) y[i] = x[i] + h * k3[i];
      f(ts + h, y, k4);
      for (int i = 0; i < 3; ++i) x[i] += h / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
    }
    smp.est = {0, 0, x[2]};
    smp.truth_true = {0, 0, A * std::sin(w * smp.t)};
    smp.truth_nav = smp.truth_true;
  }
  std::vector<gv::Line> L(1);
  L[0] = {10, false, 1000, 2400, 90, 140000, 100};  // after the loop's start-up, 600 s before the record ends
  const gv::Adjusted a = gv::adjust(r, {});
  const gv::Product p = gv::make_product(r, L, a, 20000);  // 200 s cut-off: the 900 s period passes
  double worst = 0, lagged = 0;
  for (size_t i = 0; i < p.idx.size(); ++i) {

    worst = std::max(worst, std::fabs(p.est[i][2] - p.truth_true[i][2]));
    lagged = std::max(lagged, std::fabs(r.s[p.idx[i]].est[2] - r.s[p.idx[i]].truth_true[2]));
  }
  std::printf("  loop output against the truth: %.2e (lagged), inverted %.2e m/s^2 (amplitude %.1e)\n", lagged, worst, A);
  assert_true(lagged > 0.5 * A);
  assert_true(worst < 1e-3 * A);
}

// 3. Two straight tracks crossing at a known point: one crossover there, its value the
//    difference of the two estimates at that point.
void test_crossover_geometry(void**) {
  gv::Record r = track({{0, 0}, {20000, 0}, {20000, 3000}, {7000, 3000}, {7000, -4000}}, 50, 0);
  for (auto& s : r.s) s.est = {1e-5 * s.enu[0] / 1000, 0, s.t < 700 ? 2e-5 : -1e-5};  // a field in x, two offsets
  std::vector<gv::Line> L(2);
  L[0].number = 10;
  L[0].begin = 0;
  L[0].end = 400;   // the first leg
  L[1].number = 1000;
  L[1].tie = true;
  L[1].begin = 660;  // the last leg (x = 7000, going south)
  L[1].end = r.s.size();
  const auto xo = gv::crossovers(r, L, 0);
  assert_int_equal(xo.size(), 1);
  std::printf("  crossover at lat %.6f lon %.6f, values %.3e %.3e %.3e\n", xo[0].lat_deg, xo[0].lon_deg, xo[0].y[0],
              xo[0].y[1], xo[0].y[2]);
  assert_true(std::fabs(xo[0].lon_deg - (10 + 7000 / 55.6e3)) < 1e-6);
  assert_true(std::fabs(xo[0].lat_deg - 60) < 1e-6);
  assert_true(std::fabs(xo[0].y[0]) < 1e-15);              // the same field value at the same point
  assert_true(std::fabs(xo[0].y[2] - 3e-5) < 1e-15);       // the offsets' difference
}

// 4. Monte Carlo of the model the adjustment assumes: draw Brownian errors, observe them at
//    crossovers and a closing; the posterior sigma must match the spread of the residual errors.
void test_posterior_matches_monte_carlo(void**) {
  const double q = 4e-15;
  // a racetrack: out along y = 0, back along y = 2000, then a tie across both, back to the start
  gv::Record r = track({{0, 0}, {30000, 0}, {30000, 2000}, {0, 2000}, {15000, -2000}, {15000, 4000}, {0, 4000},
                        {0, 0}},
                       60, q);
  std::vector<gv::Line> L(3);
  L[0] = {10, false, 50, 450, 90, 0, 60};
  L[1] = {20, false, 560, 950, 270, 0, 60};
  L[2] = {1000, true, 1300, 1350, 0, 0, 60};
  // find the tie's samples: the leg x = 15000 from y = -2000 to 4000
  size_t b = 0, e = 0;
  for (size_t i = 1; i < r.s.size(); ++i) {
    const bool on = std::fabs(r.s[i].enu[0] - 15000) < 1 && std::fabs(r.s[i - 1].enu[0] - 15000) < 1;
    if (on && !b) b = i - 1;
    if (on) e = i + 1;
  }
  L[2].begin = b;
  L[2].end = e;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> N(0, 1);
  double sum_z2 = 0;
  size_t nz = 0;
  const int runs = 400;
  for (int k = 0; k < runs; ++k) {
    std::vector<double> err(r.s.size());
    double x = 0;
    for (size_t i = 0; i < r.s.size(); ++i) {
      if (i) x += std::sqrt(r.s[i].var_rw[0] - r.s[i - 1].var_rw[0]) * N(rng);
      err[i] = x;
      r.s[i].est = {err[i], err[i], err[i]};  // truth 0
    }
    std::vector<gv::Observation> obs = gv::crossovers(r, L, 0);
    gv::Observation c;
    c.kind = "closing";
    c.coef = {{r.s.size() - 1, 1.0}};
    c.y = r.s.back().est;
    c.var = 1e-30;
    obs.push_back(c);
    if (k == 0) {
      std::printf("  %zu observations\n", obs.size());
      assert_int_equal(obs.size(), 3);  // the tie crosses both lines; the closing
    }
    const gv::Adjusted a = gv::adjust(r, obs);
    for (size_t i = 10; i + 30 < r.s.size(); i += 25) {
      const double z = a.value[i][0] / a.sigma[i][0];
      sum_z2 += z * z;
      ++nz;
    }
  }
  const double m = sum_z2 / static_cast<double>(nz);
  std::printf("  mean (residual error / posterior sigma)^2 over %zu: %.3f\n", nz, m);
  assert_true(m > 0.85 && m < 1.15);
}

// 5. Lines and ties on a drawn pattern: three E-W lines joined by turns, one N-S tie.
void test_find_lines(void**) {
  gv::Record r = track({{0, 0}, {20000, 0}, {21000, 1000}, {20000, 2000}, {0, 2000}, {-1000, 3000}, {0, 4000},
                        {20000, 4000}, {21000, 3000}, {10000, -3000}, {10000, 6000}},
                       80, 0);
  for (auto& s : r.s) s.h_m = 1000;
  gv::LineOptions o;
  o.min_length_m = 5000;
  const auto L = gv::find_lines(r, o);
  int lines = 0, ties = 0;
  for (const auto& l : L) {
    std::printf("  %s %d: %.0f m, heading %.1f\n", l.tie ? "tie" : "line", l.number, l.length_m, l.heading_deg);
    (l.tie ? ties : lines)++;
  }
  assert_int_equal(lines, 3);
  assert_int_equal(ties, 2);  // the oblique leg (21000, 3000) -> (10000, -3000) and the N-S tie
  assert_int_equal(L[0].number, 10);
  assert_true(L.back().tie);
}

// 6. The record read back from the file ggins run3d writes (its header), with a bad row named.
void test_read_record(void**) {
  const auto dir = std::filesystem::temp_directory_path() / "ggins_test_gravimetry";
  std::filesystem::create_directories(dir);
  const char* head =
      "t_s,seq,nav_lat_deg,nav_lon_deg,nav_h_m,true_lat_deg,true_lon_deg,true_h_m,speed_mps,est_dg_n_mps2,"
      "est_dg_e_mps2,est_dg_d_mps2,truth_nav_dg_n_mps2,truth_nav_dg_e_mps2,truth_nav_dg_d_mps2,truth_true_dg_n_mps2,"
      "truth_true_dg_e_mps2,truth_true_dg_d_mps2,loop_a_c_mps2,var_rw_n_mps2sq,var_rw_e_mps2sq,var_rw_d_mps2sq,"
      "est_gam_nn_E,est_gam_ee_E,"
      "est_gam_dd_E,est_gam_ne_E,est_gam_nd_E,est_gam_ed_E,health\n";
  {
    std::ofstream f(dir / "gravimetry_raw.csv");
    f << head;
    for (int i = 0; i < 20; ++i)
      f << i << "," << i * 100 << "," << 45.0 + i * 1e-3 << ",10,1000,45,10,1000,100,1e-5,2e-5,3e-5,0,0,0,0,0,0,0,"
        << i * 1e-15 << "," << i * 1e-15 << "," << i * 1e-15 << ",1,2,3,4,5,6,0\n";
  }
  const gv::Record r = gv::read_record(dir);
  assert_int_equal(r.s.size(), 20);
  // 1e-3 deg of latitude at 45 N, 1000 m up: (M + h) dphi, M = a (1 - e^2) / (1 - e^2 sin^2)^1.5
  const double e2 = 6.69437999014e-3, s2 = 0.5;
  const double M = 6378137.0 * (1 - e2) / std::pow(1 - e2 * s2, 1.5);
  const double dn = r.s[1].enu[1] - r.s[0].enu[1], want = (M + 1000) * 1e-3 * kPi / 180;
  std::printf("  north step %.4f m (meridian arc %.4f m)\n", dn, want);
  assert_true(std::fabs(dn - want) < 0.01);
  assert_true(std::fabs(r.s[5].est[2] - 3e-5) < 1e-20);
  {
    std::ofstream f(dir / "gravimetry_raw.csv");
    f << head << "0,0,45\n";
  }
  bool threw = false;
  try {
    gv::read_record(dir);
  } catch (const std::exception& e) {
    std::printf("  refused: %s\n", e.what());
    threw = std::string(e.what()).find(":2:") != std::string::npos;
  }
  assert_true(threw);
  std::filesystem::remove_all(dir);
}

}  // namespace

int main() {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_lowpass_response),    cmocka_unit_test(test_bridge),
      cmocka_unit_test(test_bias_from_closing),   cmocka_unit_test(test_loop_inverse),
      cmocka_unit_test(test_crossover_geometry),  cmocka_unit_test(test_posterior_matches_monte_carlo),
      cmocka_unit_test(test_find_lines),          cmocka_unit_test(test_read_record),
  };
  return cmocka_run_group_tests(tests, nullptr, nullptr);
}
