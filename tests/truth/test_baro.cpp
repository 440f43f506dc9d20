// Truth barometer: statistics of the generated error against the
// model it claims (generator.hpp, BaroSample): constant bias, first-order
// Gauss-Markov error by the exact discrete recursion (stationary variance
// sigma^2, autocorrelation exp(-|lag| / tau)), white noise, sample rate,
// dropouts (probability and scheduled windows), outliers, NaN samples.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "ggins/truth/generator.hpp"

using namespace ggins::truth;

#include "check.hpp"

static Scenario scen(double duration_s, double rate_hz, const std::string& baro) {
  char head[256];
  std::snprintf(head, sizeof head, "[time]\nduration_s = %.1f\nrate_hz = %.1f\n[baro]\n", duration_s, rate_hz);
  return parse_scenario(std::string(head) + baro, "baro-test", "test");
}

struct Series {
  std::vector<double> e;  // errors of the samples sent
  int due = 0, dropped = 0, outliers = 0, invalid = 0;
};

static Series collect(const Generator& g, int64_t stride_check_every) {
  Series s;
  for (int64_t k = 0; k < g.n_steps(); ++k) {
    const bool due_expected = k % stride_check_every == 0;
    TruthState t;
    t.seq = k;
    t.t_s = g.time_of(k);
    t.kin = g.trajectory().at(t.t_s);  // altitude only: no field evaluation needed
    const BaroSample b = g.baro(k, t);
    if (b.due != due_expected) {
      CHECK(false, "sample due at step %lld: %d", static_cast<long long>(k), b.due);
      return s;
    }
    if (!b.due) continue;
    ++s.due;
    if (b.dropped) {
      ++s.dropped;
      if (b.status != GG_SENSOR_ABSENT || !std::isnan(b.alt_m)) CHECK(false, "dropped sample carries data");
      continue;
    }
    if (b.invalid) {
      ++s.invalid;
      if (!std::isnan(b.alt_m) || b.status != GG_SENSOR_OK) CHECK(false, "invalid sample is not NaN/OK");
      continue;
    }
    s.outliers += b.outlier;
    if (std::fabs(b.alt_m - b.true_alt_m - b.error_m) > 1e-6) CHECK(false, "alt - true != error");
    s.e.push_back(b.error_m);
  }
  return s;
}

static double mean(const std::vector<double>& v) {
  double m = 0;
  for (double x : v) m += x;
  return m / static_cast<double>(v.size());
}

static double autocorr(const std::vector<double>& v, size_t lag) {
  const double m = mean(v);
  double c0 = 0, cl = 0;
  for (size_t i = 0; i < v.size(); ++i) c0 += (v[i] - m) * (v[i] - m);
  for (size_t i = 0; i + lag < v.size(); ++i) cl += (v[i] - m) * (v[i + lag] - m);
  return cl / c0;
}

