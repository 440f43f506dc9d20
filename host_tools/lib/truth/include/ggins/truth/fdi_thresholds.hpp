// Default fault-detection thresholds of the 2-D firmware (fdi2d.h), derived
// from a scenario's sensor errors, baseline and field.
//
// The firmware tests p_x, p_z (m/s^2) less the point-mass curvature terms
// p_exp it computes itself (gg_fdi2d_expected_parity, mu = |G| |r|^2), and
// p_s = Gxz - Gzx (s^-2). With healthy sensors what is left is
//   systematic  the residuals of the error-free readings of this field
//               (curvature beyond the point mass: an anomaly field's third
//               derivatives over the half-baselines, ~6e-13 m/s^2 in the
//               Rubenstein & Winter field at 0.5 m) plus the scenario's own
//               constant biases and scale factors (the values the generator
//               drew), evaluated along the whole trajectory (samples every
//               15 s, or duration/1440 when longer: 1.5 km at 100 m/s, far
//               below the anomaly field's correlation length) from the exact field at
//               each sensor; D = the largest |.| over the samples;
//   random      white noise sigma per reading: p_x, p_z have sigma_n.
//   p_s         is tested also while one reading is rebuilt from its group's
//               parity relation with p = p_exp (fdi2d.h): the rebuilt reading
//               then carries twice the group's residual e = p - p_exp, which
//               moves p_s by e/b (x group) or e/a (z group), and the noise of
//               the three readings it is built from: its systematic part is
//               D_s + D_f / min(a, b), its noise up to
//               sigma_n sqrt(1.5/min(a,b)^2 + 0.5/max(a,b)^2).
// Threshold = 2 D + 7 sigma + floor: twice the systematic part (its
// variation between samples and the navigation's own position error in
// p_exp are far below it), 7 sigma (a false alarm per ~4e11 samples of
// Gaussian noise), and a floor of 1e-14 m/s^2 (1e-14 / min(a, b) s^-2) for
// the rounding of readings to double on a double-only target.
// A bias d on one reading moves p_x or p_z by d/2 and p_s by d/(2b) or
// d/(2a): it is flagged once d exceeds twice the threshold (for the built-in
// scenarios ~1e-12 m/s^2: 1e-8 is flagged by four orders of magnitude).
#pragma once

#include "ggins/truth/scenario.hpp"

namespace ggins::truth {

struct FdiThresholds {
  double parity_f_max_mps2 = 0;  // fdi_parity_f_max
  double asym_max_ps2 = 0;       // fdi_asym_max
  double sys_f_mps2 = 0;         // D of p_x, p_z less p_exp (curvature beyond the point mass, biases, scale)
  double sys_s_ps2 = 0;          // D of p_s
  double curv_f_mps2 = 0;        // the field's share of sys_f (error-free readings)
  double curv_s_ps2 = 0;
  double noise_f_mps2 = 0;       // sigma of p_x, p_z
  double noise_s_ps2 = 0;        // sigma of p_s
  int samples = 0;
};

// Default frozen-reading window of the firmware (navtask.h), frames. A reading of white
// noise sigma at a double's resolution eps = ulp(f_max) repeats bit for bit from one frame to
// the next with probability p < eps / (sigma sqrt(4 pi)) (the difference of two samples has
// density 1/(sigma sqrt(4 pi)) at 0); over kFrozenFrames frames, p^(kFrozenFrames - 1).
// With sigma >= 10 eps, p < 0.028 and a false alarm has probability < 1e-14 per reading and
// frame (< 1e-6 in 10 h of 18 readings at 100 Hz). Below that (noise-free sensors: an exact
// reading of a constant field is constant) the monitor is off: 0.
constexpr int64_t kFrozenFrames = 10;
int64_t default_frozen_frames(double noise_sigma_mps2, double f_max_mps2);

// Evaluate the thresholds for scenario s (its sensor faults are ignored).
FdiThresholds derive_fdi_thresholds(const Scenario& s);

// Fill s.firmware.fdi_parity_f_max_mps2 / fdi_asym_max_ps2 with the derived
// values where the scenario did not set them (parse_scenario does this for the flight as
// flown: after its ScenarioAdjust, e.g. a front-end's --seed or --duration).
void apply_default_fdi_thresholds(Scenario& s);

}  // namespace ggins::truth
