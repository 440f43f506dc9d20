#include "ggins/truth/config2d.hpp"

#include <cmath>
#include <cstring>

namespace ggins::truth {

void vchan_config(const BaroLoopParams& l, double period_s, gg_real_t omega_s2, gg_vchan_config_t& c) {
  for (size_t i = 0; i < 3; ++i) c.poles[i] = static_cast<gg_real_t>(l.poles_radps[i]);
  c.omega_s2 = omega_s2;
  c.period_us = std::llround(period_s * 1e6);
  c.max_age_us = std::llround(l.max_age_s * 1e6);
  c.coast_us = std::llround(l.coast_s * 1e6);
  c.alt_min_m = l.alt_min_m;
  c.alt_max_m = l.alt_max_m;
  c.gate_m = l.gate_m;
  c.max_rejects = static_cast<int32_t>(l.max_rejects);
}

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
  c.acc_frozen_frames = static_cast<int32_t>(s.firmware.acc_frozen_frames);
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
  // w_s^2 = |G| / |r| at the start (the point-mass vertical gradient is 2 w_s^2), as a double
  const double ws2 = l.omega_s2 > 0 ? l.omega_s2 : static_cast<double>(t0.g.norm() / t0.kin.r.norm());
  vchan_config(l, s.baro_period_s(), static_cast<gg_real_t>(ws2), c.baro);
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
