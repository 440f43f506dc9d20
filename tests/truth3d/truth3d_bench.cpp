// Not a test: per-step CPU cost of the 3-D truth generator (scripts/bench-truth3d).
//   truth3d_bench SCENARIO N [REPEATS]
// Thread CPU time per step over steps 0..N-1, the best of REPEATS passes
// (default 3; the first pass also fills lattice caches, so it is printed too):
//   frame      Generator3::frame (what the runners call: trajectory, field at the
//              centre, the six accelerometers, gyros, barometer)
//   reference  truth() + accel_reference() for the six sensors (the field at
//              each sensor's own position)
//   trajectory Trajectory3::at alone
// Built with GGINS_BENCH_FRAME_ONLY it uses only the interface every version of
// the generator has (Generator3(scenario), frame()), so the script can build it
// against an earlier revision for the side-by-side ratio.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <string>

#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

using namespace ggins::truth3d;

static double cpu_s() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// per-step microseconds: first pass and best pass
static void time_it(const char* what, long n, int repeats, const std::function<double(long)>& step) {
  volatile double sink = 0;
  double first = 0, best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = cpu_s();
    for (long k = 0; k < n; ++k) sink = sink + step(k);
    const double us = (cpu_s() - t0) / static_cast<double>(n) * 1e6;
    if (r == 0) first = us;
    best = std::min(best, us);
  }
  std::printf("%-10s %9.3f us/step (first pass %.3f)\n", what, best, first);
}

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::fprintf(stderr, "usage: truth3d_bench SCENARIO N [REPEATS]\n");
    return 2;
  }
  try {
    const Scenario3 s = load_scenario3(argv[1], {GGINS_SCENARIO_DIR});
    const Generator3 g(s);
    const long n = std::min<long>(std::atol(argv[2]), static_cast<long>(g.n_steps()));
    const int repeats = argc == 4 ? std::max(1, std::atoi(argv[3])) : 3;
    if (n <= 0) throw std::invalid_argument("N must be positive");
    std::printf("scenario %s, %ld steps, best of %d\n", argv[1], n, repeats);
    time_it("frame", n, repeats, [&](long k) {
      gg_frame_t f;
      g.frame(k, f);
      return f.f[0][0] + f.f[5][2];
    });
#ifndef GGINS_BENCH_FRAME_ONLY
    time_it("reference", n, repeats, [&](long k) {
      const Truth3 t = g.truth(k);
      double x = 0;
      for (int j = 0; j < 6; ++j) x += static_cast<double>(g.accel_reference(t, j)(0));
      return x;
    });
    time_it("trajectory", n, repeats, [&](long k) { return static_cast<double>(g.trajectory().at(g.time_of(k)).r_e(0)); });
#endif
  } catch (const std::exception& e) {
    std::fprintf(stderr, "truth3d_bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