int main() {
  {  // Gauss-Markov + bias: 1000 h of 1 Hz samples (6000 correlation times)
    const double sig = 3.0, tau = 600.0, bias = 2.0;
    Generator g(scen(3.6e6, 1.0, "seed = 4\nbias_m = 2.0\ngm_sigma_m = 3.0\ngm_tau_s = 600.0\n"));
    const Series s = collect(g, 1);
    std::vector<double> m;
    for (double x : s.e) m.push_back(x - bias);
    double var = 0;
    for (double x : m) var += x * x;
    var /= static_cast<double>(m.size());
    // sampling sd of the variance of an AR(1) sequence: sigma^2 sqrt(2 (1 + phi^2) / (1 - phi^2) / N) = 1.8 %
    CHECK(std::fabs(var / (sig * sig) - 1) < 0.08, "GM variance %.4f vs sigma^2 = %.1f (8%% = 4.4 sd)", var, sig * sig);
    // mean of an AR(1) sequence: sd sigma sqrt(2 tau / N) = 0.055 m
    CHECK(std::fabs(mean(m)) < 0.25, "GM mean %.4f m (bias removed), sd 0.055 m", mean(m));
    const double phi = std::exp(-1.0 / tau);
    CHECK(std::fabs(autocorr(m, 1) - phi) < 5e-4, "lag-1 autocorrelation %.6f vs exp(-T/tau) = %.6f", autocorr(m, 1), phi);
    CHECK(std::fabs(autocorr(m, 600) - std::exp(-1.0)) < 0.07, "lag-tau autocorrelation %.4f vs exp(-1) = %.4f",
          autocorr(m, 600), std::exp(-1.0));
    CHECK(std::fabs(autocorr(m, 1800) - std::exp(-3.0)) < 0.07, "lag-3tau autocorrelation %.4f vs exp(-3) = %.4f",
          autocorr(m, 1800), std::exp(-3.0));
    // stationary from the first sample: the first samples of many seeds have variance sigma^2
    double v0 = 0;
    const int n_seeds = 2000;
    for (int sd = 0; sd < n_seeds; ++sd) {
      Generator g0(scen(10.0, 1.0, "seed = " + std::to_string(sd + 100) + "\ngm_sigma_m = 3.0\n"));
      TruthState t;
      t.kin = g0.trajectory().at(0);
      const double e = g0.baro(0, t).error_m;
      v0 += e * e;
    }
    v0 /= n_seeds;
    CHECK(std::fabs(v0 / (sig * sig) - 1) < 0.15, "variance of the first sample over %d seeds %.3f (sd 3%%)", n_seeds, v0);
  }
  {  // white noise, 10 Hz steps with a 1 Hz barometer
    Generator g(scen(1.0e5, 10.0, "seed = 2\nnoise_sigma_m = 0.5\nrate_hz = 1.0\n"));
    const Series s = collect(g, 10);
    double var = 0;
    for (double x : s.e) var += x * x;
    var /= static_cast<double>(s.e.size());
    CHECK(s.due == 100001, "one sample every 10 steps (%d)", s.due);
    CHECK(std::fabs(std::sqrt(var) / 0.5 - 1) < 0.02, "noise sigma %.4f m vs 0.5 m (sd 0.2%%)", std::sqrt(var));
    CHECK(std::fabs(autocorr(s.e, 1)) < 0.015, "noise lag-1 autocorrelation %.4f (sd 0.003)", autocorr(s.e, 1));
  }
  {  // dropouts, outliers, NaN samples
    Generator g(scen(1.0e5, 1.0,
                     "seed = 3\ndropout_prob = 0.1\ndropouts = [[100.0, 200.0]]\noutlier_prob = 0.05\noutlier_m = 100.0\n"
                     "invalid_prob = 0.02\n"));
    const Series s = collect(g, 1);
    const double n = static_cast<double>(s.due);
    CHECK(std::fabs(s.dropped / n - (0.1 + 0.9 * 100 / n)) < 0.005, "dropped fraction %.4f", s.dropped / n);
    bool window = true;
    for (int64_t k = 100; k < 200; ++k) {
      TruthState t;
      t.t_s = g.time_of(k);
      t.kin = g.trajectory().at(t.t_s);
      window = window && g.baro(k, t).dropped;
    }
    CHECK(window, "every sample in the scheduled window [100, 200) s dropped");
    const double sent = n - s.dropped;
    CHECK(std::fabs(s.outliers / sent - 0.05) < 0.004, "outlier fraction %.4f (0.05)", s.outliers / sent);
    CHECK(std::fabs(s.invalid / sent - 0.02) < 0.003, "NaN fraction %.4f (0.02)", s.invalid / sent);
    int big = 0;
    for (double e : s.e) big += std::fabs(std::fabs(e) - 100.0) < 1e-9;
    CHECK(big > 0 && std::abs(big - s.outliers) <= s.outliers / 50 + 1, "outliers are +-100 m (%d of %d)", big, s.outliers);
  }
  {  // off by default, and frames carry the sample
    Generator g(scen(10.0, 10.0, "enable = false\n"));
    gg_frame_t f;
    g.frame(0, f);
    CHECK(f.baro_status == GG_SENSOR_ABSENT, "no [baro]: no samples");
    Generator g2(scen(10.0, 10.0, "bias_m = 5.0\n"));
    g2.frame(10, f);
    CHECK(f.baro_status == GG_SENSOR_OK && std::fabs(f.baro_alt_m - 5.0) < 1e-6 && f.baro_utime == 1000000,
          "frame 10 carries the 1 s sample: alt %.6f m, utime %lld", f.baro_alt_m, static_cast<long long>(f.baro_utime));
    g2.frame(11, f);
    CHECK(f.baro_status == GG_SENSOR_ABSENT, "frame 11: no new sample");
  }
  std::printf(g_fail ? "%d check(s) failed\n" : "baro: all checks passed\n", g_fail);
  return g_fail ? 1 : 0;
}
