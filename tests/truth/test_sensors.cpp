// Sensor error models of the simulation library (truth/sensors.hpp) against
// the statistics they claim, computed analytically:
//   accelerometer / gyro  m = (1 + s) x + b + n:  the reading is affine in the
//     true value with slope 1 + s and offset b (exactly, without noise);
//     b ~ N(fixed, sigma_b^2), s ~ N(fixed, sigma_s^2) across sensors and seeds;
//     n white N(0, sigma_n^2): zero lag-1 autocorrelation, variance sigma_n^2;
//     unmeasured axes read the true value; the 2-D and 3-D streams are uncorrelated.
//   barometer  Gauss-Markov m_j: variance sigma^2 at every j (stationary start),
//     lag-L correlation phi^L = exp(-L T / tau); white noise variance; bias.
// Sample variances are checked against the chi-square band for their degrees
// of freedom (Wilson-Hilferty, +-4 standard-normal quantiles), means against
// +-4 standard errors, correlations against +-4 / sqrt(N).
#include <cmath>
#include <cstdio>
#include <vector>

#include "ggins/truth/sensors.hpp"
#include "ggins/truth/stats.hpp"

using namespace ggins::truth;

#include "check.hpp"

// sample mean and variance about a known mean (N degrees of freedom)
struct Moments {
  double mean = 0, var_known = 0;
  size_t n = 0;
};
static Moments moments(const std::vector<double>& x, double mu) {
  Moments m;
  m.n = x.size();
  for (double v : x) m.mean += v;
  m.mean /= static_cast<double>(m.n);
  for (double v : x) m.var_known += (v - mu) * (v - mu);
  m.var_known /= static_cast<double>(m.n);
  return m;
}
static bool var_ok(const Moments& m, double sigma2, double* ratio) {
  const Chi2Band b = chi2_band(static_cast<double>(m.n), 4.0);
  *ratio = m.var_known / sigma2;
  return *ratio >= b.ms_lo && *ratio <= b.ms_hi;
}
static bool mean_ok(const Moments& m, double mu, double sigma) {
  return std::fabs(m.mean - mu) <= 4.0 * sigma / std::sqrt(static_cast<double>(m.n));
}
static double corr(const std::vector<double>& a, const std::vector<double>& b) {
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += a[i] * b[i];
    saa += a[i] * a[i];
    sbb += b[i] * b[i];
  }
  return sab / std::sqrt(saa * sbb);
}

static void test_accel_affine() {
  AccelErrorParams p;
  p.seed = 9;
  p.bias_sigma_mps2 = 1e-6;
  p.scale_sigma = 1e-4;
  p.bias_mps2[1][2] = 3e-6;  // fixed parts add to the random ones
  p.scale[1][2] = 2e-4;
  const AccelModel a(p, 4, {true, false, true}, kAccelStreams2D);
  const AccelModel a0(AccelErrorParams{}, 4, {true, false, true}, kAccelStreams2D);
  double worst_b = 0, worst_s = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 3; ++j) {
      const Real f1 = 9.80665L, f2 = -3.5L;
      const Real r0 = a.read(17, i, j, 0.0L), r1 = a.read(17, i, j, f1), r2 = a.read(17, i, j, f2);
      worst_b = std::max(worst_b, static_cast<double>(std::fabs(r0 - static_cast<Real>(a.bias(i, j)))));
      const Real slope = (r1 - r2) / (f1 - f2);
      worst_s = std::max(worst_s, static_cast<double>(std::fabs(slope - 1 - static_cast<Real>(a.scale(i, j)))));
      if (j == 1) CHECK(a.bias(i, j) == 0 && a.scale(i, j) == 0 && r1 == f1, "accel: unmeasured axis y of sensor %d reads the truth", i);
      CHECK(a0.read(5, i, j, f1) == f1, "accel: error-free model reads the truth exactly (sensor %d axis %d)", i, j);
    }
  CHECK(worst_b < 1e-18, "accel: reading at f = 0 is the bias (worst %.2g m/s^2)", worst_b);
  CHECK(worst_s < 1e-15, "accel: slope of the reading is 1 + scale (worst %.2g)", worst_s);
  // fixed bias and scale of sensor 1, axis z: the random draw plus the given value
  AccelErrorParams q = p;
  q.bias_mps2 = {};
  q.scale = {};
  const AccelModel aq(q, 4, {true, false, true}, kAccelStreams2D);
  CHECK(std::fabs(a.bias(1, 2) - aq.bias(1, 2) - 3e-6) < 1e-21 && std::fabs(a.scale(1, 2) - aq.scale(1, 2) - 2e-4) < 1e-19,
        "accel: fixed bias 3e-6 and scale 2e-4 add to the random draw");
}

