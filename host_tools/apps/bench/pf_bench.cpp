// Step time of the firmware particle filter (gg_pf_step, 500 particles, candidates
// from a gmap tile) on the host: median over repeated steps, and the split shot
// (begin, chunks of 50 particles, end). Run under valgrind --tool=callgrind with
// --steps 50 for instructions per step. Settings: pf_bench.hpp.
//   coldatom-pf-bench [--steps N] [--particles N] [--chunk N] [--rw | --ins]
//   (--rw: the first version's random-walk model; --ins: the 6-state INS particles;
//   default: the Rao-Blackwellised filter of the flights)
#include <CLI/CLI.hpp>
#include <cstdio>

#include "ggins/coldatom/pf_bench.hpp"

using namespace ggins::coldatom;

int main(int argc, char** argv) {
  int steps = 2000, particles = 500, chunk = 50;
  PfBenchModel m = PfBenchModel::kRbpf;
  bool rw = false, ins = false;
  CLI::App app{"coldatom-pf-bench: step time of the firmware particle filter (gg_pf_step, candidates from a\n"
               "gmap tile) on the host: median and p10/p90 over repeated shots, and the split shot (begin,\n"
               "chunks, end). Under valgrind --tool=callgrind with --steps 50: instructions per shot.\n"
               "Exit status: 0 done; 1 the filter refused a step; 2 bad arguments."};
  app.add_option("--steps", steps, "shots to time")->check(CLI::Range(1, 100000000))->capture_default_str();
  app.add_option("--particles", particles, "particles")->check(CLI::Range(1, GG_PF_MAX))->capture_default_str();
  app.add_option("--chunk", chunk, "particles per chunk of the split shot (0: no split shot)")
      ->check(CLI::Range(0, GG_PF_MAX))->capture_default_str();
  auto* o_rw = app.add_flag("--rw", rw, "the random-walk particle model");
  app.add_flag("--ins", ins, "the 6-state INS particle model (default: the Rao-Blackwellised filter of the flights)")
      ->excludes(o_rw);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  if (rw) m = PfBenchModel::kRw;
  if (ins) m = PfBenchModel::kIns;
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
