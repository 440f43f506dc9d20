// Benchmark of the gravity models (not a test): CPU microseconds per evaluation
// (potential + G + Gamma) for each model, and the fast paths along a flight
// of 6 accelerometers at 100 Hz, with the machine it ran on.
//   ggins_gravity_bench [--egm96 data/egm96_to360.ascii.txt] [--km 20]
#include <CLI/CLI.hpp>
#include "ggins/gravity/composite.hpp"
#include "ggins/gravity/lattice.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>

using namespace ggins::gravity;
// Thread CPU time, not wall time: the machine is shared, and CPU time of this
// (single-threaded) benchmark is what the evaluation costs.
double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

namespace {

std::string loadavg() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

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
    const double t0 = cpu_s();
    double acc = 0;
    for (int i = 0; i < n; ++i) acc += static_cast<double>(f.eval(pts[i % pts.size()]).gamma(0, 0));
    const double us = 1e6 * (cpu_s() - t0) / n;
    g_sink = g_sink + acc;
    best = std::min(best, us);
  }
  return best;
}

double us_per_g(const Field& f, const std::vector<Vec3>& pts, int n) {  // gravitation() alone
  double best = 1e300;
  for (int rep = 0; rep < 3; ++rep) {
    const double t0 = cpu_s();
    double acc = 0;
    for (int i = 0; i < n; ++i) acc += static_cast<double>(f.gravitation(pts[i % pts.size()]).x());
    best = std::min(best, 1e6 * (cpu_s() - t0) / n);
    g_sink = g_sink + acc;
  }
  return best;
}

// A flight: straight and level at 170 m/s, 100 Hz, six accelerometers at
// +-0.5 m along the local axes. generator = true calls the field as the 3-D
// truth generator does (truth3d/src/generator3d.cpp: eval() at the body
// centre for G and Gamma, gravitation() at each accelerometer); false calls
// eval() at the six accelerometers only. Returns total seconds and steps.
struct FlightCost { double seconds; long steps; };
FlightCost fly(const Field& f, Real lat, Real lon, Real h, Real km, bool generator, Real start_km = 0) {
  const Vec3 c = wgs84::geodetic_to_ecef(lat, lon, h);
  const Mat3 enu = wgs84::enu_to_ecef(lat, lon);
  const Vec3 dir = enu.col(1);  // north
  const long steps = static_cast<long>(km * 1000 / 1.7L), k0 = static_cast<long>(start_km * 1000 / 1.7L);
  const Vec3 off[6] = {0.5L * enu.col(0), -0.5L * enu.col(0), 0.5L * enu.col(1), -0.5L * enu.col(1), 0.5L * enu.col(2), -0.5L * enu.col(2)};
  const double t0 = cpu_s();
  double acc = 0;
  for (long k = k0; k < k0 + steps; ++k) {
    const Vec3 p = c + (1.7L * k) * dir;
    if (generator) {
      acc += static_cast<double>(f.eval(p).gamma(0, 0));
      for (const Vec3& o : off) acc += static_cast<double>(f.gravitation(p + o).x());
    } else {
      for (const Vec3& o : off) acc += static_cast<double>(f.eval(p + o).g.x());
    }
  }
  g_sink = g_sink + acc;
  return {cpu_s() - t0, steps};
}

}  // namespace

