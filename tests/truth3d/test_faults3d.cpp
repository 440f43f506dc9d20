// Sensor faults in 3-D scenarios (host_tools/lib/truth3d faults3d.hpp):
//  * each kind changes exactly the reading it names, by what it says, against
//    the same scenario without faults (frames are pure functions of k);
//  * the parser's errors name the key and its line;
//  * the firmware (gg_nav3d_step, fdi3d.h) in process, as ggins run3d --direct
//    steps it: a 1e-8 m/s^2 bias on one accelerometer axis is flagged at once
//    and that reading, and only it, excluded, the navigation staying with the
//    clean run's; a NaN pair (both readings of one axis of a pair) for 1.5 s
//    is bridged and the task navigates on after it.
#include <cmath>
#include <cstdio>
#include <string>

#include "compare3d.hpp"
#include "ggins/truth3d/config3d.hpp"
#include "checks.hpp"

using namespace ggins;
using namespace ggins::truth3d;

namespace {

using ggins_test::check;
using ggins_test::g_fail;

// Short straight-and-level strapdown flight (a route leg): 45 N eastbound, 150 m/s.
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
duration_s = 30.0
rate_hz = 100.0
[baro]
enable = true
)";

// readings are hi + lo (about 106 bits); as long double (64 bits) they round at
// 1.1e-19 relative: 2e-18 m/s^2 for |f| < 10 m/s^2
constexpr double kExact = 2e-18;

long double reading(const gg_frame_t& f, int s, int j) {
  return static_cast<long double>(f.f[s][j]) + static_cast<long double>(f.f_lo[s][j]);
}

