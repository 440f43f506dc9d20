#include "ggins/truth/config2d.hpp"

#include <cmath>
#include <cstring>

namespace ggins::truth {

gg_nav2d_config_t config2d(const Generator& g, const SurveyGrid* grid) {
  const Scenario& s = g.scenario();
  const TruthState t0 = g.truth(0);
  gg_nav2d_config_t c;
  std::memset(&c, 0, sizeof c);
  c.geometry.a_m = static_cast<gg_real_t>(s.a_m);
  c.geometry.b_m = static_cast<gg_real_t>(s.b_m);
  c.dt_us = s.dt_us();
  c.dt_tol_us = s.firmware.dt_tol_us;
  for (int j = 0; j < 3; ++j) {
    c.r0[j] = t0.kin.r(j);
    c.v0[j] = t0.kin.v(j);
    c.g0[j] = t0.g(j);
  }
  c.f_max = s.firmware.f_max_mps2;
  c.asym_max = s.firmware.asym_max_ps2;
  c.gravdr_trapezoid_only = s.firmware.gravdr_trapezoid_only ? 1 : 0;
  c.fdi_parity_f_max = s.firmware.fdi_parity_f_max_mps2;
  c.fdi_asym_max = s.firmware.fdi_asym_max_ps2;
  // gravity source, onboard model (zonal part, programmed grid)
  c.gravity_mode = s.navigation.gravity == "model" ? GG_GRAVITY_MODEL : GG_GRAVITY_GRADIOMETER;
  const NavModelParams nm = s.nav_model();
  c.model.gm = static_cast<gg_real_t>(nm.gm_m3ps2);
  c.model.a_m = static_cast<gg_real_t>(nm.a_m);
  for (size_t n = 0; n <= GG_GMODEL_MAX_DEGREE && n < nm.j.size(); ++n) c.model.j[n] = static_cast<gg_real_t>(nm.j[n]);
  if (c.gravity_mode == GG_GRAVITY_MODEL && grid) fill_gmodel_grid(*grid, c.model.grid);
  // barometric loop
  c.baro_enable = s.baro_loop_enabled() ? 1 : 0;
  const BaroLoopParams& l = s.navigation.baro;
  for (size_t i = 0; i < 3; ++i) c.baro.poles[i] = static_cast<gg_real_t>(l.poles_radps[i]);
  // w_s^2 = |G| / |r| at the start (the point-mass vertical gradient is 2 w_s^2), as a double
  c.baro.omega_s2 = static_cast<gg_real_t>(l.omega_s2 > 0 ? l.omega_s2 : static_cast<double>(t0.g.norm() / t0.kin.r.norm()));
  c.baro.period_us = std::llround(s.baro_period_s() * 1e6);
  c.baro.max_age_us = std::llround(l.max_age_s * 1e6);
  c.baro.coast_us = std::llround(l.coast_s * 1e6);
  c.baro.alt_min_m = l.alt_min_m;
  c.baro.alt_max_m = l.alt_max_m;
  c.baro.gate_m = l.gate_m;
  c.baro.max_rejects = static_cast<int32_t>(l.max_rejects);
  c.r_ref_m = static_cast<gg_real_t>(s.r_ref_m());
  return c;
}

gg_nav2d_config_t config2d(const Scenario& s) {
  const Generator g(s);
  if (s.navigation.gravity == "model" && s.navigation.survey.enable) {
    const SurveyGrid grid = make_survey_grid(g);
    return config2d(g, &grid);
  }
  return config2d(g);
}

}  // namespace ggins::truth
