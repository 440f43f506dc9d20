#include "ggins/gravity/wgs84.hpp"

#include <cmath>

#include "ggins/gravity/ldmath.hpp"

namespace ggins::gravity::wgs84 {

Vec3 geodetic_to_ecef(Real lat, Real lon, Real h) {
  const Real s = std::sin(lat), c = std::cos(lat);
  const Real n = kA / std::sqrt(1.0L - kE2 * s * s);  // prime-vertical radius
  return Vec3((n + h) * c * std::cos(lon), (n + h) * c * std::sin(lon), (n * (1.0L - kE2) + h) * s);
}

void ecef_to_geodetic(const Vec3& r, Real& lat, Real& lon, Real& h) {
  const Real p = std::hypot(r.x(), r.y());
  lon = std::atan2(r.y(), r.x());
  // start: Bowring's formula (Survey Review 23(181), 1976), from the reduced
  // latitude beta of the h = 0 solution; ~1e-11 rad at aircraft heights
  const Real za = r.z() * kA, pb = p * kB, nb = std::hypot(za, pb);
  const Real sb = nb > 0 ? za / nb : 0, cb = nb > 0 ? pb / nb : 1;
  lat = std::atan2(r.z() + kE2 / (1.0L - kE2) * kB * sb * sb * sb, p - kE2 * kA * cb * cb * cb);
  // then the fixed point lat = atan2(z + e^2 N sin(lat), p) (contraction ~e^2 per step)
  Real s, c;
  for (int it = 0; it < 30; ++it) {
    sincos_ld(lat, s, c);
    const Real n = kA / std::sqrt(1.0L - kE2 * s * s);
    const Real next = std::atan2(r.z() + kE2 * n * s, p);
    const bool done = std::fabs(next - lat) < 1e-19L;
    lat = next;
    if (done) break;
  }
  sincos_ld(lat, s, c);
  const Real n = kA / std::sqrt(1.0L - kE2 * s * s);
  h = (std::fabs(c) > 1e-3L) ? p / c - n : r.z() / s - n * (1.0L - kE2);
}

void radii(Real lat, Real& m, Real& n) {
  const Real s = std::sin(lat), w = 1 - kE2 * s * s;
  n = kA / std::sqrt(w);
  m = kA * (1 - kE2) / (w * std::sqrt(w));
}

Mat3 enu_to_ecef(Real lat, Real lon) {
  const Real sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  Mat3 c;
  c << -so, -sl * co, cl * co,
        co, -sl * so, cl * so,
        0.0L, cl, sl;
  return c;
}

}  // namespace ggins::gravity::wgs84
