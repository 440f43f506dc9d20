// Errors of a 3-D navigation output (gg_nav3d_output_t, nav3d.h) against the
// 3-D truth (truth3d/generator3d.hpp) at the same step. Shared by ggins run3d
// and the direct-call closure tests (tests/integration3d).
//
//   position   dr_e = r_e(nav, hi + lo) - r_e(true), in NED at the true position (m)
//   velocity   dv_e = v_e(nav) - v_e(true) (Earth-relative), NED (m/s)
//   attitude   psi: rotation vector of C_b_e(nav) C_b_e(true)^T (ECEF), in NED (rad)
//   gravity    dG = g_e(nav, hi + lo) - G_e(true position) (the estimate against the
//              true gravitation at the TRUE position, as in the 2-D run), NED (m/s^2)
//   gradient   dGamma_e = gamma_e(nav) - Gamma_e(true position), ECEF; and the body-axis
//              tensor gamma_b(nav) - C_e_b Gamma_e C_b_e: largest |element| (s^-2)
//   height     h(nav) - h(true) (m)
#pragma once

#include <algorithm>
#include <cmath>

extern "C" {
#include "ggins/nav3d.h"
#include "ggins/quat.h"
}
#include "ggins/truth3d/generator3d.hpp"

namespace ggins::run3d {

using truth3d::Mat3;
using truth3d::Real;
using truth3d::Vec3;

struct Errors3 {
  Vec3 dr_n = Vec3::Zero(), dv_n = Vec3::Zero(), psi_n = Vec3::Zero(), dg_n = Vec3::Zero();
  Real dr = 0, dv = 0, psi = 0, dg = 0;
  Real dgamma_e = 0;  // max |element| of gamma_e(nav) - Gamma_e(true), s^-2
  Real dgamma_b = 0;  // same in body axes
  Real dh = 0;
};

// The DCM of the task's published quaternion (firmware quat.h).
inline Mat3 dcm_from_quat(const double q[4]) {
  const gg_real_t ql[4] = {q[0], q[1], q[2], q[3]};
  gg_real_t c[3][3];
  gg_quat_to_dcm(ql, c);
  Mat3 C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C(i, j) = c[i][j];
  return C;
}

// Rotation vector of a rotation matrix near the identity (|angle| < pi).
inline Vec3 rotation_vector(const Mat3& R) {
  const Vec3 v(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const Real s = v.norm() / 2, c = (R.trace() - 1) / 2;
  if (s < 1e-30L) return v / 2;
  return v * (std::atan2(s, c) / (2 * s));
}

inline Errors3 compare(const truth3d::Truth3& t, const gg_nav3d_output_t& o) {
  Errors3 e;
  const Mat3 C_n_e = truth3d::ned_to_ecef(t.s.lat, t.s.lon);
  const Mat3 C_e_n = C_n_e.transpose();
  Vec3 r, v, g;
  Mat3 ge, gb;
  for (int i = 0; i < 3; ++i) {
    r(i) = static_cast<Real>(o.r_e[i]) + static_cast<Real>(o.r_e_lo[i]);
    v(i) = o.v_e[i];
    g(i) = static_cast<Real>(o.g_e[i]) + static_cast<Real>(o.g_e_lo[i]);
    for (int j = 0; j < 3; ++j) {
      ge(i, j) = o.gamma_e[i][j];
      gb(i, j) = o.gamma_b[i][j];
    }
  }
  e.dr_n = C_e_n * (r - t.s.r_e);
  e.dv_n = C_e_n * (v - t.s.v_e);
  e.dg_n = C_e_n * (g - t.g_e);
  const Mat3 Cn = dcm_from_quat(o.q_b_e);
  e.psi_n = C_e_n * rotation_vector(Cn * t.s.C_b_e.transpose());
  e.dr = e.dr_n.norm();
  e.dv = e.dv_n.norm();
  e.dg = e.dg_n.norm();
  e.psi = e.psi_n.norm();
  e.dgamma_e = (ge - t.gamma_e).cwiseAbs().maxCoeff();
  e.dgamma_b = (gb - t.gamma_b).cwiseAbs().maxCoeff();
  e.dh = static_cast<Real>(o.h_m) - t.s.h;
  return e;
}

}  // namespace ggins::run3d
