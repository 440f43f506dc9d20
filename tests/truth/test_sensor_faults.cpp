// Sensor fault injection of the truth generator ([sensor_faults],
// sensor_faults.hpp): each kind changes exactly what it says, on exactly the
// steps it says, against the same generator without faults; intermittent
// faults are seeded and repeatable; bad tables are refused naming the key.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "ggins/truth/generator.hpp"

using namespace ggins::truth;

static int g_fail = 0;
#define CHECK(cond, ...)                         \
  do {                                           \
    if (!(cond)) {                               \
      std::printf("FAIL %s:%d: ", __FILE__, __LINE__); \
      std::printf(__VA_ARGS__);                  \
      std::printf("\n");                         \
      ++g_fail;                                  \
    }                                            \
  } while (0)

static const char* kBase = "name = \"t\"\n[time]\nduration_s = 100.0\nrate_hz = 100\n";

static Scenario with(const std::string& fault) {
  return parse_scenario(std::string(kBase) + "[sensor_faults]\nseed = 3\n[[sensor_faults.fault]]\n" + fault, "t", "test");
}

static long double reading(const gg_frame_t& f, int i, int j) {
  return static_cast<long double>(f.f[i][j]) + static_cast<long double>(f.f_lo[i][j]);
}

// every field but (sensor i, axis j) readings equal
static bool same_except(const gg_frame_t& a, const gg_frame_t& b, int i, int j) {
  for (int s = 0; s < GG_MAX_ACC; ++s)
    for (int x = 0; x < 3; ++x)
      if (!(s == i && x == j) && (a.f[s][x] != b.f[s][x] || a.f_lo[s][x] != b.f_lo[s][x])) return false;
  for (int s = 0; s < GG_MAX_ACC; ++s)
    if (a.acc_status[s] != b.acc_status[s]) return false;
  return a.utime == b.utime && a.seq == b.seq && a.n_acc == b.n_acc && a.baro_status == b.baro_status;
}

static void test_reading_faults() {
  const Generator clean(parse_scenario(kBase, "t", "test"));
  gg_frame_t c, f;
  // step: +size on 2x from 5 s (step 500), exactly (long double), nothing else
  {
    const Generator g(with("kind = \"step\"\nsensor = 2\naxis = \"x\"\nstart_s = 5.0\nsize = 1e-9\n"));
    for (int64_t k : {0, 499, 500, 501, 9000}) {
      clean.frame(k, c);
      g.frame(k, f);
      const long double d = reading(f, 1, 0) - reading(c, 1, 0);
      const long double want = k >= 500 ? 1e-9L : 0.0L;
      // the faulty reading is formed in long double: one ulp at 9.8 m/s^2 is 8.7e-19
      CHECK(std::fabs(d - want) < 1e-18L, "step k=%lld: %.6Le", static_cast<long long>(k), d);
      CHECK(same_except(c, f, 1, 0), "step k=%lld touched another field", static_cast<long long>(k));
    }
  }
  // drift: size per second from start_s, on 4z
  {
    const Generator g(with("kind = \"drift\"\nsensor = 4\naxis = \"z\"\nstart_s = 2.0\nsize = 1e-12\n"));
    for (int64_t k : {199, 200, 1200}) {
      clean.frame(k, c);
      g.frame(k, f);
      const long double d = reading(f, 3, 2) - reading(c, 3, 2);
      const long double want = k >= 200 ? 1e-12L * (static_cast<long double>(k - 200) * 0.01L) : 0.0L;
      CHECK(std::fabs(d - want) < 1e-18L, "drift k=%lld: %.6Le want %.6Le", static_cast<long long>(k), d, want);
    }
  }
  // stuck: 3z holds its value of step 300
  {
    const Generator g(with("kind = \"stuck\"\nsensor = 3\naxis = \"z\"\nstart_s = 3.0\n"));
    gg_frame_t c0;
    clean.frame(300, c0);
    for (int64_t k : {300, 301, 5000}) {
      clean.frame(k, c);
      g.frame(k, f);
      CHECK(f.f[2][2] == c0.f[2][2] && f.f_lo[2][2] == c0.f_lo[2][2], "stuck k=%lld", static_cast<long long>(k));
      CHECK(same_except(c, f, 2, 2), "stuck touched another field");
    }
    CHECK(c.f[2][2] != c0.f[2][2], "the true reading moves (else the test proves nothing)");
  }
  // NaN, Inf, range, saturate, status
  {
    Generator g(with("kind = \"nan\"\nsensor = 1\naxis = \"z\"\nstart_s = 1.0\n"));
    g.frame(100, f);
    CHECK(std::isnan(f.f[0][2]) && f.f_lo[0][2] == 0, "nan");
    g.frame(99, f);
    CHECK(std::isfinite(f.f[0][2]), "nan before start");
    Generator gi(with("kind = \"inf\"\nsensor = 1\naxis = \"x\"\nsize = -1\n"));
    gi.frame(0, f);
    CHECK(std::isinf(f.f[0][0]) && f.f[0][0] < 0, "-inf");
    Generator gr(with("kind = \"range\"\nsensor = 2\naxis = \"z\"\nsize = 1e3\n"));
    gr.frame(7, f);
    CHECK(f.f[1][2] == 1e3 && f.f_lo[1][2] == 0, "range");
    Generator gs(with("kind = \"status_bad\"\nsensor = 4\n"));
    gs.frame(7, f);
    clean.frame(7, c);
    CHECK(f.acc_status[3] == GG_SENSOR_BAD && f.f[3][0] == c.f[3][0], "status_bad");
  }
}

