// Helper for the pyshtools comparisons and the field benchmark (not a test by
// itself): evaluates a spherical-harmonic model at points read from stdin
// ("x y z" in metres, Earth-fixed) and prints "V gx gy gz Gxx Gxy Gxz Gyy Gyz Gzz".
//   gravity_eval_points MODEL NMAX [--prec ld|double|mixed|cunningham] [--reps K] [--dump FILE]
// MODEL: an ICGEM file (*.gfc), "kaula:SEED" (synthetic_kaula) or a NASA/NGA
// ASCII file (EGM96 GM and radius). --reps K: evaluate all points K times and
// print the best thread-CPU time per point on stderr ("cpu_us_per_point X").
// --dump FILE: write nmax (int32), GM, a, then C and S (index n(n+1)/2+m) as doubles.
#include "ggins/gravity/spherical_harmonic.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <iostream>
#include <string>
#include <vector>

using namespace ggins::gravity;

static double cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s MODEL NMAX [--prec ld|double|mixed|cunningham] [--reps K] [--dump FILE] < points\n", argv[0]);
    return 2;
  }
  const std::string model = argv[1];
  const int nmax = std::atoi(argv[2]);
  std::string prec = "ld", dump;
  int reps = 0;
  for (int i = 3; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--prec")) prec = argv[i + 1];
    else if (!std::strcmp(argv[i], "--reps")) reps = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--dump")) dump = argv[i + 1];
    else { std::fprintf(stderr, "unknown option %s\n", argv[i]); return 2; }
  }
  ShCoefficients k;
  if (model.rfind("kaula:", 0) == 0) k = synthetic_kaula(nmax, std::strtoull(model.c_str() + 6, nullptr, 10));
  else if (model.size() > 4 && model.substr(model.size() - 4) == ".gfc") k = read_icgem_gfc(model, nmax);
  else k = read_nasa_ascii(model, kEgm96Gm, kEgm96A, nmax);
  if (!dump.empty()) {
    FILE* f = std::fopen(dump.c_str(), "wb");
    if (!f) { std::perror(dump.c_str()); return 1; }
    const int n = k.nmax;
    const double gm = static_cast<double>(k.gm), a = static_cast<double>(k.a);
    std::fwrite(&n, sizeof n, 1, f); std::fwrite(&gm, sizeof gm, 1, f); std::fwrite(&a, sizeof a, 1, f);
    std::vector<double> v(k.c.size());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(k.c[i]);
    std::fwrite(v.data(), sizeof(double), v.size(), f);
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(k.s[i]);
    std::fwrite(v.data(), sizeof(double), v.size(), f);
    std::fclose(f);
  }
  const bool cunningham = prec == "cunningham";
  const ShPrecision p = prec == "double" ? ShPrecision::Double : prec == "mixed" ? ShPrecision::Mixed : ShPrecision::LongDouble;
  const SphericalHarmonicField f(std::move(k), nmax, 2, p);
  std::vector<Vec3> pts;
  long double x, y, z;
  while (std::cin >> x >> y >> z) pts.emplace_back(x, y, z);
  auto eval = [&](const Vec3& r) {
    if (!cunningham) return f.eval(r);
    const auto d = f.derivatives(r, 2);
    FieldSample s;
    s.potential = d[0].value[0];
    s.g = Vec3(d[1].at(1, 0, 0), d[1].at(0, 1, 0), d[1].at(0, 0, 1));
    s.gamma << d[2].at(2, 0, 0), d[2].at(1, 1, 0), d[2].at(1, 0, 1), d[2].at(1, 1, 0), d[2].at(0, 2, 0), d[2].at(0, 1, 1),
        d[2].at(1, 0, 1), d[2].at(0, 1, 1), d[2].at(0, 0, 2);
    return s;
  };
  std::vector<FieldSample> out(pts.size());
  if (reps > 0 && !pts.empty()) {
    (void)eval(pts[0]);  // builds lazy tables
    double best = 1e300;
    for (int k2 = 0; k2 < reps; ++k2) {
      const double t0 = cpu_s();
      for (std::size_t i = 0; i < pts.size(); ++i) out[i] = eval(pts[i]);
      best = std::min(best, (cpu_s() - t0) / static_cast<double>(pts.size()));
    }
    std::fprintf(stderr, "cpu_us_per_point %.3f\n", 1e6 * best);
  } else {
    for (std::size_t i = 0; i < pts.size(); ++i) out[i] = eval(pts[i]);
  }
  for (const FieldSample& s : out) {
    std::printf("%.21Le %.21Le %.21Le %.21Le", s.potential, s.g.x(), s.g.y(), s.g.z());
    const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (const auto& e : ij) std::printf(" %.21Le", s.gamma(e[0], e[1]));
    std::printf("\n");
  }
  return 0;
}
