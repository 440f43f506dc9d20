// ggins-coldatom: flights Liverpool -> Toulouse with the cold-atom gradiometer
// and the firmware particle filter (Phillips et al. section V). docs/cold-atom-pf.md
//
//   ggins-coldatom --flights 50 --sweep none            # Fig. 4: error vs time, aided/unaided
//   ggins-coldatom --flights 50 --sweep phase           # Fig. 5: mean error vs phase noise 0..15 mrad
//   ggins-coldatom --flights 50 --sweep fail            # Fig. 6: mean error vs failure probability 0..40 %
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

extern "C" {
#include "ggins/pf.h"
}

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "ggins/cli_checks.hpp"
#include "ggins/coldatom/flight.hpp"
#include "ggins/coldatom/route_map.hpp"
#include "ggins/coldatom/route_tiles.hpp"
#include "ggins/truth/stats.hpp"
#include "hil_common.hpp"
#include "report.hpp"

using namespace ggins::coldatom;
using json = nlohmann::json;

namespace {
struct Setting {
  std::string tag;
  double phase_mrad, p_fail;
};

double mean(const std::vector<double>& v) {
  double s = 0; int n = 0;
  for (double x : v) if (std::isfinite(x)) { s += x; ++n; }
  return n ? s / n : NAN;
}
double stdev(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0; int n = 0;
  for (double x : v) if (std::isfinite(x)) { s += (x - m) * (x - m); ++n; }
  return n > 1 ? std::sqrt(s / (n - 1)) : NAN;
}
}  // namespace