std::string parse_error(const std::string& text) {
  try {
    parse_scenario3(text, "t", "test");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

struct Run {
  int64_t rejected = 0, first_flag = -1, last_nonfinite = -1;
  uint32_t health_or = 0, excluded = 0;
  double dr_final = 0, dr_max = 0;
};
Run fly(const Scenario3& sc, int64_t fault_step, uint32_t flag) {
  const Generator3 gen(sc);
  const gg_nav3d_config_t cfg = config3d(sc, gen);
  static gg_nav3d_t nav;
  Run r;
  if (gg_nav3d_init(&nav, &cfg) != GG_OK) {
    check(false, "gg_nav3d_init");
    return r;
  }
  for (int64_t k = 0; k < gen.n_steps(); ++k) {
    gg_frame_t f;
    Truth3 t;
    gen.frame(k, f, &t);
    gg_nav3d_output_t o;
    if (gg_nav3d_step(&nav, &f, nullptr, &o) != GG_OK) ++r.rejected;
    r.health_or |= o.health;
    if (k >= fault_step && r.first_flag < 0 && (o.health & flag)) r.first_flag = k - fault_step;
    if (o.health & GG_HEALTH_ACC_NONFINITE) r.last_nonfinite = k;
    r.excluded = o.acc_excluded;
    const run3d::Errors3 e = run3d::compare(t, o);
    r.dr_final = static_cast<double>(e.dr);
    r.dr_max = std::max(r.dr_max, r.dr_final);
  }
  return r;
}

}  // namespace

int main() {
  // ---------------- every kind against the clean frames
  {
    const std::string faults = R"(
[sensor_faults]
seed = 7
[[sensor_faults.fault]]
kind = "step"
sensor = 1
axis = "x"
start_s = 1.0
size = 1e-8
[[sensor_faults.fault]]
kind = "nan"
sensor = 4
axis = "z"
start_s = 1.0
duration_s = 0.5
[[sensor_faults.fault]]
kind = "stuck"
sensor = 2
axis = "y"
start_s = 2.0
[[sensor_faults.fault]]
kind = "drift"
sensor = 3
axis = "y"
start_s = 1.0
size = 2e-9
[[sensor_faults.fault]]
kind = "noise"
sensor = 0
axis = "z"
start_s = 0.0
size = 1e-6
[[sensor_faults.fault]]
kind = "status_bad"
sensor = 5
start_s = 3.0
duration_s = 0.1
[[sensor_faults.fault]]
kind = "step"
sensor = "gyro"
axis = "z"
start_s = 1.0
size = 1e-7
[[sensor_faults.fault]]
kind = "inf"
sensor = "gyro"
axis = "x"
start_s = 4.0
duration_s = 0.01
[[sensor_faults.fault]]
kind = "time_jump"
start_s = 5.0
duration_s = 0.01
size = 5000
[[sensor_faults.fault]]
kind = "saturate"
sensor = 0
axis = "x"
start_s = 6.0
size = 5.0
)";
    const Generator3 clean(parse_scenario3(kBase, "clean", "test"));
    const Generator3 faulty(parse_scenario3(kBase + faults, "faulty", "test"));
    bool step_ok = true, nan_ok = true, stuck_ok = true, drift_ok = true, gyro_ok = true, others_ok = true;
    bool status_ok = true, inf_ok = true, jump_ok = true, sat_ok = true;
    double n1 = 0, n2 = 0;
    int nn = 0;
    gg_frame_t ref;
    clean.frame(200, ref);
    for (int64_t k = 0; k < 700; ++k) {
      gg_frame_t a, b;
      clean.frame(k, a);
      faulty.frame(k, b);
      const double t = static_cast<double>(k) * 0.01;
      const long double d1x = reading(b, 1, 0) - reading(a, 1, 0);
      step_ok &= std::fabs(static_cast<double>(d1x - (t >= 1.0 ? 1e-8L : 0.0L))) < kExact;
      nan_ok &= (t >= 1.0 && t < 1.5) ? std::isnan(b.f[4][2]) : b.f[4][2] == a.f[4][2];
      stuck_ok &= t >= 2.0 ? (b.f[2][1] == ref.f[2][1] && b.f_lo[2][1] == ref.f_lo[2][1]) : b.f[2][1] == a.f[2][1];
      const long double d3y = reading(b, 3, 1) - reading(a, 3, 1);
      drift_ok &= std::fabs(static_cast<double>(d3y - (t >= 1.0 ? 2e-9L * (static_cast<long double>(k) * 0.01L - 1) : 0.0L))) < kExact;
      const double dn = static_cast<double>(reading(b, 0, 2) - reading(a, 0, 2));
      if (t < 6.0) {
        n1 += dn;
        n2 += dn * dn;
        ++nn;
      }
      status_ok &= b.acc_status[5] == ((t >= 3.0 && t < 3.1) ? GG_SENSOR_BAD : GG_SENSOR_OK);
      gyro_ok &= std::fabs(b.omega_b[2] - a.omega_b[2] - (t >= 1.0 ? 1e-7 : 0.0)) < 1e-20;
      inf_ok &= (k == 400) ? std::isinf(b.omega_b[0]) : b.omega_b[0] == a.omega_b[0];
      jump_ok &= b.utime == a.utime + (k == 500 ? 5000 : 0);
      sat_ok &= t >= 6.0 ? (b.f[0][0] == 5.0 && b.f_lo[0][0] == 0.0) : b.f[0][0] == a.f[0][0];
      // every reading no fault names is untouched
      for (int s = 0; s < 6; ++s)
        for (int j = 0; j < 3; ++j) {
          const bool named = (s == 1 && j == 0) || (s == 4 && j == 2) || (s == 2 && j == 1) || (s == 3 && j == 1) ||
                             (s == 0 && j == 2) || (s == 0 && j == 0);
          if (!named) others_ok &= a.f[s][j] == b.f[s][j] && a.f_lo[s][j] == b.f_lo[s][j];
        }
      others_ok &= a.omega_b[1] == b.omega_b[1];
    }
    check(step_ok, "step: reading 1x moved by exactly 1e-8 m/s^2 from 1 s (hi + lo)");
    check(nan_ok, "nan: 4z NaN from 1 s for 0.5 s, clean before and after");
    check(stuck_ok, "stuck: 2y keeps its fault-free value of step 200 (2 s)");
    check(drift_ok, "drift: 3y grows by 2e-9 m/s^2 per s from 1 s");
    const double mean = n1 / nn, sd = std::sqrt(n2 / nn - mean * mean);
    std::printf("     noise burst on 0z: mean %.3e, sd %.4e (size 1e-6, %d samples)\n", mean, sd, nn);
    check(std::fabs(sd / 1e-6 - 1) < 0.1 && std::fabs(mean) < 4 * 1e-6 / std::sqrt(nn), "noise: 0z sd = size (10 %), mean 0 (4 sigma)");
    check(status_ok, "status_bad: acc_status[5] bad from 3 s for 0.1 s");
    check(gyro_ok, "gyro step: omega_b z + 1e-7 rad/s from 1 s");
    check(inf_ok, "gyro inf: omega_b x +Inf on step 400 only");
    check(jump_ok, "time_jump: utime of step 500 + 5000 us only");
    check(sat_ok, "saturate: 0x pinned at 5 m/s^2 from 6 s");
    check(others_ok, "every other reading bit-identical to the clean frames");
  }
  // ---------------- parser errors: key and line
  {
    const std::string e1 = parse_error(kBase + "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 6\naxis = \"x\"\n");
    check(e1.find("test:21: sensor_faults.fault[0].sensor = 6: must be an accelerometer or the gyro (allowed: [0, 5], "
                  "\"gyro\")") != std::string::npos,
          "sensor 6 rejected with its line: " + e1);
    const std::string e2 = parse_error(kBase + "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"wobble\"\nsensor = 1\n");
    check(e2.find("test:20: sensor_faults.fault[0].kind = \"wobble\": unknown value (allowed: \"nan\",") != std::string::npos,
          "unknown kind: " + e2);
    const std::string e3 = parse_error(kBase + "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 1\n");
    check(e3.find("test:19: sensor_faults.fault[0].axis is required for kind 'step' (allowed: \"x\", \"y\", \"z\")") !=
              std::string::npos,
          "missing axis: " + e3);
    const std::string e4 = parse_error(kBase + "[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = 1\naxis = \"w\"\n");
    check(e4.find("test:22: sensor_faults.fault[0].axis = \"w\": unknown value (allowed: \"x\", \"y\", \"z\")") !=
              std::string::npos,
          "bad axis: " + e4);
    const std::string e5 = parse_error(kBase + "[sensor_faults]\nseed = 1\nfoo = 2\n");
    check(e5.find("test:20: unknown key 'sensor_faults.foo' (allowed: fault, seed)") != std::string::npos,
          "unknown key: " + e5);
  }
  // ---------------- the firmware: 1e-8 m/s^2 bias on one axis, flagged and isolated
  {
    const Scenario3 clean = parse_scenario3(kBase, "clean", "test");
    const Run c = fly(clean, 0, GG_HEALTH_ACC_FAULT);
    std::printf("FAULTMATRIX3D | none (reference) | - | - | final |dr| %.3e m (max %.3e m) | health 0x%08x | rejected %lld\n",
                c.dr_final, c.dr_max, c.health_or, static_cast<long long>(c.rejected));
    check(!(c.health_or & GG_HEALTH_ACC_FAULT) && c.rejected == 0 && c.excluded == 0, "clean flight: no fault flagged");
    struct Case {
      int sensor, axis;
      const char* name;
    };
    for (const Case& cs : {Case{1, 0, "1x"}, Case{2, 2, "2z"}, Case{3, 1, "3y"}}) {
      const std::string f = std::string("[sensor_faults]\n[[sensor_faults.fault]]\nkind = \"step\"\nsensor = ") +
                            std::to_string(cs.sensor) + "\naxis = \"" + "xyz"[cs.axis] + "\"\nstart_s = 5.0\nsize = 1e-8\n";
      const Run r = fly(parse_scenario3(kBase + f, "bias", "test"), 500, GG_HEALTH_ACC_FAULT);
      std::printf("FAULTMATRIX3D | %s step 1e-8 m/s^2 from 5 s | flagged after %lld steps | excluded 0x%05x (its bit 0x%05x) | "
                  "final |dr| %.3e m | health 0x%08x | rejected %lld\n",
                  cs.name, static_cast<long long>(r.first_flag), r.excluded, GG_FDI3D_BIT(cs.sensor, cs.axis), r.dr_final,
                  r.health_or, static_cast<long long>(r.rejected));
      check(r.first_flag >= 0 && r.first_flag <= 1, std::string("bias on ") + cs.name + ": ACC_FAULT within 1 step");
      check(r.excluded == GG_FDI3D_BIT(cs.sensor, cs.axis), std::string("bias on ") + cs.name + ": that reading excluded, no other");
      check(r.rejected == 0, std::string("bias on ") + cs.name + ": no frame rejected");
      // the excluded reading is rebuilt: the error stays the clean run's (the bias alone, 5e-9 on
      // the pair mean for 25 s, would be 1.6e-6 m)
      check(std::fabs(r.dr_final - c.dr_final) < 1e-7, std::string("bias on ") + cs.name + ": final error within 1e-7 m of the clean run's");
    }
  }
  // ---------------- a NaN pair for 1.5 s: bridged, then the task goes on
  {
    const std::string f = R"([sensor_faults]
[[sensor_faults.fault]]
kind = "nan"
sensor = 2
axis = "z"
start_s = 10.0
duration_s = 1.5
[[sensor_faults.fault]]
kind = "nan"
sensor = 5
axis = "z"
start_s = 10.0
duration_s = 1.5
)";
    Scenario3 sc = parse_scenario3(kBase + f, "nanpair", "test");
    const Run r = fly(sc, 1000, GG_HEALTH_ACC_NONFINITE);
    std::printf("FAULTMATRIX3D | NaN on 2z and 5z (a whole pair-axis), 10-11.5 s | flagged after %lld steps | last NONFINITE "
                "step %lld | rejected %lld | health 0x%08x | final |dr| %.3e m (max %.3e m)\n",
                static_cast<long long>(r.first_flag), static_cast<long long>(r.last_nonfinite),
                static_cast<long long>(r.rejected), r.health_or, r.dr_final, r.dr_max);
    check(r.first_flag == 0, "NaN pair: flagged on its first step");
    check(r.last_nonfinite == 1149, "NaN pair: flagged to its last step (1149) and not after");
    check(r.rejected <= 150, "NaN pair: at most its 150 frames not used");
    // steady level flight: the held inputs are the true ones to the 1.5 s change of the
    // specific force (< 1e-6 m/s^2 here), so the bridge costs < 1 mm
    check(r.dr_final < 1e-3, "NaN pair: navigating after it, final position error < 1 mm");
  }
  std::printf(g_fail ? "FAILED (%d)\n" : "PASSED\n", g_fail);
  return g_fail ? 1 : 0;
}
