// The particle filter's step-time benchmark, shared by coldatom-pf-bench and
// ggins profile: gg_pf_step with 500 particles whose candidates come from a synthetic
// 50 x 50 gmap tile (Gamma_DD varying smoothly, the normal field's height gradient), pairs
// on the ellipse of ~3080 E with the laser phase turning 0.7 rad per shot, and the flights'
// filter settings (flight.cpp, Table I). The same settings as the Cortex-M7 image
// firmware/target/m7_qemu_filters.c (PF_BENCH).
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <vector>

extern "C" {
#include "ggins/gmap.h"
#include "ggins/pf.h"
}

namespace ggins::coldatom {

enum class PfBenchModel { kRbpf, kIns, kRw };

struct PfBench {
  gg_gmap_tile_t tile{};
  gg_gmap_t gm{};
  gg_pf_t pf{};
  int k = 0;  // next shot
};

// Build the tile and initialise the filter (heap: the state is ~150 kB). nullptr on error.
inline std::unique_ptr<PfBench> pf_bench_make(PfBenchModel m, int particles) {
  auto b = std::make_unique<PfBench>();
  gg_gmap_tile_t& tile = b->tile;
  tile.nlat = tile.nlon = 50;
  tile.lat0_rad = 0.8; tile.lon0_rad = -0.03; tile.dlat_rad = 4e-5; tile.dlon_rad = 6e-5;
  tile.h0_m = 3000; tile.h_range_m = 1000;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) {
      tile.node[i * 50 + j][GG_GMAP_C_DD] = 3.08e-6 + 2e-8 * std::sin(0.3 * i) * std::cos(0.2 * j);
      tile.node[i * 50 + j][GG_GMAP_NCOMP + GG_GMAP_C_DD] = -1.45e-12;
    }
  if (gg_gmap_init(&b->gm, &tile) != GG_OK) return nullptr;
  gg_pf_config_t c{};
  c.n = particles; c.seed = 1; c.k_eff = 4 * M_PI / 852.347e-9; c.T = 0.16; c.dz = 1; c.contrast = 0.5;
  c.c0 = c.c1 = 0.5; c.sigma = 0.003; c.sigma0_pos = 300; c.sigma0_vel = 0.05;
  c.dt = 1; c.gain = 0.05; c.ess_frac = 0.5;
  if (m == PfBenchModel::kRw) {  // the first version: random-walk velocity
    c.model = GG_PF_MODEL_RW; c.q_pos = 2; c.q_vel = 0.02;
  } else if (m == PfBenchModel::kRbpf) {  // the flights' settings, Rao-Blackwellised
    c.model = GG_PF_MODEL_RBPF; c.q_pos = 0; c.q_vel = 1.47e-4; c.q_acc = 1.96e-5; c.sigma0_vel = 0;
    c.sigma0_jerk = 4.9e-7; c.sigma0_bias = 3.1e-4; c.reg_bw = 1.0;
  } else {  // the 6-state INS particles (session 3)
    c.model = GG_PF_MODEL_INS; c.q_pos = 0; c.q_vel = 1.47e-4; c.q_acc = 2.72e-5; c.sigma0_acc = 3.1e-4; c.reg_bw = 0.5;
  }
  if (gg_pf_map_from_gmap(&b->gm, &c.map) != GG_OK || gg_pf_init(&b->pf, &c) != GG_OK) return nullptr;
  return b;
}

inline gg_pf_input_t pf_bench_input(int k) {
  const double th = 0.7 * k;
  return gg_pf_input_t{0.8 + 25 * 4e-5, -0.03 + 25 * 6e-5, 3000, 1, 0.5 - 0.25 * std::cos(th),
                       0.5 - 0.25 * std::cos(th + 1.16), -97.0, 26.0};
}

struct PfStepTimes {
  std::vector<double> shot, begin, chunk, end;  // ns per call
};

// `shots` whole shots through gg_pf_step, then `shots` split shots (begin, chunks of
// `chunk` particles, end), each call timed with steady_clock. false on a filter error.
inline bool pf_bench_run(PfBench& b, int shots, int chunk, PfStepTimes* t) {
  using clk = std::chrono::steady_clock;
  auto ns = [](clk::time_point a, clk::time_point z) { return std::chrono::duration<double, std::nano>(z - a).count(); };
  for (int s = 0; s < shots; ++s) {
    const gg_pf_input_t in = pf_bench_input(b.k++);
    gg_pf_output_t o;
    const auto t0 = clk::now();
    if (gg_pf_step(&b.pf, &in, &o) != GG_OK) return false;
    t->shot.push_back(ns(t0, clk::now()));
  }
  for (int s = 0; s < shots && chunk > 0; ++s) {
    const gg_pf_input_t in = pf_bench_input(b.k++);
    gg_pf_output_t o;
    auto t0 = clk::now();
    if (gg_pf_step_begin(&b.pf, &in) != GG_OK) return false;
    t->begin.push_back(ns(t0, clk::now()));
    int done = 0;
    while (!done) {
      t0 = clk::now();
      if (gg_pf_step_chunk(&b.pf, chunk, &done) != GG_OK) return false;
      t->chunk.push_back(ns(t0, clk::now()));
    }
    t0 = clk::now();
    if (gg_pf_step_end(&b.pf, &o) != GG_OK) return false;
    t->end.push_back(ns(t0, clk::now()));
  }
  return true;
}

// quantile q of v (sorts v)
inline double pf_bench_quantile(std::vector<double>& v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto i = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(i, v.size() - 1)];
}

}  // namespace ggins::coldatom
