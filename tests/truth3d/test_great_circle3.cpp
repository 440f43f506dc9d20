// The great-circle trajectory of the 3-D generator (GreatCircle3, Taylor jets)
// against its closed form written out here:
//   r_e = rho (c u + s w),  v_e = V (-s u + c w),  a_e = -(V^2 / rho) (c u + s w),  phi = V t / rho;
//   strapdown C_b_e = [t^, -n, -r^],  omega_b = C_b_e^T (omega_ie z + (V / rho) n),
//             omega_b' = C_b_e^T omega_ie (V / rho) (z x n);
//   stabilized C_b_i = [w, -n, -u] constant, omega_b = 0;
//   r_i = R3(omega_ie t) r_e, the Earth rate the trajectory's own (0: non-rotating).
#include <cmath>
#include <cstdio>

#include "ggins/truth3d/trajectory3d.hpp"

using namespace ggins::truth3d;

#include "../truth/check.hpp"

static void run(Attitude att, Real wie) {
  GreatCircleParams p;
  p.radius_m = 6378137.0L;
  p.height_m = 3000.0L;
  p.lat0 = 0.7L;
  p.lon0 = 0.2L;
  p.heading = 0.6L;
  p.speed_mps = 250.0L;
  p.omega_ie = wie;
  const GreatCircle3 g(p, att);
  const Real rho = p.radius_m + p.height_m, V = p.speed_mps, wg = V / rho;
  const Vec3 u(std::cos(p.lat0) * std::cos(p.lon0), std::cos(p.lat0) * std::sin(p.lon0), std::sin(p.lat0));
  const Vec3 north(-std::sin(p.lat0) * std::cos(p.lon0), -std::sin(p.lat0) * std::sin(p.lon0), std::cos(p.lat0));
  const Vec3 east(-std::sin(p.lon0), std::cos(p.lon0), 0);
  const Vec3 w = std::cos(p.heading) * north + std::sin(p.heading) * east, n = u.cross(w), z(0, 0, 1);
  Real er = 0, ev = 0, ea = 0, eC = 0, ew = 0, ewd = 0, eri = 0;
  for (Real t : {0.0L, 17.5L, 600.0L, 3599.0L}) {
    const State3 s = g.at(t);
    const Real c = std::cos(wg * t), sn = std::sin(wg * t);
    const Vec3 rh = c * u + sn * w, th = -sn * u + c * w;
    er = std::max(er, (s.r_e - rho * rh).norm());
    ev = std::max(ev, (s.v_e - V * th).norm());
    ea = std::max(ea, (s.a_e + V * wg * rh).norm());
    Mat3 C;
    Vec3 om = Vec3::Zero(), omd = Vec3::Zero();
    const Real th_e = wie * t;
    Mat3 R3;
    R3 << std::cos(th_e), -std::sin(th_e), 0, std::sin(th_e), std::cos(th_e), 0, 0, 0, 1;
    if (att == Attitude::Coordinated) {
      C.col(0) = th;
      C.col(1) = -n;
      C.col(2) = -rh;
      om = C.transpose() * (wie * z + wg * n);
      omd = C.transpose() * (wie * wg * z.cross(n));
    } else {
      Mat3 C0;
      C0.col(0) = w;
      C0.col(1) = -n;
      C0.col(2) = -u;
      C = R3.transpose() * C0;
    }
    eC = std::max(eC, (s.C_b_e - C).norm());
    ew = std::max(ew, (s.omega_b - om).norm());
    ewd = std::max(ewd, (s.omega_dot_b - omd).norm());
    eri = std::max(eri, (s.r_i - R3 * s.r_e).norm());
  }
  const char* k = att == Attitude::Coordinated ? "strapdown" : "stabilized";
  CHECK(er < 1e-8L && ev < 1e-12L && ea < 1e-15L, "%s, omega_ie %.3Lg: r, v, a = closed form (%.1Lg m, %.1Lg m/s, %.1Lg m/s^2)",
        k, wie, er, ev, ea);
  CHECK(eC < 1e-15L, "%s: C_b_e = closed form (%.1Lg)", k, eC);
  CHECK(ew < 1e-19L && ewd < 1e-22L, "%s: omega_b, omega_b' = closed form (%.1Lg rad/s, %.1Lg rad/s^2)", k, ew, ewd);
  CHECK(eri < 1e-8L, "%s: r_i = R3(omega_ie t) r_e with the trajectory's own Earth rate (%.1Lg m)", k, eri);
}

int main() {
  run(Attitude::Coordinated, kOmegaIe);
  run(Attitude::Stabilized, kOmegaIe);
  run(Attitude::Coordinated, 0.0L);
  run(Attitude::Stabilized, 0.0L);
  std::printf("%s (%d failures)\n", g_fail ? "FAILED" : "all passed", g_fail);
  return g_fail ? 1 : 0;
}
