#include "ggins/gravity/wgs84.hpp"

#include <cmath>

namespace ggins::gravity::wgs84 {

Vec3 geodetic_to_ecef(Real lat, Real lon, Real h) {
  const Real s = std::sin(lat), c = std::cos(lat);
  const Real n = kA / std::sqrt(1.0L - kE2 * s * s);  // prime-vertical radius
  return Vec3((n + h) * c * std::cos(lon), (n + h) * c * std::sin(lon), (n * (1.0L - kE2) + h) * s);
}

void ecef_to_geodetic(const Vec3& r, Real& lat, Real& lon, Real& h) {
  const Real p = std::hypot(r.x(), r.y());
  lon = std::atan2(r.y(), r.x());
  lat = std::atan2(r.z(), p * (1.0L - kE2));
  for (int it = 0; it < 30; ++it) {
    const Real s = std::sin(lat);
    const Real n = kA / std::sqrt(1.0L - kE2 * s * s);
    const Real next = std::atan2(r.z() + kE2 * n * s, p);
    const bool done = std::fabs(next - lat) < 1e-19L;
    lat = next;
    if (done) break;
  }
  const Real s = std::sin(lat), c = std::cos(lat);
  const Real n = kA / std::sqrt(1.0L - kE2 * s * s);
  h = (std::fabs(c) > 1e-3L) ? p / c - n : r.z() / s - n * (1.0L - kE2);
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
