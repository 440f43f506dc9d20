// The Monte Carlo draw of a 3-D scenario ([draw], scenario3d.hpp), against
// independent truth:
//  * the statistics of the draw over many seeds: gaussian values have mean 0
//    and the stated sigma (inside the sampling bands of N draws), "sign" values
//    are exactly +-the stated value with either sign half the time, and the
//    quantities and axes are uncorrelated;
//  * the draw reaches the sensors and the initial state as a fixed error
//    would: every reading of the six accelerometers moves by the common bias
//    (difference of the frames with and without the draw), the gyro by its
//    bias, the initial position and velocity by a vector of the drawn length;
//  * an inactive draw changes nothing and is not written; bad values are
//    refused with the key's name.
#include <cmath>
#include <cstdio>
#include <string>

#include "ggins/truth3d/config3d.hpp"
#include "checks.hpp"

using namespace ggins;
using namespace ggins::truth3d;

namespace {

using ggins_test::check;
using ggins_test::g_fail;

const std::string kBase = R"(
[trajectory]
type = "route"
lat_deg = 45.0
lon_deg = 10.0
height_m = 3000.0
speed_mps = 150.0
[[trajectory.waypoint]]
lat_deg = 45.0
lon_deg = 11.0
[platform]
kind = "strapdown"
[time]
duration_s = 2.0
rate_hz = 100.0
[accel]
noise_sigma_mps2 = 1e-9
[gyro]
noise_sigma_radps = 1e-9
)";

const std::string kDraw = R"(
[draw]
seed = 17
bias = "sign"
accel_common_bias_mps2 = [1e-4, 2e-4, 3e-4]
gyro_bias_radps = [4.85e-8, 4.85e-8, 9.7e-8]
position_ned_m = [10.0, 20.0, 30.0]
velocity_ned_mps = [1.0, 1.0, 0.5]
attitude_ned_rad = [0.001, 0.002, 0.003]
)";

