// Route map and flights (short). Independent checks: the synthetic terrain
// field's rms at 3000 m against the continuous spectral integral of the model
// (Parseval, polar coordinates, not the FFT grid); the normal field's vertical
// gradient at 3000 m against 2 GM / r^3 (spherical approximation, 0.5 %); then
// the INS error model against the Schuler closed forms; behaviour: with a perfect INS and a near-noise-free sensor the filter holds
// the position (< 100 m mean over 1500 s); with the Table I INS the aided
// error is below the unaided error over 3000 s.
#include <cmath>
#include <cstdio>

#include "check.hpp"
#include "ggins/coldatom/flight.hpp"
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

  // INS error model against closed forms (Earth rate 0, no noise, no PF):
  // accelerometer bias b on every body axis -> horizontal |df| = sqrt2 b for any heading,
  //   |dr| = sqrt2 b / w_s^2 (1 - cos w_s t)                     (Schuler, psi stays 0)
  // gyro bias e on every body axis -> horizontal |eps| = sqrt2 e,
  //   |dr| = sqrt2 e R (t - sin(w_s t) / w_s)                   (psi = eps t through the Schuler loop)
  {
    const double R = 6371000.0 + mp.h, ws = std::sqrt(9.80665 / R);
    FlightConfig f0;
    f0.duration = 3600; f0.run_pf = false; f0.use_gmap = false; f0.alt_noise = 0;
    f0.ins = InsErrorParams{30e-6, 0, 0, 0, 0, 0, 0, 0, 0.1, false, 0.0};
    const FlightResult ra = fly(map, f0);
    f0.ins = InsErrorParams{0, 0, 0, 0, 0.05e-6, 0, 0, 0, 0.1, false, 0.0};
    const FlightResult rg = fly(map, f0);
    double wa = 0, wg = 0;
    for (std::size_t j = 0; j < ra.t.size(); ++j) {
      const double t = ra.t[j];
      const double da = std::sqrt(2.0) * 30e-6 * 9.80665 / (ws * ws) * (1 - std::cos(ws * t));
      const double dg = std::sqrt(2.0) * 0.05e-6 * R * (t - std::sin(ws * t) / ws);
      wa = std::fmax(wa, std::fabs(ra.err_unaided[j] - da) / (std::sqrt(2.0) * 30e-6 * 9.80665 / (ws * ws)));
      if (t > 600) wg = std::fmax(wg, std::fabs(rg.err_unaided[j] / dg - 1));
    }
    std::printf("INS model vs closed form over 1 h: accelerometer bias worst %.2f %% of b/w_s^2, gyro bias worst %.2f %%\n",
                100 * wa, 100 * wg);
    CHECK(wa < 0.02, "accelerometer-bias response off the Schuler closed form by %g", wa);
    CHECK(wg < 0.03, "gyro-bias response off the closed form by %g", wg);
  }

  FlightConfig fc;
  fc.duration = 1500;
  fc.grad.n_atoms = 1e7;
  fc.ins = InsErrorParams{0, 0, 0, 0, 0, 0, 0, 0, 0.1};
  FlightResult a = fly(map, fc);
  std::printf("perfect INS, 1e7 atoms: mean aided error %.1f m over %.0f s; PF step %.0f us\n", a.mean_aided,
              a.t.back(), a.pf_step_ns_median / 1e3);
  CHECK(a.mean_unaided == 0.0, "perfect INS drifted");
  CHECK(a.mean_aided < 100.0, "filter does not hold the position: %g m", a.mean_aided);
  FlightConfig fb;
  fb.duration = 3000;
  FlightResult b = fly(map, fb);
  std::printf("Table I INS: mean aided %.0f m, unaided %.0f m (final %.0f / %.0f m)\n", b.mean_aided, b.mean_unaided,
              b.final_aided, b.final_unaided);
  CHECK(b.mean_aided < b.mean_unaided, "aided %g not below unaided %g", b.mean_aided, b.mean_unaided);
  CHECK(b.final_unaided > 300.0, "unaided drift implausibly small: %g m", b.final_unaided);
  std::printf(g_fail ? "coldatom.flight: %d FAILED\n" : "coldatom.flight: all passed\n", g_fail);
  return g_fail ? 1 : 0;
}
