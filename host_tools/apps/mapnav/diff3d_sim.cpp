// See diff3d_sim.hpp.
#include "diff3d_sim.hpp"

#include <cmath>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::mapnav {

using gravity::Mat3;
using gravity::Real;
using gravity::Vec3;

void diff3d_readings(const gravity::Field& field, const Diff3dTruth& t, double half_base,
                     const double (*noise)[3], const double omega_removal[3], gg_diff3d_input_t& in) {
  const Real sl = std::sin(static_cast<Real>(t.lat)), cl = std::cos(static_cast<Real>(t.lat));
  const Real so = std::sin(static_cast<Real>(t.lon)), co = std::cos(static_cast<Real>(t.lon));
  Mat3 cne;  // C_n_e: rows north, east, down in ECEF (v_n = cne v_e)
  cne << -sl * co, -sl * so, cl, -so, co, 0, -cl * co, -cl * so, -sl;
  const Real w = t.q_b_n[0], x = t.q_b_n[1], y = t.q_b_n[2], z = t.q_b_n[3];
  const Real nq = std::sqrt(w * w + x * x + y * y + z * z);
  const Real qw = w / nq, qx = x / nq, qy = y / nq, qz = z / nq;
  Mat3 cbn;
  cbn << 1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy),
      2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx),
      2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy);
  const Mat3 cbe = cne.transpose() * cbn;
  const Vec3 rc = gravity::wgs84::geodetic_to_ecef(t.lat, t.lon, t.h);
  const Vec3 gc = field.eval(rc).g;
  const Vec3 W(t.omega_b[0], t.omega_b[1], t.omega_b[2]);
  const Vec3 Wd(t.omega_dot_b[0], t.omega_dot_b[1], t.omega_dot_b[2]);
  const Vec3 fc(t.f_c[0], t.f_c[1], t.f_c[2]);
  for (int j = 0; j < 6; ++j) {
    Vec3 d = Vec3::Zero();
    d(j % 3) = (j < 3 ? 1 : -1) * static_cast<Real>(half_base);
    const Vec3 rj = rc + cbe * d;
    const Vec3 dg = cbe.transpose() * (field.eval(rj).g - gc);
    const Vec3 f = fc + Wd.cross(d) + W.cross(W.cross(d)) - dg;
    for (int i = 0; i < 3; ++i) {
      const Real fi = f(i) + (noise ? static_cast<Real>(noise[j][i]) : 0.0L);
      in.f[j][i] = static_cast<double>(fi);
      in.f_lo[j][i] = static_cast<double>(fi - static_cast<Real>(in.f[j][i]));
    }
  }
  for (int i = 0; i < 3; ++i) in.omega_b[i] = omega_removal[i];
}

gg_status_t diff3d_gamma6(const gg_diff3d_input_t& in, double half_base, double g6[6], gg_diff3d_output_t* out) {
  gg_diff3d_config_t cfg{};
  for (int k = 0; k < 3; ++k) cfg.half_base_m[k] = half_base;
  gg_diff3d_t st{};
  gg_status_t s = gg_diff3d_init(&st, &cfg);
  if (s != GG_OK) return s;
  gg_diff3d_output_t o{};
  s = gg_diff3d_step(&st, &in, &o);
  if (s != GG_OK) return s;
  const int ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 6; ++k) g6[k] = static_cast<double>(o.gamma[ij[k][0]][ij[k][1]]);
  if (out) *out = o;
  return GG_OK;
}

}  // namespace ggins::mapnav
