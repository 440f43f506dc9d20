// Flight simulation of Phillips et al. section V: an aviation-grade INS (paper
// Table I) flying Liverpool -> Toulouse at 3000 m, 100 m/s, unaided and aided by
// the firmware particle filter (firmware/include/ggins/pf.h) fed with single
// pairs of the cold-atom gradiometer; the ellipse-fitting baseline on batches.
//
// INS: a simplified horizontal error model driven by the Table I errors (the
// lead's 3-D firmware was not ready): psi-angle error equations (Benson 1975;
// Titterton & Weston 2004 ch. 12) in NED, level flight, body x along the route
// heading:
//   dr'  = dv                                    (N, E; vertical held by the altimeter)
//   dv'  = -(psi x f_n) - w_s^2 dr - 2 Omega x dv + C_b^n df_b
//   psi' = -(Omega + rho) x psi + C_b^n eps_b
//   df_b  = b_a + (S_a + N_a) f_b + n_a,   eps_b = b_g + (S_g + N_g) w_b + n_g
// with f_n = (0, 0, -g), w_b the Earth + transport rate in body axes, integrated
// at 10 Hz. Perfect initial alignment (as the paper). Altimeter: true height +
// white noise (alt_noise), used for the candidates' height.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ggins/coldatom/gradiometer.hpp"
#include "ggins/coldatom/route_map.hpp"
#include "ggins/gravity/wgs84.hpp"

extern "C" {
#include "ggins/gmap.h"
}

namespace ggins::coldatom {

// Table I of Phillips et al. (1 sigma). The units the text lost: gyro bias read as
// 0.05 urad/s (0.01 deg/h, aviation grade), gyro noise as 2.0 urad/s/sqrt(Hz),
// accelerometer noise 15 ug/sqrt(Hz).
struct InsErrorParams {
  double acc_bias_g = 30e-6;
  double acc_nonorth = 10e-6;   // rad
  double acc_scale = 10e-6;
  double acc_noise_g = 15e-6;   // g / sqrt(Hz)
  double gyro_bias = 0.05e-6;   // rad/s
  double gyro_nonorth = 10e-6;  // rad
  double gyro_scale = 10e-6;
  double gyro_noise = 2.0e-6;   // rad/s / sqrt(Hz)
  double dt = 0.1;              // s, error-model step
  bool random = true;           // false: biases = +value on every body axis (tests), no scale/non-orthogonality draw
  double earth_rate = static_cast<double>(gravity::wgs84::kOmega);  // rad/s (0 in the closed-form tests)
};

struct FlightConfig {
  GradiometerParams grad;
  InsErrorParams ins;
  int particles = 500;
  double sigma_like = 0;   // 0: max(0.001, gradiometer expected_sigma)
  // Particle dynamics: 1 = GG_PF_MODEL_INS (default): the INS error dynamics (Schuler, Coriolis)
  // with a specific-force error state; 0 = GG_PF_MODEL_RW: the random-walk velocity of the first
  // version (q_pos 2 m, q_vel 0.02 m/s per shot, sigma0_vel 0.05 m/s, no regularisation).
  // Negative values: the model's default - for INS from the INS specification (Table I, see fly()):
  // q_pos 0, q_vel = g0 acc_noise sqrt(dt), q_acc = g0 sqrt((gyro_noise^2 + gyro_bias^2 tau) dt),
  // sigma0_acc = g0 sqrt(acc_bias^2 + acc_nonorth^2), sigma0_vel 0 (perfect alignment).
  // 2 = GG_PF_MODEL_RBPF: Rao-Blackwellised - particles for the position only, a Kalman filter for
  // velocity, tilt, gyro bias and accelerometer error (pf.h); from Table I: q_vel as INS,
  // q_acc = g0 gyro_noise sqrt(dt) (tilt), sigma0_acc 0 (aligned), sigma0_jerk = g0 gyro_bias,
  // sigma0_bias = g0 sqrt(acc_bias^2 + acc_nonorth^2), q_jerk = q_bias = 0 (constant errors).
  int model = 2;
  double sigma0_pos = 50, sigma0_vel = -1;
  double q_pos = -1, q_vel = -1;
  double sigma0_acc = -1, q_acc = -1;
  double q_jerk = -1, q_bias = -1;  // RBPF random walks (<0: 0)
  double reg_bw = -1;      // regularised resampling bandwidth, multiple of Silverman's (RBPF 1.0, INS 0.5, RW 0 = off)
  double ess_frac = 0.5;   // resample when N_eff < ess_frac N (paper: 1/2)
  double gain = 0.05;
  double alt_noise = 5.0;  // m
  int batch = 20;          // pairs per ellipse fit
  double duration = 0;     // s, 0: the whole route
  int record_every = 10;   // s
  bool run_pf = true;
  // Candidates' Gamma_zz through the firmware map module (gmap.h): a 50 x 50 tile
  // at 250 m spacing (12 km square) around the INS position, re-centred when the
  // INS is more than tile_recentre metres from its centre (the host pages tiles,
  // as a flight would). false: the route map directly (host double precision).
  // The tile is paged around the filter's corrected position INS + corr (tile_on_estimate; the
  // candidates lie around it) - false: around the raw INS position (before 2026-12: candidates
  // more than ~3-6 km from the drifting INS fell off the tile and got weight 0).
  bool use_gmap = true;
  bool tile_on_estimate = true;
  double tile_step = 250.0, tile_recentre = 2000.0;
  std::uint64_t seed = 1;
};

struct FlightResult {
  std::string error;  // empty when the flight flew; else why it did not (refused filter config, map tile)
  std::vector<double> t, err_unaided, err_aided;  // every record_every s, metres
  // gradient estimates per batch (s^-2): truth mean over the batch, ellipse fit, PF (map at the corrected position)
  std::vector<double> batch_t, g_true, g_fit, g_pf;
  // filter diagnostics at the same instants as t (host reads the PF state): actual error of the
  // particle mean (m), weighted particle spread sqrt(var_N + var_E) (m), N_eff (last step), actual
  // velocity error of the particle mean (m/s), velocity spread (m/s), true |INS velocity error| (m/s)
  std::vector<double> d_err_mean, d_spread, d_ess, d_verr, d_vspread, d_ins_dv;
  double pf_step_ns_median = 0;
  int shots = 0, failed = 0, degenerate = 0, resampled = 0, tiles = 0, map_miss = 0;
  double mean_aided = 0, mean_unaided = 0, final_unaided = 0, final_aided = 0;
};

FlightResult fly(const RouteMap& map, const FlightConfig& cfg);

}  // namespace ggins::coldatom
