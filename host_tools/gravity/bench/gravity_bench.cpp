// Benchmark of the gravity models (not a test): microseconds per evaluation
// (potential + G + Gamma) for each model, and the fast paths along a flight
// of 6 accelerometers at 100 Hz, with the machine it ran on.
//   ggins_gravity_bench [--egm96 data/egm96_to360.ascii.txt] [--km 20]
#include "ggins/gravity/composite.hpp"
#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>

using namespace ggins::gravity;
using Clock = std::chrono::steady_clock;

namespace {

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  for (std::string l; std::getline(f, l);)
    if (l.rfind("model name", 0) == 0) return l.substr(l.find(':') + 2);
  return "unknown";
}

volatile double g_sink = 0;

// Best of 3 runs of n evaluations at points cycling through a small set.
double us_per_eval(const Field& f, const std::vector<Vec3>& pts, int n) {
  double best = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    const auto t0 = Clock::now();
    double acc = 0;
    for (int i = 0; i < n; ++i) acc += static_cast<double>(f.eval(pts[i % pts.size()]).gamma(0, 0));
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / n;
    g_sink = g_sink + acc;
    best = std::min(best, us);
  }
  return best;
}

// A flight: straight and level at 170 m/s, 100 Hz, six accelerometers at
// +-0.5 m along the local axes. Returns total seconds and evaluations.
struct FlightCost { double seconds; long evals; };
FlightCost fly(const Field& f, Real lat, Real lon, Real h, Real km) {
  const Vec3 c = wgs84::geodetic_to_ecef(lat, lon, h);
  const Mat3 enu = wgs84::enu_to_ecef(lat, lon);
  const Vec3 dir = enu.col(1);  // north
  const long steps = static_cast<long>(km * 1000 / 1.7L);
  const Vec3 off[6] = {0.5L * enu.col(0), -0.5L * enu.col(0), 0.5L * enu.col(1), -0.5L * enu.col(1), 0.5L * enu.col(2), -0.5L * enu.col(2)};
  const auto t0 = Clock::now();
  double acc = 0;
  for (long k = 0; k < steps; ++k) {
    const Vec3 p = c + (1.7L * k) * dir;
    for (const Vec3& o : off) acc += static_cast<double>(f.eval(p + o).g.x());
  }
  g_sink = g_sink + acc;
  return {std::chrono::duration<double>(Clock::now() - t0).count(), steps * 6};
}

}  // namespace

