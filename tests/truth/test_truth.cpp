// Unit tests of the truth generator (host_tools/lib/truth): trajectory consistency,
// sensor readings against the field, error model, scenarios. Independent
// checks: finite differences of the trajectory, the closed-form point-mass
// gradient, sample statistics of the counter-based generator.
#include <cmath>
#include <cstdio>
#include <string>

#include "ggins/truth/generator.hpp"

using namespace ggins::truth;

static int g_fail = 0;
#define CHECK(cond, ...)                         \
  do {                                           \
    if (!(cond)) {                               \
      ++g_fail;                                  \
      std::printf("FAIL %s:%d: ", __FILE__, __LINE__); \
      std::printf(__VA_ARGS__);                  \
      std::printf("\n");                         \
    }                                            \
  } while (0)

static Scenario scen(const std::string& extra = "") {
  return parse_scenario("name = \"t\"\n" + extra, "t", "test");
}

// v = dr/dt and a = dv/dt by central differences (long double), and the
// closed form of docs/design.md at t = 0.
static void test_trajectory() {
  NorthFlight nf(300.0L, 1000.0L, 0.3L, 6378137.0L);
  const Real t = 1234.5L, h = 1e-2L;
  const Kinematics k = nf.at(t), kp = nf.at(t + h), km = nf.at(t - h);
  const Vec3 v_fd = (kp.r - km.r) / (2 * h), a_fd = (kp.v - km.v) / (2 * h);
  CHECK((v_fd - k.v).norm() < 1e-9L, "v != dr/dt: %Lg", (v_fd - k.v).norm());
  CHECK((a_fd - k.a).norm() < 1e-9L, "a != dv/dt: %Lg", (a_fd - k.a).norm());
  CHECK(std::fabs(k.v.norm() - 300.0L) < 1e-12L, "speed %Lg", k.v.norm());
  CHECK(std::fabs(k.r.norm() - 6379137.0L) < 1e-8L, "radius %Lg", k.r.norm());
  const Kinematics k0 = nf.at(0);
  CHECK(std::fabs(k0.r(0) - 6379137.0L * std::cos(0.3L)) < 1e-8L && k0.r(1) == 0, "r(0)");
  CHECK(std::fabs(k0.v(0) + 300.0L * std::sin(0.3L)) < 1e-12L, "v(0)");
}

