// The 3-D GAMMA_ASYM threshold ([firmware] asym_max_ps2, derived_asym_max_ps2 in
// scenario3d.hpp) against the noise propagation worked out here, independently of the code:
//  * its value for Gao et al.'s sensors (gyro 2.909e-6 rad/s per 10 ms sample, accelerometers
//    5.5e-10 m/s^2, 0.5 m half-baselines, 100 Hz): 7 sqrt(530)/6 sigma_g / h + 1e-6 (the
//    third-order difference's weights 11, -18, 9, -2 over 6h), how it scales with the gyro
//    noise and the step, a stabilized platform (no gyro term), a fixed accelerometer bias,
//    a key the scenario gives (wins, and is written back), a noise too large (refused);
//  * the firmware in process on that scenario (truth3d Generator3 -> gg_nav3d_step, as
//    ggins run3d --direct): the measured spread of the strapdown residuals p_x..p_z matches
//    sqrt(530)/6 sigma_g / h, no GAMMA_ASYM on any step with the derived threshold, and the
//    former fixed 1e-6 flags nearly every step (the false alarm this threshold removes).
#include <cmath>
#include <cstdio>
#include <string>

#include "checks.hpp"
#include "ggins/truth3d/config3d.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

using namespace ggins;
using namespace ggins::truth3d;
using ggins_test::check;
using ggins_test::g_fail;

namespace {

const std::string kHead = R"(
[trajectory]
type = "route"
lat_deg = 45.0
lon_deg = 10.0
height_m = 3000.0
speed_mps = 150.0
turn_rate_dps = 3.0
[[trajectory.waypoint]]
lat_deg = 45.0
lon_deg = 10.05
[[trajectory.waypoint]]
lat_deg = 45.05
lon_deg = 10.1
[time]
duration_s = 60.0
)";

std::string scen(const std::string& platform, double sg, double sa, double rate, const std::string& extra = "") {
  char b[512];
  std::snprintf(b, sizeof b,
                "[platform]\nkind = \"%s\"\na_m = 0.5\nb_m = 0.5\nc_m = 0.5\n[accel]\nnoise_sigma_mps2 = %.17g\n"
                "[gyro]\nnoise_sigma_radps = %.17g\n",
                platform.c_str(), sa, sg);
  std::string t = kHead + b + extra;
  const std::string r = "rate_hz = " + std::to_string(rate) + "\n";
  t.insert(t.find("duration_s"), r);
  return t;
}

// the analysis: gyro-derived w' noise, accelerometer part of p_x..p_z and of the trace (d = 0.5 m)
double expected(bool strapdown, double sg, double sa, double rate, double fixed = 0) {
  const double h = 1.0 / rate, d2 = 0.25;
  const double wd = std::sqrt(121.0 + 324.0 + 81.0 + 4.0) / 6.0 * sg / h;
  const double acc = sa * sa * (2.0 / d2) / 8.0, acc_tr = sa * sa * (3.0 / d2) / 2.0;
  double s = std::sqrt(std::max(acc, acc_tr));
  if (strapdown) s = std::max({s, std::sqrt(wd * wd + acc), std::sqrt(16.0 * 100.0 * sg * sg + acc_tr)});
  return 7.0 * s + fixed + 1e-6;
}

bool rel(double a, double b, double tol) { return std::fabs(a - b) <= tol * std::fabs(b); }

std::string num(double x) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", x);
  return b;
}

}  // namespace

