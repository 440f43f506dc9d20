// The scenario -> firmware configuration mapping of the 2-D task: the one
// place where a 2-D scenario (scenario.hpp) becomes the gg_nav2d_config_t of
// nav2d.h that every tool (ggins run over LCM or in process, rw-eq8, the
// benchmarks) hands the firmware.
//   geometry a, b; step and tolerance; r0, v0 and G(0) from the truth at t = 0
//   (G known at the start, as in Welker et al.); accelerometer range, symmetry
//   and fault-detection thresholds; gravity mode and the onboard zonal model
//   (Scenario::nav_model()) with the programmed anomaly grid when given; the
//   barometric loop (vchan.h: poles, w_s^2 = |G(r0)| / |r0| unless given,
//   period, ages, range, gate); the altitude reference r_ref.
// Values the host sends as doubles over LCM (w_s^2) are rounded to double
// here, so a configuration sent over LCM and one handed over in process are
// the same bit for bit.
#pragma once

extern "C" {
#include "ggins/nav2d.h"
}
#include "ggins/truth/generator.hpp"
#include "ggins/truth/scenario.hpp"
#include "ggins/truth/survey.hpp"

namespace ggins::truth {

// The barometric loop ([navigation.baro], vchan.h) of a 2-D or 3-D scenario, with its
// sample period and w_s^2 resolved by the caller.
void vchan_config(const BaroLoopParams& l, double period_s, gg_real_t omega_s2, gg_vchan_config_t& c);

// The configuration of g's scenario; with a survey grid (model mode,
// [navigation.survey]) the grid is programmed into the onboard model.
gg_nav2d_config_t config2d(const Generator& g, const SurveyGrid* grid = nullptr);
// The same from the scenario alone (builds its generator, and its survey grid
// when the scenario asks for one).
gg_nav2d_config_t config2d(const Scenario& s);

}  // namespace ggins::truth
