// Not a test: prints 3-D truth frames at full long-double precision, for
// comparing two builds of the generator to the digit
// (tests/truth3d/compare_dumps.py). Per line: step k, G_e (3), Gamma_e (9,
// row-major), f_b (3), then the true specific force of the six
// accelerometers (6 x 3), every `stride`-th step of the first n. With
// `reference`, the accelerometers from the field at each sensor's own position
// (Generator3::accel_reference) instead of the fast path frame() sends.
//   truth3d_dump SCENARIO N STRIDE [reference]
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

using namespace ggins::truth3d;

int main(int argc, char** argv) {
  const bool reference = argc == 5 && std::string(argv[4]) == "reference";
  if (argc != 4 && !reference) {
    std::fprintf(stderr, "usage: truth3d_dump SCENARIO N STRIDE [reference]\n");
    return 2;
  }
  try {
    const Scenario3 s = load_scenario3(argv[1], {GGINS_SCENARIO_DIR});
    const Generator3 g(s);
    const long n = std::atol(argv[2]), stride = std::atol(argv[3]);
    if (n <= 0 || stride <= 0) throw std::invalid_argument("N and STRIDE must be positive");
    for (long k = 0; k < n; k += stride) {
      const Truth3 t = g.truth(k);
      std::printf("%ld", k);
      for (int i = 0; i < 3; ++i) std::printf(" %.21Le", t.g_e[i]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) std::printf(" %.21Le", t.gamma_e(i, j));
      for (int i = 0; i < 3; ++i) std::printf(" %.21Le", t.f_b[i]);
      const auto fast = g.accel_true(t);
      for (int a = 0; a < 6; ++a) {
        const Vec3 f = reference ? g.accel_reference(t, a) : fast[static_cast<size_t>(a)];
        for (int i = 0; i < 3; ++i) std::printf(" %.21Le", f[i]);
      }
      std::printf("\n");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "truth3d_dump: %s\n", e.what());
    return 1;
  }
  return 0;
}