int main() {
  const double sg = 2.909e-6, sa = 5.5e-10;
  // ---------------- the derived value
  const Scenario3 gao = parse_scenario3(scen("strapdown", sg, sa, 100), "gao", "test");
  const double t_gao = gao.firmware.asym_max_ps2, e_gao = expected(true, sg, sa, 100);
  check(!gao.firmware.asym_max_set && rel(t_gao, e_gao, 1e-12),
        "Gao's sensors, 100 Hz: asym_max " + num(t_gao) + " s^-2 = 7 x 3.837 sigma_g / h + 1e-6 = " + num(e_gao));
  check(rel(t_gao, 7.0 * 3.8370 * sg / 0.01 + 1e-6, 1e-4), "  the gyro noise's gain 3.837 / h (7.814e-3 s^-2)");
  const Scenario3 g10 = parse_scenario3(scen("strapdown", 10 * sg, sa, 100), "g10", "test");
  check(rel(g10.firmware.asym_max_ps2 - 1e-6, 10 * (t_gao - 1e-6), 1e-9), "  ten times the gyro noise: ten times the noise term");
  const Scenario3 r50 = parse_scenario3(scen("strapdown", sg, sa, 50), "r50", "test");
  check(rel(r50.firmware.asym_max_ps2, expected(true, sg, sa, 50), 1e-12) &&
            rel(r50.firmware.asym_max_ps2 - 1e-6, 0.5 * (t_gao - 1e-6), 1e-9),
        "  50 Hz: half the noise term (sigma_g / h), " + num(r50.firmware.asym_max_ps2));
  const Scenario3 exact = parse_scenario3(scen("strapdown", 0, 0, 100), "exact", "test");
  check(exact.firmware.asym_max_ps2 == kAsymFloorPs2, "  exact sensors: the floor 1e-6 (the former fixed default)");
  const Scenario3 stab = parse_scenario3(scen("stabilized", sg, sa, 100), "stab", "test");
  check(rel(stab.firmware.asym_max_ps2, expected(false, sg, sa, 100), 1e-12) && stab.firmware.asym_max_ps2 < 1.01e-6,
        "  stabilized (gyros unused): accelerometer terms only, " + num(stab.firmware.asym_max_ps2));
  // a fixed bias on sensor 1 (at +b on y), axis z: M[2][1] by 1e-4 / (2b), p_x by half that
  {
    std::string t = scen("stabilized", 0, 0, 100);
    t.insert(t.find("[gyro]"), "bias_mps2 = [[0,0,0],[0,0,1e-4],[0,0,0],[0,0,0],[0,0,0],[0,0,0]]\n");
    const Scenario3 f = parse_scenario3(t, "fixed", "test");
    check(rel(f.firmware.asym_max_ps2, 1e-6 + 0.5 * 1e-4 / (2 * 0.5), 1e-12),
          "  a fixed 1e-4 m/s^2 bias on 1z: + 1e-4 / (4b) = 5e-5, " + num(f.firmware.asym_max_ps2));
  }
  {
    const Scenario3 g = parse_scenario3(scen("strapdown", sg, sa, 100) + "[firmware]\nasym_max_ps2 = 3e-3\n", "given", "test");
    const std::string toml = scenario3_to_toml(g);
    const std::string toml_gao = scenario3_to_toml(gao);
    check(g.firmware.asym_max_set && g.firmware.asym_max_ps2 == 3e-3 && toml.find("asym_max_ps2 = 0.003") != std::string::npos &&
              toml_gao.find("asym_max_ps2 =") == std::string::npos,
          "a given asym_max_ps2 wins and is written back; a derived one is not");
  }
  {
    std::string err;
    try {
      parse_scenario3(scen("strapdown", 1e-3, sa, 100), "big", "test");
    } catch (const std::exception& e) {
      err = e.what();
    }
    check(err.find("asym_max_ps2") != std::string::npos && err.find("exceeds") != std::string::npos,
          "gyro noise 1e-3 rad/s at 100 Hz (threshold 2.7 s^-2 > GG_LIM_ASYM_MAX): refused, naming the key");
  }

  // ---------------- the firmware on the flight
  for (int former = 0; former < 2; ++former) {
    Scenario3 sc = gao;
    if (former) {
      sc.firmware.asym_max_ps2 = 1e-6;
      sc.firmware.asym_max_set = true;
    }
    const Generator3 gen(sc);
    const gg_nav3d_config_t cfg = config3d(sc, gen);
    static gg_nav3d_t nav;
    if (gg_nav3d_init(&nav, &cfg) != GG_OK) {
      check(false, "gg_nav3d_init");
      continue;
    }
    int64_t flagged = 0, other = 0, n = 0;
    double ss = 0, worst = 0, tr_max = 0;
    const double S = std::sqrt(530.0) / 6.0 * sg / 0.01;
    for (int64_t k = 0; k < gen.n_steps(); ++k) {
      gg_frame_t f;
      gen.frame(k, f, nullptr);
      gg_nav3d_output_t o;
      (void)gg_nav3d_step(&nav, &f, nullptr, &o);
      if (o.health & GG_HEALTH_GAMMA_ASYM) ++flagged;
      if (o.health & ~static_cast<uint32_t>(GG_HEALTH_GAMMA_ASYM)) ++other;
      if (k >= 3) {
        for (int j = 0; j < 3; ++j) {
          ss += o.parity[j] * o.parity[j];
          worst = std::max(worst, std::fabs(o.parity[j]));
        }
        n += 3;
        tr_max = std::max(tr_max, std::fabs(o.parity[3]));
      }
    }
    const int64_t steps = gen.n_steps();
    if (!former) {
      // sd estimate of this MA(3) noise (lag correlations -0.713, 0.255, -0.042): relative sd
      // sqrt((1 + 2 sum rho^2) / (2n)) = 0.77% at n = 18000; 5 of them allowed
      const double ratio = std::sqrt(ss / static_cast<double>(n));
      const double tol = 5.0 * std::sqrt(2.15 / (2.0 * static_cast<double>(n)));
      check(std::fabs(ratio / S - 1.0) < tol,
            "60 s strapdown flight with turns, Gao's noise: sd of p_x..p_z " + num(ratio) + " rad/s^2 = " +
                num(ratio / S) + " x sqrt(530)/6 sigma_g / h (" + num(S) + ", within " + num(tol) + ")");
      check(flagged == 0 && other == 0,
            "  derived asym_max " + num(sc.firmware.asym_max_ps2) + ": GAMMA_ASYM on " + std::to_string(flagged) + " of " +
                std::to_string(steps) + " steps, other bits on " + std::to_string(other) + " (largest |p_j| " +
                num(worst) + " = " + num(worst / S) + " sigma, |trace| " + num(tr_max) + " s^-2)");
    } else {
      check(flagged >= steps - 3 - steps / 100,
            "  the former fixed 1e-6: GAMMA_ASYM on " + std::to_string(flagged) + " of " + std::to_string(steps) +
                " steps (the false alarm)");
    }
  }
  std::printf("%s\n", g_fail ? "FAILED" : "all passed");
  return g_fail ? 1 : 0;
}
