// The scenario -> firmware configuration mapping of the 2-D task
// (truth/config2d.hpp) against configurations written out by hand from the
// scenario text and nav2d.h: every field, with the initial state from the
// closed form of the north flight over a point mass,
//   r0 = rho (cos L0, 0, sin L0),  v0 = V (-sin L0, 0, cos L0),
//   G(r0) = -GM / rho^2 (cos L0, 0, sin L0),  w_s^2 = GM / rho^3,  rho = R + h.
// The firmware accepts what the mapping produces (gg_nav2d_init).
#include <cmath>
#include <cstdio>
#include <string>

#include "ggins/truth/config2d.hpp"

using namespace ggins::truth;

#include "check.hpp"

static bool near(long double a, long double b, long double rel) { return fabsl(a - b) <= rel * fabsl(b) + 1e-30L; }

static void test_model_mode() {
  const std::string text = R"(
name = "config2d-model"
[trajectory]
type = "north-flight"
speed_mps = 250.0
height_m = 1000.0
lat0_deg = 30.0
radius_m = 6378137.0
[gravity]
model = "point-mass"
gm_m3ps2 = 3.986004418e14
[platform]
a_m = 0.4
b_m = 0.6
[time]
duration_s = 10.0
rate_hz = 50.0
[firmware]
f_max_mps2 = 40.0
asym_max_ps2 = 2e-6
dt_tol_us = 3
gravdr_trapezoid_only = true
fdi_parity_f_max_mps2 = 1e-3
fdi_asym_max_ps2 = 1e-5
[baro]
rate_hz = 2.0
[navigation]
gravity = "model"
r_ref_m = 6378000.0
[navigation.model]
gm_m3ps2 = 3.9860044e14
a_m = 6378100.0
j = [1.0e-3, 0.0, -2.0e-6]
[navigation.baro]
poles_radps = [0.02, 0.03, 0.04]
max_age_s = 0.25
coast_s = 5.0
alt_min_m = -500.0
alt_max_m = 20000.0
gate_m = 60.0
max_rejects = 7
)";
  const Scenario s = parse_scenario(text, "config2d-model", "test");
  const gg_nav2d_config_t c = config2d(s);
  // hand-written expectation
  const long double GM = 3.986004418e14L, rho = 6378137.0L + 1000.0L, V = 250.0L;
  const long double L0 = 30.0L * 3.14159265358979323846264338327950288L / 180.0L;
  const long double cl = cosl(L0), sl = sinl(L0), g = GM / (rho * rho);
  const long double r0[3] = {rho * cl, 0, rho * sl}, v0[3] = {-V * sl, 0, V * cl}, g0[3] = {-g * cl, 0, -g * sl};
  bool rv = true;
  for (int j = 0; j < 3; ++j)
    rv = rv && fabsl(c.r0[j] - r0[j]) < 1e-9L && fabsl(c.v0[j] - v0[j]) < 1e-12L && fabsl(c.g0[j] - g0[j]) < 1e-15L;
  CHECK(rv, "r0, v0, G(r0) = the closed form of the north flight over the point mass");
  CHECK(c.geometry.a_m == static_cast<gg_real_t>(0.4) && c.geometry.b_m == static_cast<gg_real_t>(0.6), "half-baselines 0.4, 0.6 m");
  CHECK(c.dt_us == 20000 && c.dt_tol_us == 3, "step 20000 us (50 Hz), tolerance 3 us");
  CHECK(c.f_max == 40.0 && c.asym_max == 2e-6 && c.gravdr_trapezoid_only == 1, "range 40 m/s^2, symmetry 2e-6 s^-2, plain trapezoid");
  CHECK(c.fdi_parity_f_max == 1e-3 && c.fdi_asym_max == 1e-5, "fault-detection thresholds 1e-3 m/s^2, 1e-5 s^-2");
  CHECK(c.gravity_mode == GG_GRAVITY_MODEL, "gravity from the onboard model");
  CHECK(c.model.gm == static_cast<gg_real_t>(3.9860044e14) && c.model.a_m == 6378100.0L, "onboard GM and a as given");
  CHECK(c.model.j[0] == 0 && c.model.j[1] == 0 && c.model.j[2] == static_cast<gg_real_t>(1.0e-3) && c.model.j[3] == 0 &&
            c.model.j[4] == static_cast<gg_real_t>(-2.0e-6) && c.model.j[5] == 0 && c.model.j[8] == 0,
        "onboard J2 = 1e-3, J4 = -2e-6 at j[2], j[4]");
  CHECK(c.model.n_pm == 0 && c.model.grid.n_th == 0, "no programmed masses, no grid");
  CHECK(c.baro_enable == 1, "barometric loop on (the [baro] table enables it)");
  CHECK(c.baro.poles[0] == static_cast<gg_real_t>(0.02) && c.baro.poles[1] == static_cast<gg_real_t>(0.03) &&
            c.baro.poles[2] == static_cast<gg_real_t>(0.04),
        "loop poles 0.02, 0.03, 0.04 rad/s");
  CHECK(near(c.baro.omega_s2, GM / (rho * rho * rho), 1e-15L) && c.baro.omega_s2 == static_cast<double>(c.baro.omega_s2),
        "w_s^2 = GM / rho^3 = %.12Lg s^-2, carried as a double", c.baro.omega_s2);
  CHECK(c.baro.period_us == 500000 && c.baro.max_age_us == 250000 && c.baro.coast_us == 5000000,
        "baro period 0.5 s (2 Hz), max age 0.25 s, coast 5 s");
  CHECK(c.baro.alt_min_m == -500.0 && c.baro.alt_max_m == 20000.0 && c.baro.gate_m == 60.0 && c.baro.max_rejects == 7,
        "altitude range [-500, 20000] m, gate 60 m, 7 rejects");
  CHECK(c.r_ref_m == 6378000.0L, "altitude reference 6378000 m");
  gg_nav2d_t nav;
  CHECK(gg_nav2d_init(&nav, &c) == GG_OK, "the firmware accepts the configuration");
}

