// Default 2-D fault-detection thresholds (host_tools/lib/truth fdi_thresholds.hpp)
// for the built-in 2-D scenarios: printed, and checked against what they
// must do - leave the field's own parity residual (curvature beyond the point
// mass: the anomaly scenarios) and the scenario's biases below the threshold
// with a factor 2 to spare, and flag a 1e-8 m/s^2 bias on any one reading
// (which moves p_x or p_z by 5e-9 m/s^2 and p_s by 1e-8 / (2 h) s^-2).
// Independent check of the field share: in a point-mass field the firmware's
// expected parity is exact, so the error-free readings' residual must vanish
// to rounding (< 1e-15 m/s^2), and the survey / anomaly scenarios must show
// their field (> 1e-14 m/s^2).
#include <cmath>
#include <cstdio>
#include <string>

#include "ggins/truth/fdi_thresholds.hpp"
#include "ggins/truth/scenario.hpp"

using namespace ggins::truth;

int main() {
  int fail = 0;
  // the four rw-* scenarios share one field, trajectory and sensors: the first stands for them
  // (the anomaly field costs ~3 ms per evaluation; fdi_scenario_check flies them all)
  bool rw_done = false;
  for (const auto& name : builtin_scenario_names()) {
    if (name.rfind("rw-", 0) == 0) {
      if (rw_done) continue;
      rw_done = true;
    }
    const Scenario sc = load_scenario(name, {});
    const FdiThresholds th = derive_fdi_thresholds(sc);
    const bool pm = sc.gravity.model == "point-mass";
    std::printf("%-24s field %-12s samples %5d  curvature %.2e m/s^2 %.2e s^-2  systematic %.2e %.2e  "
                "noise %.1e  ->  fdi_parity_f_max %.3e m/s^2, fdi_asym_max %.3e s^-2 (loaded: %.3e, %.3e)\n",
                name.c_str(), sc.gravity.model.c_str(), th.samples, th.curv_f_mps2, th.curv_s_ps2, th.sys_f_mps2,
                th.sys_s_ps2, th.noise_f_mps2, th.parity_f_max_mps2, th.asym_max_ps2,
                sc.firmware.fdi_parity_f_max_mps2, sc.firmware.fdi_asym_max_ps2);
    const double hmax = std::fmax(sc.a_m, sc.b_m);
    auto check = [&](bool ok, const char* what) {
      if (!ok) {
        std::printf("FAIL %s: %s\n", name.c_str(), what);
        ++fail;
      }
    };
    check(th.parity_f_max_mps2 > 0 && th.asym_max_ps2 > 0, "thresholds on");
    check(th.parity_f_max_mps2 >= 2 * th.sys_f_mps2 && th.asym_max_ps2 >= 2 * th.sys_s_ps2, "systematic part x2 below");
    check(2 * th.parity_f_max_mps2 < 5e-9 && 2 * th.asym_max_ps2 < 1e-8 / (2 * hmax), "a 1e-8 bias is flagged");
    check(sc.firmware.fdi_parity_f_max_mps2 == th.parity_f_max_mps2 && sc.firmware.fdi_asym_max_ps2 == th.asym_max_ps2,
          "load_scenario applies them");
    if (pm) check(th.curv_f_mps2 < 1e-15, "point mass: the expected parity is exact");
    else check(th.curv_f_mps2 > 1e-14, "anomaly field: its curvature shows");
  }
  {
    // the frozen-reading window: on (10 frames) when the white noise is at least 10 ulp of the
    // range; ulp(50 m/s^2) = 2^-47 m/s^2 = 7.105e-15 (50 lies in [32, 64), 52 mantissa bits)
    auto fcheck = [&](bool ok, const char* what) {
      std::printf("  frozen window: %s: %s\n", what, ok ? "ok" : "FAIL");
      if (!ok) fail = 1;
    };
    const double ulp50 = std::ldexp(1.0, -47);
    fcheck(default_frozen_frames(0.0, 50.0) == 0, "noise-free: off");
    fcheck(default_frozen_frames(9.99 * ulp50, 50.0) == 0, "noise of 9.99 ulp: off");
    fcheck(default_frozen_frames(10.0 * ulp50, 50.0) == 10, "noise of 10 ulp: 10 frames");
    fcheck(default_frozen_frames(5.5e-10, 50.0) == 10, "5.5e-10 m/s^2: 10 frames");
    fcheck(default_frozen_frames(1e-13, 1e6) == 0, "1e-13 m/s^2 against a 1e6 m/s^2 range (ulp 1.2e-10): off");
    fcheck(default_frozen_frames(NAN, 50.0) == 0, "NaN noise: off");
    for (const auto& name : builtin_scenario_names()) {
      const Scenario sc = load_scenario(name, {});
      const bool noisy = sc.accel.noise_sigma_mps2 > 0;
      std::printf("  %s: noise %.1e -> acc_frozen_frames %lld\n", name.c_str(), sc.accel.noise_sigma_mps2,
                  static_cast<long long>(sc.firmware.acc_frozen_frames));
      fcheck(sc.firmware.acc_frozen_frames == (noisy ? 10 : 0), "built-in: derived from its noise");
    }
  }
  std::printf("%s\n", fail ? "FAILED" : "ok");
  return fail ? 1 : 0;
}