// Readings f_i = a - G(r + d_i): the differenced readings give the gradient
// (to second order in the baseline), the mean gives the centre specific force,
// and the 2-D layout matches the paper's sensors 1..4.
static void test_frame_geometry() {
  const Scenario s = scen("[platform]\na_m = 0.5\nb_m = 0.5\n[time]\nduration_s = 10\n");
  Generator g(s);
  gg_frame_t f;
  TruthState t;
  g.frame(500, f, &t);
  CHECK(f.seq == 500 && f.utime == 500 * 10000, "seq/utime %lld %lld", (long long)f.seq, (long long)f.utime);
  CHECK(f.n_acc == 4 && f.acc_status[0] == GG_SENSOR_OK && f.acc_status[4] == GG_SENSOR_ABSENT, "status");
  auto rd = [&](int i, int j) { return (Real)f.f[i][j] + (Real)f.f_lo[i][j]; };
  // closed-form point-mass gradient at the centre
  const Real r = t.kin.r.norm();
  const Vec3 u = t.kin.r / r;
  const Real w2 = 3.986004418e14L / (r * r * r);
  const Real gxx = w2 * (3 * u(0) * u(0) - 1), gxz = w2 * 3 * u(0) * u(2), gzz = w2 * (3 * u(2) * u(2) - 1);
  const Real a = 0.5L, b = 0.5L;
  // Gxx = (f3x - f1x)/2a, Gxz = (f4x - f2x)/2b, Gzx = (f3z - f1z)/2a, Gzz = (f4z - f2z)/2b (docs/design.md)
  const Real m_xx = (rd(2, 0) - rd(0, 0)) / (2 * a), m_xz = (rd(3, 0) - rd(1, 0)) / (2 * b);
  const Real m_zx = (rd(2, 2) - rd(0, 2)) / (2 * a), m_zz = (rd(3, 2) - rd(1, 2)) / (2 * b);
  // baseline truncation ~ Gamma * (a/r)^2 ~ 1e-20 s^-2; rounding of hi+lo ~ 1e-22
  CHECK(std::fabs(m_xx - gxx) < 1e-18L, "Gxx %Lg vs %Lg", m_xx, gxx);
  CHECK(std::fabs(m_xz - gxz) < 1e-18L, "Gxz %Lg vs %Lg", m_xz, gxz);
  CHECK(std::fabs(m_zx - gxz) < 1e-18L, "Gzx %Lg vs %Lg", m_zx, gxz);
  CHECK(std::fabs(m_zz - gzz) < 1e-18L, "Gzz %Lg vs %Lg", m_zz, gzz);
  for (int j : {0, 2}) {
    const Real mean = (rd(0, j) + rd(1, j) + rd(2, j) + rd(3, j)) / 4;
    // symmetric pairs cancel the first order; the second order is ~ (a^2/2) d2G/dx2 ~ 1e-13
    CHECK(std::fabs(mean - t.f_c(j)) < 1e-12L, "centre f axis %d: %.3Le", j, mean - t.f_c(j));
  }
  for (int i = 0; i < 4; ++i) CHECK(f.f[i][1] == 0 && f.f_lo[i][1] == 0, "y axis reads 0");
  // f_lo is the residual below double resolution
  for (int i = 0; i < 4; ++i)
    for (int j : {0, 2}) CHECK(std::fabs(f.f_lo[i][j]) <= 0.5 * std::nextafter(std::fabs(f.f[i][j]), 1e9) - 0.5 * std::fabs(f.f[i][j]) + 1e-30,
                               "f_lo within half an ulp");
}

// Errors: fixed bias and scale add exactly; random biases are seeded,
// reproducible and have the requested spread; noise is white and zero mean.
static void test_errors() {
  const Scenario s0 = scen("[time]\nduration_s = 1\n");
  const Scenario s1 = scen("[time]\nduration_s = 1\n[accel]\nbias_mps2 = [[1e-9, 0, 0], [0, 0, -2e-9]]\nscale = [[0, 0, 1e-6]]\n");
  Generator g0(s0), g1(s1);
  gg_frame_t f0, f1;
  g0.frame(7, f0);
  g1.frame(7, f1);
  // long double resolution at 9.8 m/s^2 is ~1e-18
  auto rd = [](const gg_frame_t& f, int i, int j) { return (Real)f.f[i][j] + (Real)f.f_lo[i][j]; };
  CHECK(std::fabs(rd(f1, 0, 0) - rd(f0, 0, 0) - 1e-9L) < 1e-17L, "fixed bias s1 x");
  CHECK(std::fabs(rd(f1, 1, 2) - rd(f0, 1, 2) + 2e-9L) < 1e-17L, "fixed bias s2 z");
  CHECK(std::fabs(rd(f1, 0, 2) - rd(f0, 0, 2) * (1 + 1e-6L)) < 1e-17L, "scale s1 z");
  CHECK(rd(f1, 2, 0) == rd(f0, 2, 0), "other axes untouched");

  // random constant biases: 8 axes per seed; over many seeds the spread is sigma
  double sum2 = 0;
  int n = 0;
  for (uint64_t seed = 1; seed <= 500; ++seed) {
    Scenario s = scen("[accel]\nbias_sigma_mps2 = 2e-12\nseed = " + std::to_string(seed) + "\n");
    Generator g(s);
    for (int i = 0; i < 4; ++i) {
      CHECK(g.bias(i, 1) == 0, "no bias on the unmeasured y axis");
      for (int j : {0, 2}) {
        sum2 += g.bias(i, j) * g.bias(i, j);
        ++n;
      }
    }
  }
  const double sd = std::sqrt(sum2 / n);  // n = 4000: relative std error ~1.1%
  CHECK(std::fabs(sd / 2e-12 - 1) < 0.05, "bias sigma %g (want 2e-12)", sd);
  Scenario sa = scen("[accel]\nbias_sigma_mps2 = 2e-12\nseed = 3\n");
  Generator ga(sa), gb(sa);
  CHECK(ga.bias(2, 2) == gb.bias(2, 2) && ga.bias(2, 2) != 0, "biases reproducible from the seed");

  // white noise: frame k is the same however often it is generated; mean ~0, sigma ~1e-10
  Scenario sn = scen("[time]\nduration_s = 100\n[accel]\nnoise_sigma_mps2 = 1e-10\n");
  Generator gn(sn), gc(scen("[time]\nduration_s = 100\n"));
  double m = 0, m2 = 0, lag = 0, prev = 0;
  const int N = 4000;
  for (int k = 0; k < N; ++k) {
    gg_frame_t a, c;
    gn.frame(k, a);
    gc.frame(k, c);
    const double e = (double)(rd(a, 3, 0) - rd(c, 3, 0));
    m += e;
    m2 += e * e;
    lag += e * prev;
    prev = e;
  }
  m /= N;
  const double sdn = std::sqrt(m2 / N - m * m);
  CHECK(std::fabs(sdn / 1e-10 - 1) < 0.05, "noise sigma %g", sdn);
  CHECK(std::fabs(m) < 4 * 1e-10 / std::sqrt(N), "noise mean %g", m);
  CHECK(std::fabs(lag / N) < 4 * 1e-20 / std::sqrt(N), "noise lag-1 correlation %g", lag / N);
  gg_frame_t x1, x2;
  gn.frame(1234, x1);
  gn.frame(1234, x2);
  CHECK(x1.f[0][0] == x2.f[0][0] && x1.f_lo[0][0] == x2.f_lo[0][0], "frame k reproducible");
}