static void test_accel_statistics() {
  // constant bias and scale: across 2000 seeds x 6 sensors x 3 axes
  const double sb = 2e-12, ss = 5e-5, sn = 1e-5;
  std::vector<double> b, s, b3;
  for (uint64_t seed = 1; seed <= 2000; ++seed) {
    AccelErrorParams p;
    p.seed = seed;
    p.bias_sigma_mps2 = sb;
    p.scale_sigma = ss;
    const AccelModel a(p, 6, {true, true, true}, kAccelStreams2D);
    const AccelModel a3(p, 6, {true, true, true}, kAccelStreams3D);
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 3; ++j) {
        b.push_back(a.bias(i, j));
        s.push_back(a.scale(i, j));
        b3.push_back(a3.bias(i, j));
      }
  }
  double r = 0;
  const Moments mb = moments(b, 0), ms = moments(s, 0);
  CHECK(mean_ok(mb, 0, sb) && var_ok(mb, sb * sb, &r), "accel: bias mean %.3g, variance / sigma^2 = %.4f (N = %zu)", mb.mean, r, mb.n);
  CHECK(mean_ok(ms, 0, ss) && var_ok(ms, ss * ss, &r), "accel: scale mean %.3g, variance / sigma^2 = %.4f", ms.mean, r);
  const double c23 = corr(b, b3), cbs = corr(b, s);
  const double lim = 4.0 / std::sqrt(static_cast<double>(b.size()));
  CHECK(std::fabs(c23) < lim, "accel: 2-D and 3-D bias streams uncorrelated (r = %.4f, |r| < %.4f)", c23, lim);
  CHECK(std::fabs(cbs) < lim, "accel: bias and scale uncorrelated (r = %.4f)", cbs);
  // white noise along k: variance, zero mean, lag-1 autocorrelation 0
  AccelErrorParams p;
  p.seed = 4;
  p.noise_sigma_mps2 = sn;
  const AccelModel a(p, 4, {true, false, true}, kAccelStreams2D);
  std::vector<double> n0, n1, nz;
  for (int64_t k = 0; k < 40000; ++k) {
    n0.push_back(static_cast<double>(a.read(k, 2, 0, 0.0L)));
    n1.push_back(static_cast<double>(a.read(k + 1, 2, 0, 0.0L)));
    nz.push_back(static_cast<double>(a.read(k, 2, 2, 0.0L)));
  }
  const Moments mn = moments(n0, 0);
  CHECK(mean_ok(mn, 0, sn) && var_ok(mn, sn * sn, &r), "accel: noise mean %.3g, variance / sigma^2 = %.4f (N = %zu)", mn.mean, r, mn.n);
  const double l1 = corr(n0, n1), xz = corr(n0, nz), lim2 = 4.0 / std::sqrt(static_cast<double>(n0.size()));
  CHECK(std::fabs(l1) < lim2, "accel: noise lag-1 autocorrelation %.4f (|r| < %.4f)", l1, lim2);
  CHECK(std::fabs(xz) < lim2, "accel: noise of the x and z axes uncorrelated (r = %.4f)", xz);
  CHECK(a.read(123, 2, 0, 0.0L) == a.read(123, 2, 0, 0.0L), "accel: the noise of step k is a pure function of (seed, k)");
}

