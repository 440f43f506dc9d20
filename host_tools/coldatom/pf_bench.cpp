// Step time of the firmware particle filter (gg_pf_step, 500 particles, candidates
// from a gmap tile) on the host: median over repeated steps. Run under
// valgrind --tool=callgrind with --steps 50 for instructions per step.
//   coldatom-pf-bench [--steps N] [--particles N] [--rw | --ins]   (--rw: the first version's random-walk model; --ins: the
//   6-state INS particles; default: the Rao-Blackwellised filter of the flights)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
#include <vector>

extern "C" {
#include "ggins/gmap.h"
#include "ggins/pf.h"
}

static gg_gmap_t gm;
static gg_gmap_tile_t tile;
static gg_pf_t pf;

int main(int argc, char** argv) {
  int steps = 2000, particles = 500;
  bool rw = false, ins = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--steps") && i + 1 < argc) steps = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--particles") && i + 1 < argc) particles = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--rw")) rw = true;
    else if (!std::strcmp(argv[i], "--ins")) ins = true;
  }
  tile.nlat = tile.nlon = 50;
  tile.lat0_rad = 0.8; tile.lon0_rad = -0.03; tile.dlat_rad = 4e-5; tile.dlon_rad = 6e-5;
  tile.h0_m = 3000; tile.h_range_m = 1000;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) {
      tile.node[i * 50 + j][GG_GMAP_C_DD] = 3.08e-6 + 2e-8 * std::sin(0.3 * i) * std::cos(0.2 * j);
      tile.node[i * 50 + j][GG_GMAP_NCOMP + GG_GMAP_C_DD] = -1.45e-12;
    }
  if (gg_gmap_init(&gm, &tile) != GG_OK) return 1;
  gg_pf_config_t c{};
  c.n = particles; c.seed = 1; c.k_eff = 4 * M_PI / 852.347e-9; c.T = 0.16; c.dz = 1; c.contrast = 0.5;
  c.c0 = c.c1 = 0.5; c.sigma = 0.003; c.sigma0_pos = 300; c.sigma0_vel = 0.05;
  c.dt = 1; c.gain = 0.05; c.ess_frac = 0.5;
  if (rw) {  // the first version: random-walk velocity
    c.model = GG_PF_MODEL_RW; c.q_pos = 2; c.q_vel = 0.02;
  } else if (!ins) {  // the flights' settings (flight.cpp, Table I), Rao-Blackwellised
    c.model = GG_PF_MODEL_RBPF; c.q_pos = 0; c.q_vel = 1.47e-4; c.q_acc = 1.96e-5; c.sigma0_vel = 0;
    c.sigma0_jerk = 4.9e-7; c.sigma0_bias = 3.1e-4; c.reg_bw = 1.0;
  } else {   // the 6-state INS particles (session 3)
    c.model = GG_PF_MODEL_INS; c.q_pos = 0; c.q_vel = 1.47e-4; c.q_acc = 2.72e-5; c.sigma0_acc = 3.1e-4; c.reg_bw = 0.5;
  }
  if (gg_pf_map_from_gmap(&gm, &c.map) != GG_OK || gg_pf_init(&pf, &c) != GG_OK) return 1;
  std::vector<double> ns;
  for (int k = 0; k < steps; ++k) {
    const double th = 0.7 * k;
    gg_pf_input_t in{0.8 + 25 * 4e-5, -0.03 + 25 * 6e-5, 3000, 1, 0.5 - 0.25 * std::cos(th), 0.5 - 0.25 * std::cos(th + 1.16),
                     -97.0, 26.0};
    gg_pf_output_t o;
    const auto t0 = std::chrono::steady_clock::now();
    if (gg_pf_step(&pf, &in, &o) != GG_OK) return 1;
    const auto t1 = std::chrono::steady_clock::now();
    ns.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count());
  }
  std::sort(ns.begin(), ns.end());
  std::printf("gg_pf_step (%s model), %d particles, gmap candidates: median %.1f us, p10 %.1f us, p90 %.1f us (%d steps)\n",
              rw ? "RW" : (ins ? "INS" : "RBPF"), particles, ns[ns.size() / 2] / 1e3, ns[ns.size() / 10] / 1e3, ns[ns.size() * 9 / 10] / 1e3, steps);
  return 0;
}
