// The scenario -> firmware configuration mapping of the 3-D task: the one
// place where a 3-D scenario (scenario3d.hpp) becomes the gg_nav3d_config_t
// of nav3d.h (ggins run3d over LCM or in process, Monte Carlo, the tests):
// geometry, platform, step, the initial r0_e, v0_e, g0_e (G at the true start
// position, known as in Welker et al.), q0_b_e from the truth at t = 0 (position,
// velocity and attitude less the scenario's [initial_error]), the
// Earth rate of the trajectory flown, gravity mode and onboard model (the WGS-84 normal field's zonal
// series J2..J8, or the point mass), barometric loop, the aiding sources
// ([aid_ukf]: apply_aid_ukf, src/aids3d.cpp; [aid_pf] with [coldatom]: apply_aid_pf,
// src/coldatom3d.cpp).
#pragma once

extern "C" {
#include "ggins/nav3d.h"
}
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

namespace ggins::truth3d {

// The configuration of scenario s flown by generator g (its truth at t = 0).
gg_nav3d_config_t config3d(const Scenario3& s, const Generator3& g);
// The same from the scenario alone (builds its generator).
gg_nav3d_config_t config3d(const Scenario3& s);

// [aid_ukf] onto c.aid_mm (1 E = 1e-9 s^-2); the firmware validates the values
// (gg_nav3d_init). The gyro's noise and bias one-sigma, unless [aid_ukf] states
// them, are the sensor's as [gyro] specifies it (the per-step white noise
// noise_sigma_radps; the bias sqrt(bias_sigma_radps^2 + the largest fixed
// bias_radps^2)); config3d adds the largest [draw] gyro_bias_radps to
// bias_sigma_radps in quadrature (the filter knows the draw's sigma, not its outcome).
// The barometer's white noise per sample, unless [aid_ukf] sigma_baro_m states it, is
// baro_noise_m ([baro] noise_sigma_m).
void apply_aid_ukf(const AidUkf3& a, double rate_hz, const GyroErrorParams& gyro, double baro_noise_m,
                   gg_nav3d_config_t& c);

}  // namespace ggins::truth3d