static void test_gyro() {
  const double sb = 1e-8, sn = 1e-6;
  std::vector<double> b;
  for (uint64_t seed = 1; seed <= 4000; ++seed) {
    GyroErrorParams p;
    p.seed = seed;
    p.bias_sigma_radps = sb;
    const GyroModel g(p, kGyroStreams3D);
    for (int j = 0; j < 3; ++j) b.push_back(g.bias(j));
  }
  double r = 0;
  const Moments mb = moments(b, 0);
  CHECK(mean_ok(mb, 0, sb) && var_ok(mb, sb * sb, &r), "gyro: bias mean %.3g, variance / sigma^2 = %.4f (N = %zu)", mb.mean, r, mb.n);
  GyroErrorParams p;
  p.bias_radps = {1e-7, 0, 0};
  p.scale = {0, 3e-4, 0};
  const GyroModel g(p, kGyroStreams3D);
  CHECK(g.read(0, 0, 0.0L) == static_cast<Real>(1e-7) && g.read(0, 0, 0.1L) == 0.1L + static_cast<Real>(1e-7),
        "gyro: fixed bias added exactly");
  CHECK(std::fabs(static_cast<double>(g.read(0, 1, 0.2L) - 0.2L * (1 + static_cast<Real>(3e-4)))) < 1e-19, "gyro: fixed scale factor");
  p = GyroErrorParams{};
  p.noise_sigma_radps = sn;
  const GyroModel gn(p, kGyroStreams3D);
  std::vector<double> n0, n1;
  for (int64_t k = 0; k < 40000; ++k) {
    n0.push_back(static_cast<double>(gn.read(k, 1, 0.0L)));
    n1.push_back(static_cast<double>(gn.read(k + 1, 1, 0.0L)));
  }
  const Moments mn = moments(n0, 0);
  const double l1 = corr(n0, n1), lim = 4.0 / std::sqrt(static_cast<double>(n0.size()));
  CHECK(mean_ok(mn, 0, sn) && var_ok(mn, sn * sn, &r), "gyro: noise variance / sigma^2 = %.4f", r);
  CHECK(std::fabs(l1) < lim, "gyro: noise lag-1 autocorrelation %.4f (|r| < %.4f)", l1, lim);
}

static void test_baro() {
  // Gauss-Markov: 1 Hz samples at 100 Hz steps, tau = 20 s; over 3000 seeds
  const double sigma = 2.0, tau = 20.0, T = 1.0;
  const int lag = 5;
  std::vector<double> m0, mL, m40, w;
  for (uint64_t seed = 1; seed <= 3000; ++seed) {
    BaroParams p;
    p.enable = true;
    p.seed = seed;
    p.gm_sigma_m = sigma;
    p.gm_tau_s = tau;
    const BaroModel b(p, 100, 100 * 60 + 1, 10000);
    m0.push_back(b.sample(0, 0.0, 100.0).gm_m);
    mL.push_back(b.sample(100 * lag, lag * T, 100.0).gm_m);
    m40.push_back(b.sample(100 * 40, 40.0, 100.0).gm_m);
    const BaroSample s = b.sample(100 * 40, 40.0, 100.0);
    w.push_back(s.alt_m - 100.0 - s.gm_m);  // bias 0, noise 0: the rest is 0
  }
  double r = 0;
  const Moments a = moments(m0, 0), c = moments(m40, 0);
  CHECK(var_ok(a, sigma * sigma, &r), "baro: Gauss-Markov variance at j = 0: %.4f sigma^2 (stationary start)", r);
  CHECK(var_ok(c, sigma * sigma, &r), "baro: Gauss-Markov variance at j = 40: %.4f sigma^2", r);
  const double rho = corr(m0, mL), phiL = std::exp(-lag * T / tau), lim = 4.0 * (1 - phiL * phiL) / std::sqrt(3000.0);
  CHECK(std::fabs(rho - phiL) < lim, "baro: lag-%d correlation %.4f, analytic exp(-L T / tau) = %.4f (+-%.3f)", lag, rho, phiL, lim);
  CHECK(std::sqrt(moments(w, 0).var_known) < 1e-13, "baro: without bias and noise the sample is h + m_j (to rounding)");
  // white noise and bias
  BaroParams p;
  p.enable = true;
  p.bias_m = 1.25;
  p.noise_sigma_m = 0.5;
  const BaroModel b(p, 10, 10 * 20000 + 1, 10000);
  std::vector<double> e;
  for (int64_t j = 0; j < 20000; ++j) {
    const BaroSample s = b.sample(10 * j, 0.1 * static_cast<double>(j), 50.0);
    e.push_back(s.alt_m - 50.0);
  }
  const Moments me = moments(e, 1.25);
  CHECK(mean_ok(me, 1.25, 0.5) && var_ok(me, 0.25, &r), "baro: bias 1.25 m (mean %.4f), noise variance / sigma^2 = %.4f", me.mean, r);
  CHECK(!b.sample(15, 0.15, 50.0).due && b.sample(20, 0.2, 50.0).due, "baro: a sample every `every` steps only");
}

int main() {
  test_accel_affine();
  test_accel_statistics();
  test_gyro();
  test_baro();
  std::printf("%s (%d failures)\n", g_fail ? "FAILED" : "all passed", g_fail);
  return g_fail ? 1 : 0;
}
