// Helper for the pyshtools comparison (not a test by itself): evaluates a
// NASA/NGA ASCII spherical-harmonic model at points read from stdin
// ("x y z" in metres, Earth-fixed) and prints "V gx gy gz Gxx Gxy Gxz Gyy Gyz Gzz".
#include "ggins/gravity/spherical_harmonic.hpp"

#include <cstdio>
#include <cstdlib>
#include <iostream>

int main(int argc, char** argv) {
  using namespace ggins::gravity;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s model.ascii nmax < points\n", argv[0]);
    return 2;
  }
  const int nmax = std::atoi(argv[2]);
  const SphericalHarmonicField f(read_nasa_ascii(argv[1], kEgm96Gm, kEgm96A, nmax), nmax);
  long double x, y, z;
  while (std::cin >> x >> y >> z) {
    const FieldSample s = f.eval(Vec3(x, y, z));
    std::printf("%.21Le %.21Le %.21Le %.21Le", s.potential, s.g.x(), s.g.y(), s.g.z());
    const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (const auto& e : ij) std::printf(" %.21Le", s.gamma(e[0], e[1]));
    std::printf("\n");
  }
  return 0;
}