static void test_time_faults() {
  gg_frame_t f;
  const Generator j(with("kind = \"time_jump\"\nstart_s = 5.0\nduration_s = 0.02\nsize = 5000\n"));
  for (int64_t k : {499, 500, 501, 502}) {
    j.frame(k, f);
    const int64_t want = k * 10000 + ((k == 500 || k == 501) ? 5000 : 0);
    CHECK(f.utime == want && f.seq == k, "time_jump k=%lld utime %lld", static_cast<long long>(k),
          static_cast<long long>(f.utime));
  }
  const Generator r(with("kind = \"time_repeat\"\nstart_s = 5.0\nduration_s = 0.01\n"));
  r.frame(500, f);
  CHECK(f.utime == 499 * 10000 && f.seq == 500, "time_repeat");
  const Generator b(with("kind = \"time_back\"\nstart_s = 5.0\nduration_s = 0.01\nsize = 1000000\n"));
  b.frame(500, f);
  CHECK(f.utime == 500 * 10000 - 1000000, "time_back");
  b.frame(501, f);
  CHECK(f.utime == 501 * 10000, "time_back lasts one step");
}

static void test_intermittent() {
  const Generator g(with("kind = \"nan\"\nsensor = 3\naxis = \"x\"\nprob = 0.3\n"));
  const Generator g2(with("kind = \"nan\"\nsensor = 3\naxis = \"x\"\nprob = 0.3\n"));
  int n = 0, same = 0;
  const int N = 10000;
  gg_frame_t f, f2;
  for (int64_t k = 0; k < N; ++k) {
    g.frame(k, f);
    g2.frame(k, f2);
    n += std::isnan(f.f[2][0]) ? 1 : 0;
    same += std::isnan(f.f[2][0]) == std::isnan(f2.f[2][0]) ? 1 : 0;
  }
  // binomial: sigma = sqrt(N p (1-p)) = 46; 5 sigma
  CHECK(std::abs(n - 3000) < 230, "intermittent fraction %d / %d", n, N);
  CHECK(same == N, "seeded: the same steps every time");
}

static void expect_error(const std::string& fault, const std::string& needle) {
  try {
    with(fault);
    CHECK(false, "accepted: %s", fault.c_str());
  } catch (const std::runtime_error& e) {
    CHECK(std::string(e.what()).find(needle) != std::string::npos, "error '%s' does not name '%s'", e.what(),
          needle.c_str());
  }
}

static void test_parse_errors() {
  expect_error("kind = \"melt\"\nsensor = 1\naxis = \"x\"\n", "sensor_faults.fault[0].kind");
  expect_error("kind = \"step\"\naxis = \"x\"\n", "sensor_faults.fault[0].sensor");
  expect_error("kind = \"step\"\nsensor = 5\naxis = \"x\"\n", "sensor_faults.fault[0].sensor");
  expect_error("kind = \"step\"\nsensor = 1\naxis = \"y\"\n", "sensor_faults.fault[0].axis");
  expect_error("kind = \"step\"\nsensor = 1\naxis = \"x\"\nwhen = 3\n", "sensor_faults.fault[0].when");
  expect_error("kind = \"step\"\nsensor = 1\naxis = \"x\"\nprob = 0\n", "sensor_faults.fault[0].prob");
  expect_error("kind = \"time_jump\"\nsize = 0.5\n", "sensor_faults.fault[0].size");
  expect_error("kind = \"range\"\nsensor = 1\naxis = \"x\"\n", "sensor_faults.fault[0].size");
  expect_error("kind = \"step\"\nsensor = 1\naxis = \"x\"\nstart_s = -1\n", "start_s");
}

int main() {
  test_reading_faults();
  test_time_faults();
  test_intermittent();
  test_parse_errors();
  std::printf("%s (%d failures)\n", g_fail ? "FAILED" : "all sensor-fault checks passed", g_fail);
  return g_fail ? 1 : 0;
}