int main(int argc, char** argv) {
  std::string egm = "data/egm96_to360.ascii.txt";
  double km_d = 20;
  CLI::App app{"ggins_gravity_bench: evaluation time of the gravity models (potential, gravitation and\n"
               "gradient; single thread), with the machine, compiler and load average it ran on."};
  app.add_option("--egm96", egm, "EGM96 coefficient file (scripts/fetch-egm96)")->capture_default_str();
  app.add_option("--km", km_d, "along-track distance of the moving-point benchmarks, km")
      ->check(CLI::Range(0.001, 1e5))->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  const Real km = static_cast<Real>(km_d);
  std::printf("machine: %s, %u hardware threads; compiler %s; long double %zu bytes; load average at start %s\n",
              cpu_model().c_str(), std::thread::hardware_concurrency(), __VERSION__, sizeof(long double), loadavg().c_str());
  const Real lat = 35.5L * M_PI / 180, lon = -82.5L * M_PI / 180;
  std::vector<Vec3> pts;  // 16 points spread over ~10 km (exact models)
  for (int i = 0; i < 16; ++i) pts.push_back(wgs84::geodetic_to_ecef(lat + 1e-4L * i, lon - 2e-4L * i, 3000 + 10.0L * i));
  std::vector<Vec3> acc;  // six accelerometers at +-0.5 m around one centre (fast paths, steady state in one cell)
  {
    const Vec3 c = wgs84::geodetic_to_ecef(lat, lon, 3000);
    for (int a = 0; a < 3; ++a)
      for (Real sg : {0.5L, -0.5L}) { Vec3 d = Vec3::Zero(); d[a] = sg; acc.push_back(c + d); }
  }

  std::printf("\n%-58s %12s\n", "model (potential + G + Gamma, single thread; fast paths: steady state, 6 accelerometers in one cell)", "us/eval");
  const PointMassField pm;
  std::printf("%-58s %12.3f\n", "spherical point mass", us_per_eval(pm, pts, 200000));
  const auto normal = std::make_shared<NormalField>();
  std::printf("%-58s %12.3f\n", "WGS-84 normal (closed form, AD)", us_per_eval(*normal, pts, 100000));
  std::printf("%-58s %12.3f\n", "WGS-84 normal, gravitation() only (first-order AD)", us_per_g(*normal, pts, 100000));

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
  (void)us_per_eval(fast_pm, acc, 6);  // build the nodes around the points
  std::printf("%-58s %12.3f\n", "fast: normal + split point masses (sigma 8 km, h 1 km, p 12)", us_per_eval(fast_pm, acc, 20000));

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
    {  // circle of latitude: set-up (column sums, once per circle) and each longitude
      const Vec3 p0 = wgs84::geodetic_to_ecef(lat, 0, 3000);
      for (bool dg : {false, true}) {
        const Real er = dg ? std::cos(lat) : 0, ez = dg ? std::sin(lat) : 0;
        double acc = 0, setup = 1e300, per = 1e300;
        for (int rep = 0; rep < 3; ++rep) {
          double t0 = cpu_s();
          for (int i = 0; i < 10; ++i) acc += static_cast<double>(anomaly->circle(p0.x(), p0.z(), er, ez)->eval(0.1L).g.x());
          setup = std::min(setup, 1e5 * (cpu_s() - t0));
          const auto c = anomaly->circle(p0.x(), p0.z(), er, ez);
          Mat3 d;
          t0 = cpu_s();
          for (int i = 0; i < 2000; ++i) acc += static_cast<double>(c->eval(1e-4L * i, dg ? &d : nullptr).gamma(0, 0));
          per = std::min(per, 1e6 * (cpu_s() - t0) / 2000);
        }
        g_sink = g_sink + acc;
        std::printf("%-58s %12.1f\n", dg ? "  circle of latitude with dGamma/dh: set-up + 1st longitude" : "  circle of latitude: set-up + first longitude", setup);
        std::printf("%-58s %12.3f\n", dg ? "  circle of latitude with dGamma/dh: each further longitude" : "  circle of latitude: each further longitude", per);
      }
    }
    LatticeOptions o;
    o.spacing = 2500; o.points = 8;
    fast_sh = std::make_shared<FastField>(normal, anomaly, o);
    (void)us_per_eval(*fast_sh, acc, 6);
    std::printf("%-58s %12.3f\n", "fast: normal + EGM96-360 disturbance lattice (h 2.5 km, p 8)", us_per_eval(*fast_sh, acc, 20000));
    std::printf("%-58s %12.3f\n", "  the same, gravitation() only", us_per_g(*fast_sh, acc, 20000));
  } else {
    std::printf("(EGM96 file %s absent: SH rows skipped; run scripts/fetch-egm96)\n", egm.c_str());
  }

  std::printf("\nflight north at 170 m/s, 100 Hz, 6 accelerometers at +-0.5 m, 3 km height; first km (initial\n"
              "stencil) and then %.0Lf km (steady state), node building included\n", km);
  auto report = [&](const char* what, const Field& f, const LatticeField& lf, Real la, double node_us) {
    for (bool gen : {true, false}) {
      const Real l = la + (gen ? 0 : 0.05L);  // a fresh path (no nodes shared with the other mode)
      auto n0 = lf.nodes_computed();
      const FlightCost a = fly(f, l, lon, 3000, 1, gen);
      auto n1 = lf.nodes_computed();
      const FlightCost b = fly(f, l, lon, 3000, km, gen, 1);
      auto n2 = lf.nodes_computed();
      const double per_km = (n2 - n1) / static_cast<double>(km);
      const double us_step = 1e6 * b.seconds / b.steps;
      // 10 h at 170 m/s = 6120 km = 3.6e6 steps; node building (per_km * 1.7e-3 nodes per step) counted apart
      const double build = 6120 * per_km * node_us * 1e-6, interp = 3.6e6 * (us_step - 1.7e-3 * per_km * node_us) * 1e-6;
      std::printf("  %s, %s:\n    first km %.2f s (%zu nodes); then %.3f us/step amortised, %.0f nodes/km\n", what,
                  gen ? "as the 3-D truth generator (eval at the centre + gravitation at 6 accelerometers)"
                      : "eval at the 6 accelerometers", a.seconds, n1 - n0, us_step, per_km);
      std::printf("    -> 10 h flight estimate: %.0f s (%.0f s node building at %.0f us/node + %.0f s interpolation)\n",
                  build + interp, build, node_us, interp);
    }
  };
  {
    ErfPointMassField erf(std::make_shared<const std::vector<PointMass>>(rw->masses()), 8000);
    const double node_us = us_per_eval(erf, pts, 20);
    std::printf("  (split point masses: one lattice node = long-range sum over %zu masses: %.0f us)\n", rw->masses().size(), node_us);
    report("split point masses", fast_pm, split->lattice(), lat + 0.01L, node_us);
  }
  if (fast_sh) {
    const auto& lf = static_cast<const LatticeField&>(fast_sh->anomaly());
    const SphericalHarmonicField node_field(subtract_normal(sh->coefficients()), 360, 2, ShPrecision::Double);
    const double node_us = us_per_eval(node_field, pts, 20);
    report("EGM96-360 lattice", *fast_sh, lf, lat + 0.05L, node_us);
  }
  std::printf("load average at end %s\n", loadavg().c_str());
  return 0;
}
