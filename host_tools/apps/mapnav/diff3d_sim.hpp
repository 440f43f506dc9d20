// ggins mapnav --gradiometer diff3d: the strapdown gradiometer as the
// firmware's own six tri-axis accelerometers (diff3d.h layout: sensor k at
// +d_k, sensor k+3 at -d_k, d_k = half_base along body axis k).
//
// Readings from rigid-body kinematics and the field at every sensor: with the
// centre's true specific force f_c (body axes), the inertial body rate Omega
// and angular acceleration Omega' (body axes), the body-to-ECEF rotation
// C_b_e = C_n_e^T C_b_n (C_n_e rows = north, east, down in ECEF as in
// gmap_gen.hpp) and the centre r_c (ECEF), sensor j at r_j = r_c + C_b_e d_j reads
//   f_j = f_c + Omega' x d_j + Omega x (Omega x d_j) - C_b_e^T (G_e(r_j) - G_e(r_c)) + n_j,
// evaluated in long double and handed to gg_diff3d as a double plus its
// sub-ulp residual (hi/lo). n_j: white noise, N(0, sigma_a) per axis.
//
// Noise of the differenced tensor (derived): Gamma_kk = [Omega x]^2_kk - M_kk,
// M_kk = (f_k,k - f_k+3,k) / 2a  ->  sigma_diag = sigma_a sqrt(2) / (2a);
// Gamma_xy = [..] - (M_xy + M_yx)/2 with four independent readings ->
// sigma_off = sigma_a / (2a) = sigma_diag / sqrt(2). The six components are
// uncorrelated (each uses its own reading axes). mapnav sets
// sigma_a = sqrt(2) a sigma_Gamma so that the diagonal matches the direct mode.
#pragma once

#include "ggins/gravity/field.hpp"

extern "C" {
#include "ggins/diff3d.h"
}

namespace ggins::mapnav {

struct Diff3dTruth {
  double lat = 0, lon = 0, h = 0;        // geodetic, rad, m
  double q_b_n[4] = {1, 0, 0, 0};        // body -> NED quaternion, scalar first
  double f_c[3] = {0, 0, 0};             // true centre specific force, body axes, m/s^2
  double omega_b[3] = {0, 0, 0};         // true inertial body rate, rad/s
  double omega_dot_b[3] = {0, 0, 0};     // true angular acceleration, rad/s^2
};

// Fills in.f / in.f_lo (six sensors) from the truth; noise[j][i] (m/s^2) is
// added when non-null; in.omega_b is set to omega_removal (the rate diff3d
// uses to remove [Omega x]^2: the true one or the gyro's).
void diff3d_readings(const gravity::Field& field, const Diff3dTruth& t, double half_base,
                     const double (*noise)[3], const double omega_removal[3], gg_diff3d_input_t& in);

// gg_diff3d on the readings; g6 = Gamma_b in the order mmukf expects
// (xx, yy, zz, xy, xz, yz). Returns the firmware's status.
gg_status_t diff3d_gamma6(const gg_diff3d_input_t& in, double half_base, double g6[6],
                          gg_diff3d_output_t* out = nullptr);

}  // namespace ggins::mapnav
