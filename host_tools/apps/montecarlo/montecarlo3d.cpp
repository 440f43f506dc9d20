// ggins-montecarlo3d: N runs of the real 3-D firmware (gg_nav3d_step, direct
// calls, no LCM) along the analytic great-circle flight of ggins-covariance3d
// with seeded random sensor errors (18 accelerometer biases, gyro biases,
// optional white noise), against the covariance of the same scenario
// The sample one-sigma s = sqrt(sum e^2 / N) of each NED
// component is compared with the covariance sigma; N s^2/sigma^2 ~ chi^2_N,
// band at +-3 standard-normal quantiles (Wilson-Hilferty).
#include <CLI/CLI.hpp>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "ggins/cli_checks.hpp"
#include "ggins/covariance/propagate.hpp"
#include "ggins/truth/stats.hpp"
#include "frame_names.hpp"
#include "hil_common.hpp"
#include "report.hpp"
#include "sim3d.hpp"
#include "ggins/covariance/cov3d_truth3d.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace ggins::covariance;
using namespace ggins::montecarlo3d;

namespace {
std::string sch_num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
}  // namespace

#ifndef GGINS_MC3D_PLOT_SCRIPT
#define GGINS_MC3D_PLOT_SCRIPT ""
#endif

int main(int argc, char** argv) {
  CLI::App app{
      "ggins montecarlo3d: N runs of the 3-D firmware (gg_nav3d_step, direct calls) along the analytic\n"
      "great-circle flight (or truth3d scenario) of ggins covariance3d with seeded sensor errors, against\n"
      "the covariance; "
      "chi-square band for N. Writes to --out the report summary.json (the shape of ggins run3d's,\n"
      "docs/hil.md, with the ensemble block), scenario.toml (as flown), montecarlo3d.json (the comparison)\n"
      "and montecarlo3d.csv. docs/error-analysis.md.",
      "ggins-montecarlo3d"};
  std::string scen = "gc3d-stabilized", out_dir, platform_s, field_s;
  int runs = 100, jobs = 0;
  uint64_t seed = 1;
  double rate = 100.0, output_dt = 60.0;
  std::optional<double> rate_opt, duration, omega_ie, speed, lat0, acc_bias, gyro_bias, acc_noise, gyro_noise;
  bool want_json = false, no_plot = false, no_baro = false;
  std::string python;
  app.add_option("-s,--scenario", scen, "3-D scenario: gc3d-* built-in, a great-circle file ([great_circle], as --print-scenario writes), or a 3-D\n"
                 "truth-generator scenario (ggins covariance3d --help)")->capture_default_str();
  app.add_option("-n,--runs", runs, "number of runs N")->capture_default_str()->check(CLI::Range(2, 100000));
  app.add_option("--seed", seed, "first seed (run i uses seed + i)")->capture_default_str()->check(ggins::cli::Seed());
  app.add_option("--rate-hz", rate_opt, "firmware step rate, Hz (1e6 / rate a whole number of microseconds; default: the scenario's, 100 for gc3d-*)")
      ->check(ggins::cli::FiniteRange(0.0, 1e4, ggins::cli::kOpenLow));
  app.add_option("--duration", duration, "s")->check(ggins::cli::FiniteRange(0.0, 1e6, ggins::cli::kOpenLow));
  app.add_option("--output-dt", output_dt, "comparison spacing, s")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(0.0, 1e6, ggins::cli::kOpenLow));
  app.add_option("-j,--jobs", jobs, "threads (default: all cores)")->check(ggins::cli::IntRange(0, 1024));
  app.add_option("--platform", platform_s, "stabilized | strapdown")->check(CLI::IsMember({"stabilized", "strapdown"}));
  app.add_option("--field", field_s, "normal | point-mass")->check(CLI::IsMember({"normal", "point-mass"}));
  app.add_option("--omega-ie", omega_ie, "Earth rate, rad/s (0: non-rotating)")->check(ggins::cli::FiniteRange(0.0, 1e-3));
  app.add_option("--speed", speed, "m/s")->check(ggins::cli::FiniteRange(0.0, 2e4));
  app.add_option("--lat0-deg", lat0, "deg")->check(ggins::cli::FiniteRange(-89.0, 89.0));
  app.add_option("--acc-bias-sigma", acc_bias, "m/s^2")->check(ggins::cli::NonNegativeFinite());
  app.add_option("--gyro-bias-sigma", gyro_bias, "rad/s")->check(ggins::cli::NonNegativeFinite());
  app.add_option("--acc-noise-sigma", acc_noise, "per sample, m/s^2")->check(ggins::cli::NonNegativeFinite());
  app.add_option("--gyro-noise-sigma", gyro_noise, "per sample, rad/s")->check(ggins::cli::NonNegativeFinite());
  app.add_option("-o,--out", out_dir, "output directory (default out/montecarlo3d/<scenario>)")->check(ggins::cli::OutputDir());
  app.add_flag("--json", want_json, "print the JSON summary");
  app.add_flag("--no-plot", no_plot, "no matplotlib plot");
  app.add_flag("--no-baro", no_baro, "fly (and analyse) a scenario that has the barometric loop without it");
  app.add_option("--python", python, "python with matplotlib (default: $GGINS_PYTHON, /usr/bin/python3)");
  bool print_scenario = false, print_defaults = false;
  app.add_flag("--print-scenario", print_scenario,
               "print the scenario as it would fly (every key: defaults filled in, overrides applied) and exit");
  app.add_flag("--defaults", print_defaults,
               "with --print-scenario: a complete great-circle template instead (every key at its default,\n"
               "commented with unit, allowed range and meaning)");
  try {  // bad arguments: CLI11's message naming the option, exit 2 (ggins/cli_checks.hpp)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? ggins::cli::kExitOk : ggins::cli::kExitBadArgs;
  }
  if (print_defaults && !print_scenario) {
    std::fprintf(stderr, "ggins-montecarlo3d: --defaults: allowed only with --print-scenario\n");
    return ggins::cli::kExitBadArgs;
  }
  if (print_scenario && print_defaults) {
    std::fputs(great_circle_scenario_to_toml(Cov3DScenario{}, true).c_str(), stdout);
    return ggins::cli::kExitOk;
  }
  try {
  // the scenario (scenario3d_to_toml writes it back as flown) and the overrides: a truth3d
  // scenario takes them in its own keys, a great circle in its own
  Scenario3DInput in;
  try {
    in = resolve_scenario3d(scen, {"scenarios", std::string(GGINS_SOURCE_DIR) + "/scenarios"});
    if (in.truth) {
      auto& t = *in.truth;
      for (const auto& [o, v] : {std::pair<const char*, bool>{"--field", !field_s.empty()}, {"--omega-ie", bool(omega_ie)},
                                 {"--speed", bool(speed)}, {"--lat0-deg", bool(lat0)}})
        if (v) throw std::runtime_error(std::string(o) + ": applies to a great-circle scenario (gc3d-*) only; '" + scen +
                                        "' has its own trajectory and field");
      if (no_baro) t.nav_baro.enable = 0;
      if (!platform_s.empty()) t.platform = platform_s;
      if (duration) t.duration_s = *duration;
      if (rate_opt) t.rate_hz = *rate_opt;
      if (acc_bias) t.accel.bias_sigma_mps2 = *acc_bias;
      if (gyro_bias) t.gyro.bias_sigma_radps = *gyro_bias;
      if (acc_noise) t.accel.noise_sigma_mps2 = *acc_noise;
      if (gyro_noise) t.gyro.noise_sigma_radps = *gyro_noise;
      in.cov = cov3d_from_truth3d(t, &in.unmodelled);
    } else {
      auto& c = in.cov;
      if (no_baro) c.model.baro.on = false;
      if (!platform_s.empty()) c.platform = platform_s == "strapdown" ? Platform::kStrapdown : Platform::kStabilized;
      if (!field_s.empty()) c.field = field_s;
      if (duration) c.duration_s = *duration;
      if (omega_ie) c.omega_ie = *omega_ie;
      if (speed) c.speed_mps = *speed;
      if (lat0) c.lat0_deg = *lat0;
      if (acc_bias) c.acc_bias_sigma_mps2 = *acc_bias;
      if (gyro_bias) c.gyro_bias_sigma_radps = *gyro_bias;
      if (acc_noise) c.model.acc_noise_sigma_mps2 = *acc_noise;
      if (gyro_noise) c.model.gyro_noise_sigma_radps = *gyro_noise;
      if (rate_opt) c.model.rate_hz = *rate_opt;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-montecarlo3d: %s\n", e.what());
    return ggins::cli::kExitBadArgs;
  }
  Cov3DScenario s = in.cov;
  rate = s.model.rate_hz;
  {
    const double us = 1e6 / rate;
    if (!(rate > 0 && rate <= 1e4) || std::fabs(us - std::round(us)) > 1e-9 * us) {
      std::fprintf(stderr, "ggins-montecarlo3d: rate %g Hz does not give a whole number of microseconds per step\n", rate);
      return ggins::cli::kExitBadArgs;
    }
  }
  if (print_scenario) {
    std::fputs(scenario3d_to_toml(in).c_str(), stdout);
    return ggins::cli::kExitOk;
  }
  for (const auto& u : in.unmodelled) std::fprintf(stderr, "ggins-montecarlo3d: NOTE not modelled: %s\n", u.c_str());
  if (out_dir.empty()) out_dir = "out/montecarlo3d/" + s.name;
  if (jobs <= 0) jobs = int(std::max(1u, std::thread::hardware_concurrency()));
  const bool sd = s.platform == Platform::kStrapdown;

  // SIGINT/SIGTERM (a terminal's Ctrl-C) from here on: no run starts after it, the runs in
  // flight stop at their next check, and the report says which ran (status interrupted, exit 130).
  ggins::hil::install_interrupt_handlers();

  // Covariance of the same scenario.
  const auto model = make_model3d(s);
  PropagationOptions opt;
  opt.t_end = s.duration_s;
  opt.dt = 1.0;
  opt.output_dt = output_dt;
  opt.method = model->has_process_noise() ? Method::kLyapunov : Method::kTransition;
  const auto cov = propagate(*model, initial_covariance3d(s, *model), opt);

  const Sim3D sim(s, rate);
  std::vector<std::vector<ErrSample>> res(size_t(runs) + 1);
  std::vector<Sim3D::FlyCounts> fc(size_t(runs) + 1);
  std::atomic<int> next{0};
  std::mutex err_mu;
  std::string err;
  const std::function<bool()> stop = [] { return ggins::hil::interrupted(); };
  const auto t0 = std::chrono::steady_clock::now();
  auto worker = [&]() {
    for (;;) {
      if (ggins::hil::interrupted()) return;
      const int i = next++;
      if (i > runs) return;
      SensorErrors e;
      if (i > 0) {  // run 0: perfect sensors (the deterministic floor)
        std::mt19937_64 g(seed + uint64_t(i) - 1);
        std::normal_distribution<double> nd(0.0, 1.0);
        for (auto& x : e.acc_bias) x = s.acc_bias_sigma_mps2 * nd(g);
        if (sd)
          for (auto& x : e.gyro_bias) x = s.gyro_bias_sigma_radps * nd(g);
        e.acc_noise = s.model.acc_noise_sigma_mps2;
        e.gyro_noise = sd ? s.model.gyro_noise_sigma_radps : 0.0;
        e.noise_seed = g();
        if (s.model.baro.on) {
          e.baro_bias_m = s.baro_bias_sigma_m * nd(g);
          e.baro_gm_sigma_m = s.model.baro.gm_sigma_m;
          e.baro_gm_tau_s = s.model.baro.gm_tau_s;
          e.baro_noise_m = s.model.baro.noise_sigma_m;
        }
      }
      try {
        res[size_t(i)] = sim.fly(e, s.duration_s, output_dt, &fc[size_t(i)], stop);
      } catch (const std::exception& ex) {
        std::lock_guard<std::mutex> l(err_mu);
        err = ex.what();
        return;
      }
    }
  };
  std::vector<std::thread> th;
  for (int j = 0; j < jobs; ++j) th.emplace_back(worker);
  for (auto& t : th) t.join();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const bool was_interrupted = ggins::hil::interrupted();
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  // The report (report.hpp: the shape of ggins run3d's): runs 1..N are the ensemble (run 0,
  // perfect sensors, is the deterministic floor, in the comparison only).
  std::vector<ggins::hil::EnsembleRun> er;
  for (int i = 1; i <= runs; ++i) {
    ggins::hil::EnsembleRun x;
    x.index = i;
    x.seed = seed + uint64_t(i) - 1;
    const auto& rs = res[size_t(i)];
    x.counts.steps_expected = sim.steps(s.duration_s);
    x.counts.steps_flown = fc[size_t(i)].steps;
    x.counts.final_seq = fc[size_t(i)].steps - 1;
    x.counts.dt_s = 1.0 / rate;
    x.status = !rs.empty() && x.counts.steps_flown == x.counts.steps_expected ? "completed"
               : fc[size_t(i)].stopped || (was_interrupted && x.counts.steps_flown == 0) ? "interrupted"
                                                                                        : "failed";
    x.health_or = fc[size_t(i)].health_or;
    for (int b = 0; b < 32; ++b)
      if (fc[size_t(i)].health_count[size_t(b)] > 0)
        x.health_counts[ggins::hil::health_bit_name(1u << b)] = fc[size_t(i)].health_count[size_t(b)];
    if (!rs.empty()) {  // |error| final and max over the output samples; per-axis finals in NED
      auto fm = [&](auto pick) {
        double mx = 0;
        for (const auto& e : rs) mx = std::max(mx, pick(e).norm());
        return json{{"final", pick(rs.back()).norm()}, {"max", mx}};
      };
      const Eigen::Matrix3d Cne = model->ned_to_ecef(rs.back().t);
      auto ned = [&](const Eigen::Vector3d& v) {
        const Eigen::Vector3d n = Cne.transpose() * v;
        return json{{"n", n(0)}, {"e", n(1)}, {"d", n(2)}};
      };
      x.errors["position_error_m"] = fm([](const ErrSample& e) { return e.dr; });
      x.errors["position_error_final_m"] = ned(rs.back().dr);
      x.errors["velocity_error_mps"] = fm([](const ErrSample& e) { return e.dv; });
      x.errors["velocity_error_final_mps"] = ned(rs.back().dv);
      x.errors["gravity_error_mps2"] = fm([](const ErrSample& e) { return e.dg; });
      x.errors["gravity_error_final_mps2"] = ned(rs.back().dg);
      if (sd) {
        x.errors["attitude_error_rad"] = fm([](const ErrSample& e) { return e.psi; });
        x.errors["attitude_error_final_rad"] = ned(rs.back().psi);
      }
    }
    er.push_back(std::move(x));
  }
  const std::string frame = "NED at the true position (north, east, down)";
  const std::string definition =
      "nav - truth (sim3d.hpp); gravity: G estimated - true gravitation at the TRUE position; attitude: the small "
      "rotation psi of C(nav) C(true)^T; final: the last step, max: the largest over the samples every output_dt_s";
  auto write_report = [&](const ggins::hil::FlightEnd& end, const json& cons, const json& extra) {
    json rep = ggins::hil::ensemble_report("ggins montecarlo3d", "3-D", s.name, scen, s.name, "direct", rate,
                                           s.duration_s, er, runs, end, frame, definition, cons, extra);
    rep["platform"] = sd ? "strapdown" : "stabilized";
    rep["gravity_model"] = s.field;
    rep["baro_loop"] = s.model.baro.on;
    rep["wall_s"] = wall;
    rep["files"] = {{"summary", "summary.json"}, {"scenario", "scenario.toml"}, {"comparison", "montecarlo3d.json"},
                    {"sigma_vs_time", "montecarlo3d.csv"}};
    rep["output_dir"] = fs::absolute(out_dir).string();
    // the scenario as flown: every key, overrides applied; it flies again as `-s scenario.toml`
    // (the ensemble's own settings, not scenario keys, in the head)
    {
      const fs::path sp = fs::path(out_dir) / "scenario.toml";
      std::ofstream f(sp);
      f << "# ggins montecarlo3d -n " << runs << " --seed " << seed << " --output-dt " << sch_num(output_dt) << "\n"
        << scenario3d_to_toml(in);
      f.close();
      if (!f) throw std::runtime_error("cannot write " + sp.string());
    }
    ggins::hil::write_json(fs::path(out_dir) / "summary.json", rep);
    return rep;
  };
  if (!err.empty()) {
    std::fprintf(stderr, "ggins-montecarlo3d: %s\n", err.c_str());
    write_report({err, 1, false, {}}, json(nullptr), json{{"seed", seed}});
    return 1;
  }
  int stopped = 0, unflown = 0;
  for (const auto& x : er) {
    if (x.status != "interrupted") continue;
    if (x.counts.steps_flown > 0) ++stopped;
    else ++unflown;
  }
  if (stopped + unflown > 0 || (was_interrupted && fc[0].stopped)) {  // the partial report: no comparison
    const std::string msg = "interrupted: " + std::to_string(stopped) + " run(s) stopped, " + std::to_string(unflown) +
                            " of " + std::to_string(runs) + " not flown";
    std::fprintf(stderr, "ggins-montecarlo3d: %s\n", msg.c_str());
    write_report({msg, 130, false, {}}, json(nullptr), json{{"seed", seed}});
    return 130;
  }

  // Sample sigma in NED at each output time vs the covariance.
  const char* blk[4] = {"r", "v", "g", "psi"};
  const char* unit[4] = {"m", "mps", "mps2", "rad"};
  const char* ned[3] = {"n", "e", "d"};
  const int nblk = sd ? 4 : 3;
  const size_t nt = res[0].size();
  if (cov.size() != nt) {
    std::fprintf(stderr, "ggins-montecarlo3d: %zu covariance samples vs %zu run samples\n", cov.size(), nt);
    return 1;
  }
  const ggins::truth::Chi2Band b3 = ggins::truth::chi2_band(runs, 3.0);  // truth/stats.hpp
  const std::pair<double, double> band{b3.rms_lo, b3.rms_hi};
  std::ofstream csv(fs::path(out_dir) / "montecarlo3d.csv");
  csv << "t_s";
  std::vector<std::string> keys;
  for (int bk = 0; bk < nblk; ++bk)
    for (int i = 0; i < 3; ++i) keys.push_back(std::string(blk[bk]) + ned[i] + "_" + unit[bk]);
  for (const auto& k : keys) csv << ",mc_" << k << ",cov_" << k << ",perfect_" << k;
  csv << '\n';
  csv.precision(10);
  json fin, ratios_all = json::object();
  bool all_in = true;
  double rmin = 1e9, rmax = 0;
  for (size_t k = 0; k < nt; ++k) {
    const double t = res[0][k].t;
    const Eigen::Matrix3d Cne = model->ned_to_ecef(t);
    csv << t;
    for (int bk = 0; bk < nblk; ++bk) {
      const Eigen::Vector3d cs = ned_sigma(cov[k].P, 3 * bk, Cne);
      Eigen::Vector3d ss = Eigen::Vector3d::Zero();
      auto pick = [bk](const ErrSample& e) { return bk == 0 ? e.dr : bk == 1 ? e.dv : bk == 2 ? e.dg : e.psi; };
      for (int i = 1; i <= runs; ++i) {
        const Eigen::Vector3d en = Cne.transpose() * pick(res[size_t(i)][k]);
        ss += en.cwiseProduct(en);
      }
      ss = (ss / runs).cwiseSqrt();
      const Eigen::Vector3d pf = Cne.transpose() * pick(res[0][k]);
      for (int i = 0; i < 3; ++i) {
        csv << ',' << ss(i) << ',' << cs(i) << ',' << pf(i);
        if (k + 1 == nt) {
          const std::string key = keys[size_t(3 * bk + i)];
          const double r = ss(i) / cs(i);
          const bool in = r >= band.first && r <= band.second;
          all_in = all_in && in;
          rmin = std::min(rmin, r);
          rmax = std::max(rmax, r);
          fin[key] = {{"mc", ss(i)}, {"cov", cs(i)}, {"ratio", r}, {"in_band", in}, {"perfect_run_error", pf(i)}};
        }
      }
    }
    csv << '\n';
  }
  json j;
  j["scenario"] = s.name;
  j["platform"] = sd ? "strapdown" : "stabilized";
  j["field"] = s.field;
  j["omega_ie_radps"] = s.omega_ie;
  j["runs"] = runs;
  j["seed"] = seed;
  j["rate_hz"] = rate;
  j["t_s"] = res[0].back().t;
  j["acc_bias_sigma_mps2"] = s.acc_bias_sigma_mps2;
  j["gyro_bias_sigma_radps"] = sd ? s.gyro_bias_sigma_radps : 0.0;
  j["acc_noise_sigma_mps2"] = s.model.acc_noise_sigma_mps2;
  j["gyro_noise_sigma_radps"] = sd ? s.model.gyro_noise_sigma_radps : 0.0;
  j["baro"] = s.model.baro.on ? json{{"bias_sigma_m", s.baro_bias_sigma_m}, {"gm_sigma_m", s.model.baro.gm_sigma_m},
                                     {"gm_tau_s", s.model.baro.gm_tau_s}, {"noise_sigma_m", s.model.baro.noise_sigma_m},
                                     {"period_s", s.model.baro.period_s}}
                              : json(false);
  j["chi2_band_3sigma"] = {band.first, band.second};
  j["ratio_min"] = rmin;
  j["ratio_max"] = rmax;
  j["all_in_band"] = all_in;
  j["final"] = fin;
  j["wall_s"] = wall;
  j["jobs"] = jobs;
  csv.close();
  if (!csv) throw std::runtime_error("cannot write " + (fs::path(out_dir) / "montecarlo3d.csv").string());
  ggins::hil::write_json(fs::path(out_dir) / "montecarlo3d.json", j);
  // the band is a result (all_in_band, the text's last line), not an exit status: 0 when
  // every run flew (the exit-status scheme of ggins --help), as ggins montecarlo
  int code = 0;
  {
    std::vector<ggins::hil::ConsistencyState> cs;
    for (const auto& k : keys) cs.push_back({k, fin[k]["mc"].get<double>(), fin[k]["cov"].get<double>()});
    const json cons = ggins::hil::consistency_block(
        cs, runs, 3.0, band.first, band.second,
        "s/sigma per NED component at the last output, s = sqrt(sum e^2/N) (zero-mean errors, N dof)");
    const json rep = write_report(ggins::hil::FlightEnd{}, cons,
                                  json{{"seed", seed},
                                       {"seeds", "run i (1..N): seed + i - 1; run 0 perfect sensors"},
                                       {"t_s", j["t_s"]},
                                       {"ratio_min", rmin},
                                       {"ratio_max", rmax},
                                       {"perfect_run_final", [&] {
                                          json p;
                                          for (const auto& k : keys) p[k] = fin[k]["perfect_run_error"];
                                          return p;
                                        }()}});
    const int st = ggins::hil::exit_status(rep);  // the flights' status before the comparison's verdict
    if (st != 0 && (code == 0 || st != 4)) code = st;
  }
  if (!no_plot) {
    const std::string py = ggins::cli::find_python(python);
    const std::string cmd = "'" + py + "' '" GGINS_MC3D_PLOT_SCRIPT "' '" + (fs::path(out_dir) / "montecarlo3d.csv").string() +
                            "' '" + (fs::path(out_dir) / "montecarlo3d.png").string() + "' --title '" + s.name +
                            " N=" + std::to_string(runs) + "' 1>&2";
    if (py.empty() || std::system(cmd.c_str()) != 0) std::fprintf(stderr, "ggins-montecarlo3d: no plot\n");
  }
  if (want_json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("scenario %s (%s, %s field), N = %d, %.0f Hz, t = %.0f s, wall %.1f s (%d threads)\n", s.name.c_str(),
                sd ? "strapdown" : "stabilized", s.field.c_str(), runs, rate, res[0].back().t, wall, jobs);
    std::printf("chi-square band (+-3 sigma) for s/sigma: [%.4f, %.4f]\n", band.first, band.second);
    for (const auto& k : keys)
      std::printf("  %-10s MC %.6g  cov %.6g  ratio %.4f %s  (perfect-sensor run %.3g)\n", k.c_str(),
                  fin[k]["mc"].get<double>(), fin[k]["cov"].get<double>(), fin[k]["ratio"].get<double>(),
                  fin[k]["in_band"].get<bool>() ? "in" : "OUT", fin[k]["perfect_run_error"].get<double>());
    std::printf("%s\n", all_in ? "all inside the band" : "NOT all inside the band");
  }
  return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-montecarlo3d: %s\n", e.what());
    return ggins::cli::kExitFailed;
  }
}