int main(int argc, char** argv) {
  namespace C = ggins::cli;
  CLI::App app{"Cold-atom partial-gradient position fixing: flights Liverpool -> Toulouse"};
  std::string egm96 = std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt";
  std::string out = "out/coldatom";
  std::string cache;
  std::string sweep = "none";
  int flights = 10, threads = 2, particles = 500;
  double duration = 0, phase_mrad = 0, p_fail = 0, cloud_rw = 0, gain = 0.05, q_pos = -1, q_vel = -1;
  double sigma0_acc = -1, q_acc = -1, reg_bw = -1, sigma0_vel = -1, ess_frac = 0.5, q_jerk = -1, q_bias = -1;
  std::string model = "rbpf";
  double sigma0_pos = 50, dz = 1.0, sigma_like = 0, n_atoms = 1e5, ins_scale = 1.0;
  unsigned long seed = 1;
  bool no_topo = false, no_egm = false, direct_map = false, dump_flights = false, tile_on_ins = false;
  double tile_recentre = 2000.0, tile_step = 250.0, topo_rms = 150.0;
  app.add_option("--egm96", egm96, "EGM96 coefficient file");
  app.add_option("--out", out, "output folder")->check(C::OutputDir())->capture_default_str();
  app.add_option("--cache", cache, "cache folder for the EGM96 grid (default <out>/cache)")->check(C::OutputDir());
  app.add_option("--sweep", sweep, "none | phase | fail")->check(CLI::IsMember({"none", "phase", "fail"}));
  app.add_option("--flights", flights, "flights per setting")->check(C::IntRange(1, 100000))->capture_default_str();
  app.add_option("--threads", threads, "worker threads")->check(C::IntRange(1, 256))->capture_default_str();
  app.add_option("--particles", particles, "particles (1 .. GG_PF_MAX = 500)")->check(C::IntRange(1, GG_PF_MAX))->capture_default_str();
  app.add_option("--duration", duration, "seconds per flight (0: the whole route, 11,370 s; else >= 10, the record interval)")
      ->check(C::FiniteRange(0.0, 1e6));
  app.add_option("--phase-noise", phase_mrad, "phase noise, mrad (sweep none)")->check(C::FiniteRange(0.0, 1000.0));
  app.add_option("--p-fail", p_fail, "failure probability, 0..1 (sweep none / phase)")->check(C::FiniteRange(0.0, 1.0));
  app.add_option("--cloud-rw", cloud_rw, "atom-cloud horizontal random walk, m/sqrt(s)")->check(C::FiniteRange(0.0, 1.0));
  app.add_option("--gain", gain, "PF smoothing gain, (0, 1]")->check(C::FiniteRange(1e-6, 1.0))->capture_default_str();
  app.add_option("--q-pos", q_pos, "PF process noise, m per shot (<0: the model's default, RW 2, INS 0)")->check(C::FiniteRange(-C::kInf, 1e5, C::kOpenLow));
  app.add_option("--q-vel", q_vel, "PF process noise, m/s per shot (<0: RW 0.02, INS from Table I)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--sigma0-pos", sigma0_pos, "PF initial spread, m")->check(C::FiniteRange(0.0, 1e5))->capture_default_str();
  app.add_option("--sigma0-vel", sigma0_vel, "PF initial velocity spread, m/s (<0: RW 0.05, INS 0)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--model", model,
                 "PF particle dynamics: rw (random walk, first version) | ins (INS error dynamics in every particle) | "
                 "rbpf (Rao-Blackwellised: particles for the position, a Kalman filter per particle for velocity, "
                 "tilt, gyro bias and accelerometer error)")
      ->check(CLI::IsMember({"rw", "ins", "rbpf"}))->capture_default_str();
  app.add_option("--q-jerk", q_jerk, "RBPF random walk of the gyro-bias (jerk) states, m/s^3 per shot (<0: 0)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--q-bias", q_bias, "RBPF random walk of the accelerometer-error states, m/s^2 per shot (<0: 0)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--q-acc", q_acc, "PF process noise on the specific-force error, m/s^2 per shot (<0: from Table I)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--sigma0-acc", sigma0_acc, "PF initial specific-force error spread, m/s^2 (<0: from Table I)")->check(C::FiniteRange(-C::kInf, 1e3, C::kOpenLow));
  app.add_option("--ess", ess_frac, "PF resampling threshold, fraction of N (0..1)")->check(C::FiniteRange(0.0, 1.0))->capture_default_str();
  app.add_option("--reg-bw", reg_bw, "PF regularised resampling bandwidth, multiple of Silverman's (0: off->check(C::FiniteRange(-C::kInf, 100, C::kOpenLow)); <0: RBPF 1.0, INS 0.5, RW 0)");
  app.add_option("--dz", dz,
                 "interferometer separation, m (1: the baseline; 2: delta phi 2.33 rad > pi/2, where the ellipse fit "
                 "under-estimates as in the paper)")
      ->check(C::FiniteRange(0.01, 100.0))->capture_default_str();
  app.add_option("--sigma-like", sigma_like, "PF likelihood sigma (0: from the noise model)")->check(C::FiniteRange(0.0, 10.0));
  app.add_option("--atoms", n_atoms, "mean atoms per shot")->check(C::FiniteRange(1.0, 1e12))->capture_default_str();
  app.add_option("--ins-scale", ins_scale, "multiplier of all Table I errors (0: perfect INS)")->check(C::FiniteRange(0.0, 1e3));
  app.add_option("--seed", seed, "first flight's seed")->check(C::Seed())->capture_default_str();
  app.add_flag("--direct-map", direct_map, "candidates from the route map directly instead of paged gmap tiles");
  app.add_flag("--tile-on-ins", tile_on_ins, "page the gmap tile around the raw INS position (before 2026-12) instead of the corrected one");
  app.add_option("--tile-recentre", tile_recentre, "re-centre the gmap tile when its centre is this far (m) from the position it follows")
      ->check(C::FiniteRange(1.0, 1e5))->capture_default_str();
  app.add_option("--tile-step", tile_step, "gmap tile node spacing, m (50 x 50 nodes)")->check(C::FiniteRange(10.0, 5000.0))->capture_default_str();
  app.add_flag("--dump-flights", dump_flights, "write flight_<tag>_<i>.csv per flight (errors and filter diagnostics)");
  app.add_flag("--no-topo", no_topo, "EGM96 only (no synthetic terrain field)");
  app.add_option("--topo-rms", topo_rms, "rms height of the synthetic terrain, m (a sensitivity check; the runs use 150)")
      ->check(C::FiniteRange(1.0, 2000.0))->capture_default_str();
  app.add_flag("--no-egm96", no_egm, "normal field instead of EGM96 (quick runs without the coefficient file)");
  bool no_plot = false;
  std::string python;
  app.add_flag("--no-plot", no_plot, "no matplotlib plots (plot_coldatom.py: coldatom-*.png in --out)");
  app.add_option("--python", python, "python with matplotlib (default: $GGINS_PYTHON, /usr/bin/python3)");
  std::string write_tiles;
  double tile_spacing = 5000.0;
  app.add_option("--write-tiles", write_tiles,
                 "write the map's Gamma_zz as gmap tiles along the route into this folder (tile_NNNN.gmap: 50 x 50 "
                 "nodes at --tile-step, one every --tile-spacing along track) for the 3-D task's map storage "
                 "(scenario [aid_pf].map_dir), then stop")
      ->check(C::OutputDir());
  app.add_option("--tile-spacing", tile_spacing, "along-track distance between the written tiles' centres, m")
      ->check(C::FiniteRange(100.0, 1e6))->capture_default_str();
  return C::run("ggins coldatom", app, argc, argv, [&]() -> int {
  if (duration > 0 && duration < 10)
    throw C::BadArgument("--duration: value " + std::to_string(duration) + " is not allowed (0: the whole route, else >= 10 s)");
  if (cache.empty()) cache = out + "/cache";
  if (const std::string why = C::output_dir_problem(cache); !why.empty())
    throw C::BadArgument("--cache: cannot write to folder '" + cache + "': " + why +
                         " (allowed: a writable folder, or one that can be created)");
  std::filesystem::create_directories(cache);
  std::filesystem::create_directories(out);

  RouteMapParams mp;
  mp.with_topo = !no_topo;
  mp.topo_rms = topo_rms;
  mp.with_egm96 = !no_egm;
  const auto tm0 = std::chrono::steady_clock::now();
  std::unique_ptr<RouteMap> map_ptr;
  try {
    map_ptr = std::make_unique<RouteMap>(mp, egm96, cache);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-coldatom: cannot build the route map: %s\n(EGM96 coefficients: scripts/fetch-egm96, "
                 "or --egm96 <file>; --no-egm96 for the normal field)\n", e.what());
    return 1;
  }
  const RouteMap& map = *map_ptr;
  const double map_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - tm0).count();
  std::printf("route %.1f km, map built in %.1f s; synthetic terrain: height rms %.0f m, Gamma_zz rms at %.0f m: %.2f E\n",
              map.length() / 1e3, map_s, map.topo_height_rms(), mp.h, map.topo_gzz_rms() * 1e9);
  {  // the map along the route (Fig. 1)
    std::ostringstream f;
    f << "s_km,lat_deg,lon_deg,land,gzz_E\n";
    for (double s = 0; s <= map.length(); s += 250.0) {
      double lat, lon, g = NAN;
      map.route_point(s, 0, &lat, &lon);
      map.gzz(lat, lon, mp.h, &g);
      f << s / 1e3 << "," << lat * 180 / M_PI << "," << lon * 180 / M_PI << "," << map.land(lat) << "," << g * 1e9
        << "\n";
    }
    C::write_file(out + "/route_gzz.csv", f.str());
  }

  if (!write_tiles.empty()) {  // the onboard map of the 3-D task's cold-atom aid (route_tiles.hpp)
    try {
      const int n = ggins::coldatom::write_route_tiles(map, tile_step, tile_spacing, write_tiles);
      std::printf("%d tiles (%d x %d nodes at %.0f m, every %.0f m along the route) in %s\n", n,
                  ggins::coldatom::kRouteTileNodes, ggins::coldatom::kRouteTileNodes, tile_step, tile_spacing,
                  write_tiles.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ggins-coldatom: %s\n", e.what());
      return 1;
    }
    return 0;
  }
  std::vector<Setting> settings;
  if (sweep == "none") settings.push_back({"base", phase_mrad, p_fail});
  if (sweep == "phase")
    for (double p : {0.0, 2.5, 5.0, 7.5, 10.0, 12.5, 15.0}) settings.push_back({"phase" + std::to_string(int(p * 10)), p, p_fail});
  if (sweep == "fail")
    for (double p : {0.0, 0.1, 0.2, 0.3, 0.4}) settings.push_back({"fail" + std::to_string(int(p * 100)), 5.0, p});

  // Ctrl-C / SIGTERM: no further flight starts (the flights under way finish), and the report
  // says which flew (status interrupted, exit 130)
  ggins::hil::install_interrupt_handlers();
  json summary = json::array();
  // the report's flights: every setting's, run index = setting * flights + flight
  std::vector<ggins::hil::EnsembleRun> report_runs;
  std::vector<ggins::hil::ConsistencyState> cons_states;
  json err_over_spread = json::object();
  int64_t records_per_flight = 0;
  const auto tr0 = std::chrono::steady_clock::now();
  for (std::size_t si = 0; si < settings.size(); ++si) {
    const Setting& st = settings[si];
    std::vector<FlightResult> res(static_cast<std::size_t>(flights));
    std::vector<char> flown(static_cast<std::size_t>(flights), 0);
    std::atomic<int> next{0};
    auto worker = [&]() {
      for (int i; !ggins::hil::interrupted() && (i = next++) < flights;) {
        FlightConfig fc;
        fc.grad.phase_noise = st.phase_mrad * 1e-3;
        fc.grad.p_fail = st.p_fail;
        fc.grad.cloud_rw = cloud_rw;
        fc.grad.dz = dz;
        fc.grad.n_atoms = n_atoms;
        fc.sigma_like = sigma_like;
        fc.ins.acc_bias_g *= ins_scale; fc.ins.acc_nonorth *= ins_scale; fc.ins.acc_scale *= ins_scale;
        fc.ins.acc_noise_g *= ins_scale; fc.ins.gyro_bias *= ins_scale; fc.ins.gyro_nonorth *= ins_scale;
        fc.ins.gyro_scale *= ins_scale; fc.ins.gyro_noise *= ins_scale;
        fc.particles = particles;
        fc.gain = gain; fc.q_pos = q_pos; fc.q_vel = q_vel; fc.sigma0_pos = sigma0_pos;
        fc.sigma0_vel = sigma0_vel; fc.model = model == "rbpf" ? 2 : (model == "ins" ? 1 : 0);  // GG_PF_MODEL_RBPF / INS / RW
        fc.q_jerk = q_jerk; fc.q_bias = q_bias;
        fc.q_acc = q_acc; fc.sigma0_acc = sigma0_acc; fc.reg_bw = reg_bw; fc.ess_frac = ess_frac;
        fc.duration = duration;
        fc.use_gmap = !direct_map;
        fc.tile_on_estimate = !tile_on_ins;
        fc.tile_recentre = tile_recentre;
        fc.tile_step = tile_step;
        fc.seed = seed + static_cast<unsigned long>(i);
        res[static_cast<std::size_t>(i)] = fly(map, fc);
        flown[static_cast<std::size_t>(i)] = 1;
      }
    };
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<std::thread> pool;
    for (int k = 0; k < threads; ++k) pool.emplace_back(worker);
    for (auto& th : pool) th.join();
    for (std::size_t i = 0; i < res.size(); ++i) {  // the flights as the report counts them
      ggins::hil::EnsembleRun x;
      x.index = static_cast<int>(si) * flights + static_cast<int>(i);
      x.seed = seed + i;
      const FlightResult& r = res[i];
      if (flown[i] && r.error.empty() && !r.t.empty()) records_per_flight = static_cast<int64_t>(r.t.size());
      x.counts.steps_flown = flown[i] && r.error.empty() ? static_cast<int64_t>(r.t.size()) : 0;
      x.counts.final_seq = x.counts.steps_flown > 0 ? x.counts.steps_flown : -1;  // record k at k 10 s
      x.counts.dt_s = 10.0;
      x.status = !flown[i] ? "interrupted" : (r.error.empty() ? "completed" : "failed");
      if (x.counts.steps_flown > 0) {
        double ma = 0, mu = 0;
        for (double v : r.err_aided) ma = std::max(ma, v);
        for (double v : r.err_unaided) mu = std::max(mu, v);
        x.errors["position_error_m"] = {{"final", r.err_aided.back()}, {"max", ma}};
        x.errors["unaided_position_error_m"] = {{"final", r.err_unaided.back()}, {"max", mu}};
      }
      report_runs.push_back(std::move(x));
    }
    if (ggins::hil::interrupted()) break;  // the setting's statistics need all its flights
    for (std::size_t i = 0; i < res.size(); ++i)
      if (!res[i].error.empty() || res[i].t.size() != res[0].t.size()) {
        std::fprintf(stderr, "ggins-coldatom: flight %zu (seed %lu) of setting %s did not fly: %s\n", i,
                     seed + static_cast<unsigned long>(i), st.tag.c_str(),
                     res[i].error.empty() ? "record count differs from the first flight's" : res[i].error.c_str());
        return 1;
      }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (dump_flights)
      for (std::size_t i = 0; i < res.size(); ++i) {
        const FlightResult& r = res[i];
        std::ostringstream g;
        g << "t_s,unaided_m,aided_m,pmean_err_m,spread_m,ess,vmean_err_mps,vspread_mps,ins_dv_mps\n";
        for (std::size_t j = 0; j < r.t.size(); ++j) {
          g << r.t[j] << "," << r.err_unaided[j] << "," << r.err_aided[j];
          if (j < r.d_spread.size())
            g << "," << r.d_err_mean[j] << "," << r.d_spread[j] << "," << r.d_ess[j] << "," << r.d_verr[j] << ","
              << r.d_vspread[j] << "," << r.d_ins_dv[j];
          g << "\n";
        }
        C::write_file(out + "/flight_" + st.tag + "_" + std::to_string(i) + ".csv", g.str());
      }
    // mean error against time over the flights
    const std::size_t nt = res[0].t.size();
    std::ostringstream f;
    f << "t_s,unaided_mean_m,aided_mean_m,aided_p90_m\n";
    for (std::size_t j = 0; j < nt; ++j) {
      std::vector<double> a, u;
      for (const auto& r : res) { a.push_back(r.err_aided[j]); u.push_back(r.err_unaided[j]); }
      std::sort(a.begin(), a.end());
      f << res[0].t[j] << "," << mean(u) << "," << mean(a) << "," << a[static_cast<std::size_t>(0.9 * (a.size() - 1))] << "\n";
    }
    C::write_file(out + "/error_vs_time_" + st.tag + ".csv", f.str());
    // gradient estimates (all flights): error of ellipse fit and PF against the batch-mean truth
    std::vector<double> efit, epf, mean_a, mean_u, fin_u, step;
    int shots = 0, failed = 0, degen = 0, tiles = 0, miss = 0;
    for (const auto& r : res) {
      for (std::size_t j = 0; j < r.g_true.size(); ++j) {
        efit.push_back((r.g_fit[j] - r.g_true[j]) * 1e9);
        epf.push_back((r.g_pf[j] - r.g_true[j]) * 1e9);
      }
      mean_a.push_back(r.mean_aided); mean_u.push_back(r.mean_unaided); fin_u.push_back(r.final_unaided);
      step.push_back(r.pf_step_ns_median);
      shots += r.shots; failed += r.failed; degen += r.degenerate; tiles += r.tiles; miss += r.map_miss;
    }
    {
      std::ostringstream g;
      g << "t_s,true_E,ellipse_fit_E,pf_E\n";
      for (std::size_t j = 0; j < res[0].g_true.size(); ++j)
        g << res[0].batch_t[j] << "," << res[0].g_true[j] * 1e9 << "," << res[0].g_fit[j] * 1e9 << ","
          << res[0].g_pf[j] * 1e9 << "\n";
      C::write_file(out + "/gradient_" + st.tag + "_flight0.csv", g.str());
    }
    std::sort(step.begin(), step.end());
    json js = {{"setting", st.tag}, {"phase_noise_mrad", st.phase_mrad}, {"p_fail", st.p_fail},
               {"flights", flights}, {"duration_s", res[0].t.empty() ? 0.0 : res[0].t.back()},
               {"mean_aided_m", mean(mean_a)}, {"std_over_flights_aided_m", stdev(mean_a)},
               {"mean_unaided_m", mean(mean_u)}, {"final_unaided_mean_m", mean(fin_u)},
               {"ellipse_fit_err_mean_E", mean(efit)}, {"ellipse_fit_err_std_E", stdev(efit)},
               {"pf_err_mean_E", mean(epf)}, {"pf_err_std_E", stdev(epf)},
               {"shots", shots}, {"failed_shots", failed}, {"degenerate_steps", degen}, {"map_miss_steps", miss}, {"gmap_tiles", tiles}, {"map", direct_map ? "route map (direct)" : "gmap tiles"},
               {"pf_step_ns_median", step[step.size() / 2]}, {"wall_s", wall}};
    {  // the particle filter's consistency at the end of the flights: error of the particle mean
       // against its spread sqrt(var_N + var_E); (err/spread)^2 averages 1 for a consistent filter
      double se = 0, ss = 0, q = 0;
      int n = 0;
      for (const auto& r : res)
        if (!r.d_spread.empty()) {
          const double e = r.d_err_mean.back(), sp = r.d_spread.back();
          se += e * e; ss += sp * sp; q += (e / sp) * (e / sp); ++n;
        }
      if (n > 0) {
        cons_states.push_back({"position_" + st.tag + "_m", std::sqrt(se / n), std::sqrt(ss / n)});
        js["pf_err_over_spread_sq_final_mean"] = q / n;
        err_over_spread[st.tag] = q / n;
      }
    }
    std::printf("%s\n", js.dump().c_str());
    std::fflush(stdout);
    summary.push_back(js);
  }
  const bool was_interrupted = ggins::hil::interrupted();
  const double wall_all = std::chrono::duration<double>(std::chrono::steady_clock::now() - tr0).count();
  if (!was_interrupted) C::write_file(out + "/summary_" + sweep + ".json", summary.dump(2) + "\n");
  {  // the report (summary.json, report.hpp): every setting's flights as one ensemble
    const int total = flights * static_cast<int>(settings.size());
    for (int k = static_cast<int>(report_runs.size()); k < total; ++k) {  // settings never reached: unflown
      ggins::hil::EnsembleRun x;
      x.index = k;
      x.seed = seed + static_cast<unsigned long>(k % flights);
      x.status = "interrupted";
      x.counts.dt_s = 10.0;
      report_runs.push_back(std::move(x));
    }
    int stopped = 0, unflown = 0;
    for (auto& x : report_runs) {
      x.counts.steps_expected = records_per_flight;
      if (x.status == "interrupted") ++(x.counts.steps_flown > 0 ? stopped : unflown);
    }
    ggins::hil::FlightEnd end;
    if (was_interrupted) {
      end.error = "interrupted: " + std::to_string(stopped) + " flight(s) stopped, " + std::to_string(unflown) + " of " +
                  std::to_string(total) + " not flown";
      end.code = 130;
    }
    json cons(nullptr);
    if (!was_interrupted && !cons_states.empty()) {
      // each flight's final error has two components (north, east): 2 N degrees of freedom
      const double z = 3.0;
      const ggins::truth::Chi2Band band = ggins::truth::chi2_band(2.0 * flights, z);
      cons = ggins::hil::consistency_block(
          cons_states, 2 * flights, z, band.rms_lo, band.rms_hi,
          "s/sigma per setting, s = sqrt(sum e^2/N) over the flights of the particle mean's final horizontal error, "
          "sigma = the particle spread sqrt(var_N + var_E) there, RMS over the same flights (2 N dof)");
    }
    json opts = {{"sweep", sweep}, {"flights", flights}, {"particles", particles}, {"model", model},
                 {"duration_s", duration}, {"phase_noise_mrad", phase_mrad}, {"p_fail", p_fail},
                 {"cloud_rw_m_per_rts", cloud_rw}, {"gain", gain}, {"q_pos_m", q_pos}, {"q_vel_mps", q_vel},
                 {"sigma0_pos_m", sigma0_pos}, {"sigma0_vel_mps", sigma0_vel}, {"q_acc_mps2", q_acc},
                 {"sigma0_acc_mps2", sigma0_acc}, {"q_jerk_mps3", q_jerk}, {"q_bias_mps2", q_bias},
                 {"ess_frac", ess_frac}, {"reg_bw", reg_bw}, {"dz_m", dz}, {"sigma_like", sigma_like},
                 {"atoms", n_atoms}, {"ins_scale", ins_scale}, {"seed", static_cast<int64_t>(seed)},
                 {"direct_map", direct_map}, {"tile_on_ins", tile_on_ins}, {"tile_recentre_m", tile_recentre},
                 {"tile_step_m", tile_step}, {"topo", !no_topo}, {"topo_rms_m", topo_rms}, {"egm96", !no_egm}};
    json extra = {{"seed0", static_cast<int64_t>(seed)},
                  {"seeds", "run i: setting i / flights, flight seed seed0 + i % flights"},
                  {"settings", summary},
                  {"pf_err_over_spread_sq_final_mean", err_over_spread},
                  {"options", opts}};
    json rep = ggins::hil::ensemble_report(
        "ggins coldatom", "3-D", "liverpool-toulouse", "built in (Phillips et al. route; the options in scenario.toml)",
        "cold-atom partial-gradient position fixing with the firmware particle filter against the unaided INS",
        "direct", 0.1, duration > 0 ? duration : 11370.0, report_runs, total, end,
        "horizontal (north, east) on the route, m",
        "horizontal position error every 10 s (the steps are these records): position_error_m of the aided "
        "solution (INS corrected by the particle filter), unaided_position_error_m of the INS alone; final: the "
        "last record, max: the largest",
        cons, extra);
    rep["setup_s"] = map_s;
    rep["wall_s"] = wall_all;
    rep["files"] = {{"summary", "summary.json"}, {"scenario", "scenario.toml"}, {"route", "route_gzz.csv"}};
    if (!was_interrupted) rep["files"]["settings"] = "summary_" + sweep + ".json";
    rep["output_dir"] = std::filesystem::absolute(out).string();
    json set;
    for (const auto& [k, v] : opts.items()) set["coldatom." + k] = v;
    ggins::hil::write_effective_scenario(out + "/scenario.toml", "liverpool-toulouse", "ggins coldatom options", "",
                                         set);
    C::write_file(out + "/summary.json", rep.dump(2) + "\n");
    if (was_interrupted) {
      std::fprintf(stderr, "ggins-coldatom: %s\n", rep["error"].get<std::string>().c_str());
      return ggins::hil::exit_status(rep);
    }
  }
  if (!no_plot) {  // plot_coldatom.py: the route, error against time, sweeps, diagnostics, gradient
    const std::string py = C::find_python(python);
    if (py.empty()) {
      std::fprintf(stderr, "ggins-coldatom: no python with matplotlib found (try --python /usr/bin/python3); no plot\n");
    } else {
      const std::string cmd = "'" + py + "' '" GGINS_COLDATOM_PLOT_SCRIPT "' '" + out + "' 1>&2";
      if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "ggins-coldatom: plot script failed: %s\n", cmd.c_str());
    }
  }
  std::printf("report: %s\n", out.c_str());
  return 0;
  });
}