std::string parse_error(const std::string& text) {
  try {
    parse_scenario3(text, "t", "test");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

std::string sci(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2e", x);
  return b;
}

long double reading(const gg_frame_t& f, int s, int j) {
  return static_cast<long double>(f.f[s][j]) + static_cast<long double>(f.f_lo[s][j]);
}

void test_statistics() {
  constexpr int kN = 4000;
  Draw3 d;
  d.accel_common_bias_mps2 = {1.0, 2.0, 3.0};
  d.gyro_bias_radps = {1.0, 1.0, 1.0};
  d.position_ned_m = {1.0, 1.0, 1.0};
  d.velocity_ned_mps = {1.0, 1.0, 1.0};
  d.attitude_ned_rad = {0.01, 0.01, 0.01};
  // gaussian: 15 quantities (5 x 3 axes), each standardised by its sigma
  double sum[15] = {}, sum2[15] = {}, cross = 0;
  for (int i = 0; i < kN; ++i) {
    d.seed = static_cast<uint64_t>(1000 + i);
    const DrawnErrors3 e = draw_errors(d);
    double z[15];
    for (size_t j = 0; j < 3; ++j) {
      z[j] = e.accel_common_bias_mps2[j] / d.accel_common_bias_mps2[j];
      z[3 + j] = e.gyro_bias_radps[j] / d.gyro_bias_radps[j];
      z[6 + j] = e.position_ned_m[j] / d.position_ned_m[j];
      z[9 + j] = e.velocity_ned_mps[j] / d.velocity_ned_mps[j];
      z[12 + j] = e.attitude_ned_rad[j] / d.attitude_ned_rad[j];
    }
    for (int q = 0; q < 15; ++q) {
      sum[q] += z[q];
      sum2[q] += z[q] * z[q];
    }
    cross += z[0] * z[6] + z[3] * z[4] + z[9] * z[12];  // across quantities and axes
  }
  bool mean_ok = true, var_ok = true;
  for (int q = 0; q < 15; ++q) {
    const double m = sum[q] / kN, v = sum2[q] / kN;
    mean_ok = mean_ok && std::fabs(m) < 4.0 / std::sqrt(double(kN));  // 4 sigma of a mean of N
    var_ok = var_ok && std::fabs(v - 1.0) < 4.0 * std::sqrt(2.0 / kN);  // 4 sigma of a mean square of N
  }
  check(mean_ok, "gaussian draw: the mean of 4000 draws of each of 15 values is 0 within 4 sigma/sqrt(N)");
  check(var_ok, "gaussian draw: the mean square of each is its sigma^2 within 4 sigma (sqrt(2/N))");
  check(std::fabs(cross / (3.0 * kN)) < 4.0 / std::sqrt(3.0 * kN), "gaussian draw: values of different quantities uncorrelated");

  // sign: exactly +-value, positive half the time
  d.bias = "sign";
  int pos = 0, n = 0;
  bool exact = true;
  for (int i = 0; i < kN; ++i) {
    d.seed = static_cast<uint64_t>(i);
    const DrawnErrors3 e = draw_errors(d);
    for (size_t j = 0; j < 3; ++j) {
      exact = exact && std::fabs(e.accel_common_bias_mps2[j]) == d.accel_common_bias_mps2[j] &&
              std::fabs(e.gyro_bias_radps[j]) == d.gyro_bias_radps[j];
      pos += (e.accel_common_bias_mps2[j] > 0) + (e.gyro_bias_radps[j] > 0);
      n += 2;
    }
  }
  check(exact, "sign draw: every bias is exactly +- its value");
  check(std::fabs(pos - 0.5 * n) < 4.0 * std::sqrt(0.25 * n), "sign draw: positive in half the draws (binomial, 4 sigma)");

  Draw3 none;
  none.seed = 5;
  const DrawnErrors3 z = draw_errors(none);
  check(!none.active() && z.position_ned_m[0] == 0 && z.accel_common_bias_mps2[2] == 0, "inactive draw: all zero");
}

void test_flown() {
  const Scenario3 a = parse_scenario3(kBase, "plain", "test");
  const Scenario3 b = parse_scenario3(kBase + kDraw, "drawn", "test");
  const DrawnErrors3 e = draw_errors(b.draw);
  const Generator3 ga(a), gb(b);
  // the readings: f_meas = f + b + n with the same noise draws; their difference is the common bias
  // (long double readings round at ~2e-18 m/s^2, the gyro's double at ~1e-16 of a 1e-2 rad/s rate)
  double worst_f = 0, worst_w = 0;
  for (int64_t k = 0; k < ga.n_steps(); k += 37) {
    gg_frame_t fa, fb;
    Truth3 ta, tb;
    ga.frame(k, fa, &ta);
    gb.frame(k, fb, &tb);
    for (int s = 0; s < 6; ++s)
      for (int j = 0; j < 3; ++j)
        worst_f = std::fmax(worst_f, std::fabs(static_cast<double>(reading(fb, s, j) - reading(fa, s, j)) -
                                               e.accel_common_bias_mps2[size_t(j)]));
    for (int j = 0; j < 3; ++j)
      worst_w = std::fmax(worst_w, std::fabs((fb.omega_b[j] - fa.omega_b[j]) - e.gyro_bias_radps[size_t(j)]));
  }
  check(worst_f < 1e-15, "every reading of the six accelerometers moves by the drawn common bias (worst " +
                             sci(worst_f) + " m/s^2)");
  check(worst_w < 1e-15, "the gyro readings move by the drawn gyro bias (worst " + sci(worst_w) + " rad/s)");
  const gg_nav3d_config_t ca = config3d(a, ga), cb = config3d(b, gb);
  double dr = 0, dv = 0;
  for (int i = 0; i < 3; ++i) {
    dr += double((ca.r0_e[i] - cb.r0_e[i]) * (ca.r0_e[i] - cb.r0_e[i]));
    dv += double((ca.v0_e[i] - cb.v0_e[i]) * (ca.v0_e[i] - cb.v0_e[i]));
  }
  auto norm = [](const std::array<double, 3>& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); };
  check(std::fabs(std::sqrt(dr) - norm(e.position_ned_m)) < 1e-6, "the initial position is off by the drawn error's length");
  check(std::fabs(std::sqrt(dv) - norm(e.velocity_ned_mps)) < 1e-9, "the initial velocity is off by the drawn error's length");
  // attitude: the angle between the two initial quaternions is the drawn rotation's
  long double dot = 0;
  for (int i = 0; i < 4; ++i) dot += ca.q0_b_e[i] * cb.q0_b_e[i];
  const double angle = 2.0 * std::acos(std::fmin(1.0, std::fabs(static_cast<double>(dot))));
  check(std::fabs(angle - norm(e.attitude_ned_rad)) < 1e-9, "the initial attitude is off by the drawn rotation's angle");
  check(e.position_ned_m[0] != 0 && e.position_ned_m[0] != b.draw.position_ned_m[0], "the initial errors are drawn, not the sigmas");

  // as flown: the [draw] table is written and reads back to the same draw
  const Scenario3 c = parse_scenario3(scenario3_to_toml(b), "again", "test");
  const DrawnErrors3 e2 = draw_errors(c.draw);
  check(e2.gyro_bias_radps == e.gyro_bias_radps && e2.position_ned_m == e.position_ned_m,
        "the scenario as flown keeps the [draw] table and flies the same draw");
  check(scenario3_to_toml(a).find("[draw]") == std::string::npos, "a scenario without a draw writes no [draw] table");
}

void test_refused() {
  const std::string e1 = parse_error(kBase + "[draw]\nbias = \"uniform\"\n");
  check(e1.find("draw.bias") != std::string::npos, "bias = \"uniform\" refused, naming draw.bias: " + e1);
  const std::string e2 = parse_error(kBase + "[draw]\nposition_ned_m = [-1.0, 0.0, 0.0]\n");
  check(e2.find("draw.position_ned_m") != std::string::npos, "a negative sigma refused: " + e2);
  const std::string e3 = parse_error(kBase + "[draw]\nattitude_ned_rad = [0.2, 0.0, 0.0]\n");
  check(e3.find("draw.attitude_ned_rad") != std::string::npos, "an attitude sigma beyond 0.1 rad refused: " + e3);
  const std::string e4 = parse_error(kBase + "[draw]\nspeed = 1.0\n");
  check(e4.find("speed") != std::string::npos, "an unknown key refused: " + e4);
}

}  // namespace

int main() {
  test_statistics();
  test_flown();
  test_refused();
  std::printf("%s\n", g_fail ? "FAILED" : "all passed");
  return g_fail ? 1 : 0;
}