static void test_scenarios() {
  for (const auto& n : builtin_scenario_names()) {
    const Scenario s = load_scenario(n, {});
    CHECK(s.name == n, "built-in %s named %s", n.c_str(), s.name.c_str());
  }
  const Scenario p = load_scenario("welker-perfect", {});
  CHECK(p.trajectory.speed_mps == 300 && p.duration_s == 3600 && p.rate_hz == 100 && p.a_m == 0.5 && p.b_m == 0.5 &&
            p.trajectory.lat0_deg == 0 && p.accel.bias_sigma_mps2 == 0,
        "welker-perfect parameters");
  CHECK(p.n_steps() == 360001 && p.dt_us() == 10000, "360001 steps of 10 ms");
  const Scenario t1 = load_scenario("welker-table1", {});
  CHECK(t1.accel.bias_sigma_mps2 == 2e-12, "welker-table1 sigma");
  auto throws = [](const std::string& text, const std::string& what) {
    try {
      parse_scenario(text, "x", "test");
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).find(what) != std::string::npos;
    }
    return false;
  };
  CHECK(throws("[accel]\nbias = 1\n", "unknown key 'accel.bias'"), "unknown key");
  CHECK(throws("[platform]\na_m = 0\n", "a_m"), "zero baseline");
  CHECK(throws("[time]\nrate_hz = 7\n", "integer number of microseconds"), "non-integer step");
  CHECK(throws("[accel]\nnoise_sigma_mps2 = \"x\"\n", "must be a number"), "type error");
  CHECK(throws("[transport]\ndrop_prob = 1.5\n", "drop_prob"), "probability range");
  CHECK(throws("[gravity]\nmodel = \"egm2008\"\n", "unknown"), "unknown model");
  bool threw = false;
  try {
    load_scenario("nope-nope", {});
  } catch (const std::runtime_error& e) {
    threw = std::string(e.what()).find("welker-perfect") != std::string::npos;
  }
  CHECK(threw, "unknown scenario lists the built-ins");
}

int main() {
  test_trajectory();
  test_frame_geometry();
  test_errors();
  test_scenarios();
  if (g_fail) {
    std::printf("%d check(s) failed\n", g_fail);
    return 1;
  }
  std::printf("truth: all checks passed\n");
  return 0;
}
