// Survey grid for the conventional INS's programmed anomalies (the
// Rubenstein & Winter "anomaly grid"): the firmware's polar anomaly grid
// (firmware/include/ggins/gmodel.h, gg_gmodel_grid_t) along the scenario's
// north flight, node values = the truth disturbance G_truth - G_onboard-zonal
// at the node (tangential and radial components), plus seeded independent
// Gaussian noise: noise_gravity_mgal on the radial component (a gravity
// anomaly survey) and g * noise_deflection_arcsec on the tangential one (a
// deflection of the vertical). Scenario keys: [navigation.survey]
// (scenario.hpp). The nodes are point values at the flight's radius +- n_rho
// levels, i.e. an ideally upward-continued survey; only the noise is imperfect.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "ggins/truth/generator.hpp"
#include "ggins/truth/scenario.hpp"

namespace ggins::truth {

struct SurveyGrid {
  int32_t n_th = 0, n_rho = 0;
  double c0 = 1, s0 = 0;          // e0: the flight's start direction in the x-z plane
  double th0_rad = 0, dth_rad = 0;
  double rho0_m = 0, drho_m = 0;
  std::vector<std::array<double, 2>> dg;       // k * n_th + i: dG_t, dG_r with noise, m/s^2
  std::vector<std::array<double, 2>> dg_true;  // the same without noise
  double rms_noise_t = 0, rms_noise_r = 0;     // sample rms of the noise added, m/s^2
  double rms_true_t = 0, rms_true_r = 0;       // rms of the true node values, m/s^2
};

// Builds the grid for g's scenario (north-flight only); throws
// std::invalid_argument when the grid does not fit GG_GMODEL_GRID_MAX or the
// trajectory is not a north flight.
SurveyGrid make_survey_grid(const Generator& g);

// The grid (and the zonal part of nav_model()) as a firmware configuration.
void fill_gmodel_grid(const SurveyGrid& s, gg_gmodel_grid_t& out);

}  // namespace ggins::truth