static void test_defaults() {
  // gradiometer mode, no barometer, WGS-84 normal field: the defaults of scenario.hpp
  const Scenario s = parse_scenario("[gravity]\nmodel = \"wgs84-normal\"\n[time]\nduration_s = 1.0\n", "config2d-default", "test");
  const gg_nav2d_config_t c = config2d(s);
  CHECK(c.gravity_mode == GG_GRAVITY_GRADIOMETER && c.baro_enable == 0, "default: gradiometer mode, loop off");
  CHECK(c.dt_us == 10000 && c.dt_tol_us == 0 && c.f_max == 50.0 && c.asym_max == 1e-6, "default: 100 Hz, range 50, symmetry 1e-6");
  CHECK(c.geometry.a_m == 0.5L && c.geometry.b_m == 0.5L && c.r_ref_m == 6378137.0L, "default: 0.5 m half-baselines, r_ref = a");
  // onboard model: WGS-84 GM = 3.986004418e14, a = 6378137, J2 = 1.08262982131e-3 (NIMA TR8350.2, from the defining constants)
  CHECK(c.model.gm == static_cast<gg_real_t>(3.986004418e14) && c.model.a_m == 6378137.0L &&
            fabsl(c.model.j[2] - 1.08262982131e-3L) < 1e-13L && c.model.j[3] == 0,
        "default model: WGS-84 GM, a, J2 = %.10Lg", c.model.j[2]);
  CHECK(c.baro.period_us == 1000000 && c.baro.max_age_us == 500000 && c.baro.gate_m == 50.0,
        "default loop fields (1 Hz, 0.5 s, 50 m) even when off");
}

int main() {
  test_model_mode();
  test_defaults();
  std::printf("%s (%d failures)\n", g_fail ? "FAILED" : "all passed", g_fail);
  return g_fail ? 1 : 0;
}
