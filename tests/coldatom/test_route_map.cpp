// The route map of Phillips' flight. Independent checks: the synthetic terrain
// field's rms at 3000 m against the continuous spectral integral of the model
// (Parseval, polar coordinates, not the FFT grid); the normal field's vertical
// gradient at 3000 m against 2 GM / r^3 (spherical approximation, 0.5 %); a
// position off the corridor has no value.
#include <cmath>
#include <cstdio>

#include "check.hpp"
#include "ggins/coldatom/route_map.hpp"

using namespace ggins::coldatom;

int main() {
  RouteMapParams mp;
  mp.with_egm96 = false;  // normal field + terrain: no coefficient file needed
  RouteMap map(mp, "", "");
  // Parseval: <Gzz^2> / <h^2> = int P(k) hp(k) (2 pi G rho k e^{-kd})^2 k dk / int P(k) hp(k) k dk,
  // P = k^-3, hp = x^4/(1+x^4), x = k / kmin; k from 2 pi / (domain) to the grid Nyquist.
  const double G = 6.674e-11, d = mp.h - mp.topo_mean, kmin = 2 * M_PI / mp.topo_highpass;
  const double k0 = 2 * M_PI / 1.2e6, k1 = M_PI / mp.topo_step;
  double num = 0, den = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {  // log-spaced midpoint rule
    const double a = std::log(k0) + (std::log(k1) - std::log(k0)) * (i + 0.5) / n;
    const double k = std::exp(a), dk = k * (std::log(k1) - std::log(k0)) / n;
    const double x4 = std::pow(k / kmin, 4), p = std::pow(k, -3) * x4 / (1 + x4);
    const double tf = 2 * M_PI * G * mp.rho * k * std::exp(-k * d);
    num += p * tf * tf * k * dk;
    den += p * k * dk;
  }
  const double rms_pred = mp.topo_rms * std::sqrt(num / den);
  std::printf("terrain Gamma_zz rms at %.0f m: %.2f E (spectral integral %.2f E)\n", mp.h, map.topo_gzz_rms() * 1e9,
              rms_pred * 1e9);
  CHECK(std::fabs(map.topo_gzz_rms() / rms_pred - 1) < 0.15, "terrain rms %g vs %g", map.topo_gzz_rms(), rms_pred);
  // sea: no terrain; normal gradient ~ 2GM/r^3 (+ J2 and latitude terms < 0.5 %)
  double lat, lon, g;
  map.route_point(0.39 * map.length(), 0, &lat, &lon);  // over the Channel (~50 N)
  CHECK(!map.land(lat), "0.39 L should be over the Channel (lat %g)", lat * 180 / M_PI);
  CHECK(map.gzz(lat, lon, mp.h, &g), "map lookup");
  const double r = 6371000.0 + mp.h, g2 = 2 * 3.986004418e14 / (r * r * r);
  CHECK(std::fabs(g / g2 - 1) < 5e-3, "normal gradient %g vs 2GM/r^3 %g", g, g2);
  CHECK(!map.gzz(lat + 1.0 * M_PI / 180, lon + 1.0 * M_PI / 180, mp.h, &g), "off the corridor must fail");

  std::printf(g_fail ? "coldatom.route_map: %d FAILED\n" : "coldatom.route_map: all passed\n", g_fail);
  return g_fail ? 1 : 0;
}
