// Step time of the firmware particle filter (gg_pf_step, 500 particles, candidates
// from a gmap tile) on the host: median over repeated steps, and the split shot
// (begin, chunks of 50 particles, end). Run under valgrind --tool=callgrind with
// --steps 50 for instructions per step. Settings: pf_bench.hpp.
//   coldatom-pf-bench [--steps N] [--particles N] [--chunk N] [--rw | --ins]
//   (--rw: the first version's random-walk model; --ins: the 6-state INS particles;
//   default: the Rao-Blackwellised filter of the flights)
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "ggins/coldatom/pf_bench.hpp"

using namespace ggins::coldatom;

int main(int argc, char** argv) {
  int steps = 2000, particles = 500, chunk = 50;
  PfBenchModel m = PfBenchModel::kRbpf;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--particles") && i + 1 < argc) particles = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--chunk") && i + 1 < argc) chunk = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--rw")) m = PfBenchModel::kRw;
    else if (!std::strcmp(argv[i], "--ins")) m = PfBenchModel::kIns;
    else {
      std::fprintf(stderr, "usage: coldatom-pf-bench [--steps N] [--particles N] [--chunk N] [--rw | --ins]\n");
      return 2;
    }
  }
  if (steps < 1 || particles < 1 || particles > GG_PF_MAX || chunk < 0) {
    std::fprintf(stderr, "coldatom-pf-bench: steps >= 1, 1 <= particles <= %d, chunk >= 0\n", GG_PF_MAX);
    return 2;
  }
  auto b = pf_bench_make(m, particles);
  PfStepTimes t;
  if (!b || !pf_bench_run(*b, steps, chunk, &t)) {
    std::fprintf(stderr, "coldatom-pf-bench: filter error\n");
    return 1;
  }
  const char* name = m == PfBenchModel::kRw ? "RW" : (m == PfBenchModel::kIns ? "INS" : "RBPF");
  std::printf("gg_pf_step (%s model), %d particles, gmap candidates: median %.1f us, p10 %.1f us, p90 %.1f us (%d steps)\n",
              name, particles, pf_bench_quantile(t.shot, 0.5) / 1e3, pf_bench_quantile(t.shot, 0.1) / 1e3,
              pf_bench_quantile(t.shot, 0.9) / 1e3, steps);
  if (chunk > 0)
    std::printf("split shot: begin median %.1f us, chunk of %d particles median %.1f us (p90 %.1f), end median %.1f us "
                "(p90 %.1f, resampling shots included)\n",
                pf_bench_quantile(t.begin, 0.5) / 1e3, chunk, pf_bench_quantile(t.chunk, 0.5) / 1e3,
                pf_bench_quantile(t.chunk, 0.9) / 1e3, pf_bench_quantile(t.end, 0.5) / 1e3,
                pf_bench_quantile(t.end, 0.9) / 1e3);
  return 0;
}