int main(int argc, char** argv) {
  std::string egm = "data/egm96_to360.ascii.txt";
  Real km = 20;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--egm96")) egm = argv[i + 1];
    else if (!std::strcmp(argv[i], "--km")) km = std::stold(argv[i + 1]);
  }
  std::printf("machine: %s, %u hardware threads; compiler %s; long double %zu bytes\n", cpu_model().c_str(),
              std::thread::hardware_concurrency(), __VERSION__, sizeof(long double));
  const Real lat = 35.5L * M_PI / 180, lon = -82.5L * M_PI / 180;
  std::vector<Vec3> pts;
  for (int i = 0; i < 16; ++i) pts.push_back(wgs84::geodetic_to_ecef(lat + 1e-4L * i, lon - 2e-4L * i, 3000 + 10.0L * i));

  std::printf("\n%-58s %12s\n", "model (potential + G + Gamma, single thread)", "us/eval");
  const PointMassField pm;
  std::printf("%-58s %12.3f\n", "spherical point mass", us_per_eval(pm, pts, 200000));
  const auto normal = std::make_shared<NormalField>();
  std::printf("%-58s %12.3f\n", "WGS-84 normal (closed form, AD)", us_per_eval(*normal, pts, 100000));

  RwAnomalyConfig cfg;
  cfg.lat0 = lat; cfg.lon0 = lon;
  const auto rw = std::make_shared<PointMassAnomalyField>(make_rubenstein_winter_field(cfg));
  char label[128];
  std::snprintf(label, sizeof label, "R&W point-mass anomalies, direct sum (%zu masses)", rw->masses().size());
  std::printf("%-58s %12.3f\n", label, us_per_eval(*rw, pts, 50));

  LatticeOptions pmo;
  pmo.spacing = 1000; pmo.points = 12; pmo.origin = wgs84::geodetic_to_ecef(lat, lon, 0);
  const auto split = std::make_shared<SplitPointMassField>(rw->masses(), 8000, pmo);
  const FastField fast_pm(normal, split);
  (void)us_per_eval(fast_pm, pts, 16);  // build the nodes around the points
  std::printf("%-58s %12.3f\n", "fast: normal + split point masses (sigma 8 km, h 1 km, p 12)", us_per_eval(fast_pm, pts, 20000));

  const bool have_egm = static_cast<bool>(std::ifstream(egm));
  std::shared_ptr<SphericalHarmonicField> sh;
  std::shared_ptr<FastField> fast_sh;
  if (have_egm) {
    for (int n : {70, 180, 360}) {
      const SphericalHarmonicField f(read_nasa_ascii(egm, kEgm96Gm, kEgm96A, n), n);
      std::snprintf(label, sizeof label, "EGM96 spherical harmonics, degree %d", n);
      std::printf("%-58s %12.1f\n", label, us_per_eval(f, pts, n == 360 ? 30 : 200));
    }
    sh = std::make_shared<SphericalHarmonicField>(read_nasa_ascii(egm), 360);
    const auto anomaly = std::make_shared<SphericalHarmonicField>(subtract_normal(sh->coefficients()), 360, 2, ShPrecision::Double);
    std::printf("%-58s %12.1f\n", "EGM96-360 minus normal, double precision (lattice node)", us_per_eval(*anomaly, pts, 30));
    LatticeOptions o;
    o.spacing = 2500; o.points = 8;
    fast_sh = std::make_shared<FastField>(normal, anomaly, o);
    (void)us_per_eval(*fast_sh, pts, 16);
    std::printf("%-58s %12.3f\n", "fast: normal + EGM96-360 disturbance lattice (h 2.5 km, p 8)", us_per_eval(*fast_sh, pts, 20000));
  } else {
    std::printf("(EGM96 file %s absent: SH rows skipped; run scripts/fetch-egm96)\n", egm.c_str());
  }

  std::printf("\nflight: %.0Lf km north at 170 m/s, 100 Hz, 6 accelerometers (node building included)\n", km);
  {
    const auto before = split->lattice().nodes_computed();
    const FlightCost c = fly(fast_pm, lat + 0.01L, lon, 3000, km);
    const auto nodes = split->lattice().nodes_computed() - before;
    std::printf("  split point masses: %.2f s, %.3f us/eval amortised, %zu lattice nodes built (%.0f nodes/km)\n", c.seconds,
                1e6 * c.seconds / c.evals, nodes, nodes / static_cast<double>(km));
    const auto t0 = Clock::now();
    ErfPointMassField erf(std::make_shared<const std::vector<PointMass>>(rw->masses()), 8000);
    (void)erf.eval(pts[0]);
    std::printf("  (one lattice node = long-range sum over all masses: %.0f us)\n",
                std::chrono::duration<double, std::micro>(Clock::now() - t0).count());
  }
  if (fast_sh) {
    const auto& lat_f = static_cast<const LatticeField&>(fast_sh->anomaly());
    const auto before = lat_f.nodes_computed();
    const FlightCost c = fly(*fast_sh, lat + 0.05L, lon, 3000, km);
    const auto nodes = lat_f.nodes_computed() - before;
    std::printf("  EGM96-360 lattice: %.2f s, %.3f us/eval amortised, %zu lattice nodes built (%.0f nodes/km)\n", c.seconds,
                1e6 * c.seconds / c.evals, nodes, nodes / static_cast<double>(km));
  }
  return 0;
}
