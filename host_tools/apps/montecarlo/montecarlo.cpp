// ggins-montecarlo: runs N host-in-the-loop flights of a scenario (ggins-run,
// fresh accelerometer error seed per run, all cores), and compares the sample
// one-sigma errors with the covariance prediction of ggins-covariance (same
// scenario file, same linear model: Welker, Pachter & Huffman eqs. 7-11).
//
// Statistics: the errors are zero-mean (zero-mean random biases through a
// linear error model), so the sample one-sigma is s = sqrt(sum e^2 / N) with
// N degrees of freedom, N s^2 / sigma^2 ~ chi^2_N. The acceptance band for
// s / sigma is the two-sided chi-square interval at +-z standard normal
// quantiles (default z = 3, 99.73 %), via the Wilson-Hilferty approximation
// chi^2_p ~ N (1 - 2/(9N) + z_p sqrt(2/(9N)))^3.
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "ggins/cli_checks.hpp"
#include "ggins/covariance/propagate.hpp"
#include "ggins/covariance/scenario.hpp"
#include "ggins/covariance/welker2d.hpp"
#include "ggins/gravity/field.hpp"
#include "ggins/truth/scenario.hpp"
#include "ggins/truth/stats.hpp"
#include "hil_common.hpp"
#include "report.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using namespace ggins::covariance;

namespace {

const char* kKeys[6] = {"x_m", "z_m", "vx_mps", "vz_mps", "gx_mps2", "gz_mps2"};
const char* kCols[6] = {"err_r_x_m", "err_r_z_m", "err_v_x_mps", "err_v_z_mps", "err_g_x_mps2", "err_g_z_mps2"};

struct RunData {
  std::vector<double> t;
  std::vector<std::array<double, 6>> e;
  bool ok = false;
};

RunData read_run(const fs::path& csv) {
  RunData r;
  std::ifstream f(csv);
  if (!f) return r;
  std::string line;
  if (!std::getline(f, line)) return r;
  std::vector<std::string> head;
  {
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) head.push_back(c);
  }
  auto idx = [&](const std::string& n) {
    for (size_t i = 0; i < head.size(); ++i)
      if (head[i] == n) return int(i);
    return -1;
  };
  const int it = idx("t_s");
  int ic[6];
  for (int k = 0; k < 6; ++k) ic[k] = idx(kCols[k]);
  if (it < 0) return r;
  for (int k = 0; k < 6; ++k)
    if (ic[k] < 0) return r;
  std::vector<double> v;
  while (std::getline(f, line)) {
    v.clear();
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) v.push_back(std::strtod(c.c_str(), nullptr));
    if (int(v.size()) < int(head.size())) continue;
    r.t.push_back(v[size_t(it)]);
    std::array<double, 6> e{};
    for (int k = 0; k < 6; ++k) e[size_t(k)] = v[size_t(ic[k])];
    r.e.push_back(e);
  }
  r.ok = !r.t.empty();
  return r;
}


// Every run's own report (summary.json, ggins run) read back as a flight of the ensemble;
// scenario.toml: the scenario as flown by the first run that reported.
struct Ensemble2 {
  std::vector<ggins::hil::EnsembleRun> runs;
  std::string mode = "lockstep", frame, definition, source, description;
  ggins::hil::FlightEnd end;
};

Ensemble2 read_ensemble(const fs::path& outp, const std::string& name, const std::string& scen, int runs, int64_t seed0,
                        const std::vector<int>& run_rc) {
  Ensemble2 en;
  en.source = scen;
  int n_interrupted = 0, n_failed = 0;
  for (int i = 0; i < runs; ++i) {
    const int rc = run_rc[size_t(i)];
    if ((WIFSIGNALED(rc) && WTERMSIG(rc) == SIGINT) || (WIFEXITED(rc) && WEXITSTATUS(rc) == 130)) ++n_interrupted;
    json r;
    try {
      std::ifstream f(outp / "runs" / std::to_string(i) / "summary.json");
      if (f) r = json::parse(f);
    } catch (const json::exception&) {
      r = json();
    }
    if (!r.is_object() || !r.contains("status")) {
      ++n_failed;
      continue;
    }
    ggins::hil::EnsembleRun x;
    x.index = i;
    x.seed = uint64_t(seed0 + i);
    x.status = r["status"].get<std::string>();
    if (x.status != "completed" && x.status != "degraded") ++n_failed;
    x.counts.steps_expected = r.value("steps_expected", int64_t(0));
    x.counts.steps_flown = r.value("steps_flown", int64_t(0));
    x.counts.steps_rejected = r.value("steps_rejected", int64_t(0));
    x.counts.frames_recovered = r.value("frames_recovered", int64_t(0));
    x.counts.final_seq = r.value("final_seq", int64_t(-1));
    x.counts.dt_s = r.value("dt_s", 0.0);
    if (r.contains("health_seen")) x.health_or = r["health_seen"].value("raw", 0u);
    if (r.contains("health_counts"))
      for (const auto& [k, v] : r["health_counts"].items()) x.health_counts[k] = v.get<int64_t>();
    if (r.contains("errors")) {
      x.errors = r["errors"];
      en.frame = x.errors.value("frame", en.frame);
      en.definition = x.errors.value("definition", en.definition);
      x.errors.erase("frame");
      x.errors.erase("definition");
    }
    en.mode = r.value("mode", en.mode);
    en.source = r.value("scenario_source", en.source);
    en.description = r.value("description", en.description);
    if (en.runs.empty()) {  // the scenario as flown by the first run (run i: accel seed seed0 + i)
      std::ifstream sf(outp / "runs" / std::to_string(i) / "scenario.toml");
      std::stringstream st;
      st << sf.rdbuf();
      ggins::hil::write_effective_scenario(outp / "scenario.toml", name, en.source, st.str(),
                                           json{{"accel.seed", seed0 + i}});
    }
    if (x.status == "degraded") {
      en.end.degraded = true;
      en.end.reasons.push_back("run " + std::to_string(i) + " degraded (runs/" + std::to_string(i) + "/summary.json)");
    }
    en.runs.push_back(std::move(x));
  }
  if (n_interrupted > 0) {
    // the runs never started (or without a report) are unflown, each with the steps of a run
    int64_t per_run = 0;
    for (const auto& x : en.runs) per_run = std::max(per_run, x.counts.steps_expected);
    int unflown = 0;
    for (int i = 0; i < runs; ++i) {
      bool have = false;
      for (const auto& x : en.runs) have = have || x.index == i;
      if (have) continue;
      ggins::hil::EnsembleRun x;
      x.index = i;
      x.seed = uint64_t(seed0 + i);
      x.status = "interrupted";
      x.counts.steps_expected = per_run;
      en.runs.push_back(std::move(x));
      ++unflown;
    }
    std::sort(en.runs.begin(), en.runs.end(), [](const auto& a, const auto& b) { return a.index < b.index; });
    en.end.error = "interrupted: " + std::to_string(n_interrupted) + " run(s) stopped, " + std::to_string(unflown) +
                   " of " + std::to_string(runs) + " not flown";
    en.end.code = 130;
  } else if (n_failed > 0) {
    en.end.error = std::to_string(n_failed) + " of " + std::to_string(runs) + " runs failed (see runs/<i>.log)";
    en.end.code = 1;
  }
  return en;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ggins montecarlo: N host-in-the-loop flights (ggins-run) with fresh random accelerometer errors,\n"
      "in parallel, against the covariance prediction (ggins-covariance's model). Writes to --out the\n"
      "report summary.json (the shape of ggins run's, docs/hil.md, with the ensemble block), scenario.toml\n"
      "(as flown by run 0; run i flies accel seed seed0 + i), montecarlo.csv, montecarlo.json (the\n"
      "comparison), run_errors.csv and montecarlo.png; --json prints montecarlo.json.",
      "ggins-montecarlo"};
  std::string scen = "welker-table1", out_dir, run_exe, python;
  int runs = 200, jobs = int(std::thread::hardware_concurrency());
  int64_t seed0 = 1000;
  double z = 3.0;
  std::optional<double> duration;
  bool want_json = false, no_plot = false, keep = false;
  app.add_option("-s,--scenario", scen, "scenario name or .toml path (as ggins run)")->capture_default_str();
  app.add_option("-n,--runs", runs, "number of flights")->capture_default_str()->check(CLI::Range(2, 100000));
  app.add_option("-j,--jobs", jobs, "flights in parallel (default: all cores)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--seed0", seed0, "run i uses accelerometer seed seed0 + i")
      ->capture_default_str()
      ->check(ggins::cli::IntRange(0, 4000000000000000000LL));
  app.add_option("--duration", duration, "override the scenario duration, s")
      ->check(ggins::cli::FiniteRange(0.0, 1e6, ggins::cli::kOpenLow));
  app.add_option("--z", z, "acceptance band: +-z normal quantiles of the chi-square interval")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(0.0, 10.0, ggins::cli::kOpenLow));
  app.add_option("-o,--out", out_dir, "output directory (default out/montecarlo/<scenario>)")->check(ggins::cli::OutputDir());
  app.add_option("--run-exe", run_exe, "ggins-run executable (default: beside this one)");
  app.add_flag("--keep-runs", keep, "keep every run's output folder");
  app.add_flag("--json", want_json, "print the JSON summary on stdout");
  app.add_flag("--no-plot", no_plot, "no PNG");
  app.add_option("--python", python, "python with matplotlib (default: $GGINS_PYTHON, /usr/bin/python3)");
  bool print_scenario = false, print_defaults = false;
  app.add_flag("--print-scenario", print_scenario,
               "print the scenario as every run flies it (ggins run's: every key, defaults filled in,\n"
               "overrides applied; run i's accel seed seed0 + i) and exit");
  app.add_flag("--defaults", print_defaults,
               "with --print-scenario: a complete template instead (every key at its default, commented\n"
               "with unit, allowed range and meaning; docs/scenario-reference.md)");
  try {  // bad arguments: CLI11's message naming the option, exit 2 (ggins/cli_checks.hpp)
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? ggins::cli::kExitOk : ggins::cli::kExitBadArgs;
  }

  if (print_defaults && !print_scenario) {
    std::fprintf(stderr, "ggins-montecarlo: --defaults: allowed only with --print-scenario\n");
    return ggins::cli::kExitBadArgs;
  }
  if (print_scenario) {  // what ggins run --print-scenario prints for the runs (the same library calls)
    try {
      if (print_defaults) {
        std::fputs(ggins::truth::scenario_to_toml(ggins::truth::Scenario{}, true).c_str(), stdout);
      } else {
        ggins::truth::Scenario t = ggins::truth::load_scenario(scen, {GGINS_SCENARIO_DIR});
        if (duration) t.duration_s = *duration;  // (run i flies accel.seed = seed0 + i)
        std::fputs(ggins::truth::scenario_to_toml(t).c_str(), stdout);
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ggins-montecarlo: %s\n", e.what());
      return ggins::cli::kExitBadArgs;
    }
    return ggins::cli::kExitOk;
  }
  CovScenario sc;
  try {
    sc = resolve_scenario(scen, GGINS_SOURCE_DIR);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-montecarlo: %s\n", e.what());
    return 2;
  }
  if (duration) sc.duration_s = *duration;
  if (out_dir.empty()) out_dir = "out/montecarlo/" + sc.name;
  if (run_exe.empty()) run_exe = (ggins::hil::self_dir() / "ggins-run").string();
  const fs::path outp = fs::absolute(out_dir);
  fs::create_directories(outp / "runs");

  // 1. The flights, `jobs` at a time.
  std::atomic<int> next{0}, failed{0}, done{0};
  std::atomic<bool> stop{false};  // Ctrl-C reached a run: launch no further run
  std::vector<int> run_rc(size_t(std::max(runs, 0)), 0);
  std::mutex io;
  auto worker = [&] {
    for (int i; !stop && (i = next++) < runs;) {
      const fs::path rd = outp / "runs" / std::to_string(i);
      std::ostringstream cmd;
      cmd << "'" << run_exe << "' --scenario '" << scen << "' --seed " << (seed0 + i)
          << " --no-log --no-plots -q --csv-rate 1 --out '" << rd.string() << "'";
      if (duration) cmd << " --duration " << *duration;
      cmd << " > '" << rd.string() << ".log' 2>&1";
      const int rc = std::system(cmd.str().c_str());
      run_rc[size_t(i)] = rc;
      // a terminal's SIGINT reaches the runs (one process group): the run exits 130, or
      // its shell dies of the signal; the runs not yet started stay unflown
      if ((WIFSIGNALED(rc) && WTERMSIG(rc) == SIGINT) || (WIFEXITED(rc) && WEXITSTATUS(rc) == 130)) stop = true;
      const int d = ++done;
      if (rc != 0) {
        ++failed;
        std::lock_guard<std::mutex> lk(io);
        std::fprintf(stderr, "ggins-montecarlo: run %d failed (rc %d), see %s.log\n", i, rc, rd.c_str());
      }
      if (d % std::max(1, runs / 10) == 0) {
        std::lock_guard<std::mutex> lk(io);
        std::fprintf(stderr, "ggins-montecarlo: %d/%d flights done\n", d, runs);
      }
    }
  };
  std::vector<std::thread> pool;
  for (int k = 0; k < std::min(jobs, runs); ++k) pool.emplace_back(worker);
  for (auto& th : pool) th.join();

  // 2. Sample one-sigma (RMS about zero, N degrees of freedom) against time.
  std::vector<RunData> data;
  for (int i = 0; i < runs; ++i) {
    RunData r = read_run(outp / "runs" / std::to_string(i) / "timeseries.csv");
    if (r.ok) data.push_back(std::move(r));
  }
  const int n = int(data.size());
  if (n < 2) {  // the report says which runs failed; no ensemble statistics
    std::fprintf(stderr, "ggins-montecarlo: fewer than 2 usable runs\n");
    try {
      Ensemble2 en = read_ensemble(outp, sc.name, scen, runs, seed0, run_rc);
      if (en.end.error.empty()) en.end = {"fewer than 2 usable runs", 1, false, {}};
      json rep = ggins::hil::ensemble_report("ggins montecarlo", "2-D", sc.name, en.source, en.description, en.mode,
                                             sc.rate_hz, sc.duration_s, en.runs, runs, en.end, en.frame, en.definition,
                                             json(nullptr), json{{"seed0", seed0}});
      rep["output_dir"] = outp.string();
      ggins::hil::write_json(outp / "summary.json", rep);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "ggins-montecarlo: %s\n", e.what());
    }
    return 1;
  }
  size_t nt = data[0].t.size();
  for (const auto& r : data) nt = std::min(nt, r.t.size());
  std::vector<std::array<double, 6>> ss(nt, std::array<double, 6>{});
  for (const auto& r : data)
    for (size_t k = 0; k < nt; ++k)
      for (int s = 0; s < 6; ++s) ss[k][size_t(s)] += r.e[k][size_t(s)] * r.e[k][size_t(s)];

  // 3. Covariance on the same scenario (model of ggins-covariance), 1 s samples.
  auto field = std::make_shared<ggins::gravity::PointMassField>(sc.gm_m3ps2);
  auto traj = std::make_shared<NorthGreatCircle2D>(sc.speed_mps, sc.height_m, sc.lat0_rad, sc.radius_m);
  Welker2DModel model(field, traj, sc.a_m, sc.b_m);
  VectorXd psd(8);
  for (int i = 0; i < 8; ++i) psd(i) = sc.noise_sigma_mps2[size_t(i)] * sc.noise_sigma_mps2[size_t(i)] / sc.rate_hz;
  model.set_white_noise_psd(psd);
  MatrixXd P0 = MatrixXd::Zero(14, 14);
  P0(4, 4) = sc.gravity0_sigma_x_mps2 * sc.gravity0_sigma_x_mps2;
  P0(5, 5) = sc.gravity0_sigma_z_mps2 * sc.gravity0_sigma_z_mps2;
  for (int i = 0; i < 8; ++i) P0(6 + i, 6 + i) = sc.bias_sigma_mps2[size_t(i)] * sc.bias_sigma_mps2[size_t(i)];
  PropagationOptions opt;
  opt.t_end = sc.duration_s;
  opt.dt = 1.0;
  opt.output_dt = 1.0;
  opt.method = model.has_process_noise() ? Method::kLyapunov : Method::kTransition;
  const auto cov = propagate(model, P0, opt);
  auto cov_sigma = [&](double t) {
    const size_t k = std::min(cov.size() - 1, size_t(std::lround(std::max(0.0, t))));
    return sigmas(cov[k].P, 6);
  };

  const ggins::truth::Chi2Band band = ggins::truth::chi2_band(n, z);  // truth/stats.hpp
  const double lo = band.rms_lo, hi = band.rms_hi;
  {
    std::ofstream f(outp / "montecarlo.csv");
    f << "t_s";
    for (auto k : kKeys) f << ",mc_" << k;
    for (auto k : kKeys) f << ",cov_" << k;
    f << '\n';
    f.precision(10);
    for (size_t k = 0; k < nt; ++k) {
      const VectorXd c = cov_sigma(data[0].t[k]);
      f << data[0].t[k];
      for (int s = 0; s < 6; ++s) f << ',' << std::sqrt(ss[k][size_t(s)] / n);
      for (int s = 0; s < 6; ++s) f << ',' << c(s);
      f << '\n';
    }
  }
  {
    std::ofstream f(outp / "run_errors.csv");  // every run's errors every 10 s, for the plot
    f << "run,t_s";
    for (auto k : kKeys) f << ',' << k;
    f << '\n';
    f.precision(8);
    for (int i = 0; i < n; ++i)
      for (size_t k = 0; k < nt; k += 10) {
        f << i << ',' << data[size_t(i)].t[k];
        for (int s = 0; s < 6; ++s) f << ',' << data[size_t(i)].e[k][size_t(s)];
        f << '\n';
      }
  }

  json j;
  j["scenario"] = sc.name;
  j["runs"] = runs;
  j["runs_used"] = n;
  j["runs_failed"] = int(failed);
  j["seed0"] = seed0;
  j["t_s"] = data[0].t[nt - 1];
  j["tolerance"] = {{"statistic", "s/sigma, s = sqrt(sum e^2/N) (zero-mean errors, N dof)"},
                    {"z", z},
                    {"ratio_lo", lo},
                    {"ratio_hi", hi},
                    {"method", "two-sided chi-square interval, Wilson-Hilferty, per state and time"}};
  bool agree = true;
  const VectorXd cf = cov_sigma(data[0].t[nt - 1]);
  json fin;
  for (int s = 0; s < 6; ++s) {
    const double m = std::sqrt(ss[nt - 1][size_t(s)] / n), ratio = m / cf(s);
    const bool ok = ratio >= lo && ratio <= hi;
    agree = agree && ok;
    fin[kKeys[s]] = {{"montecarlo", m}, {"covariance", cf(s)}, {"ratio", ratio}, {"within", ok}};
  }
  j["final"] = fin;
  // The same comparison every 600 s (t >= 600 s), for the record.
  json marks = json::array();
  for (size_t k = 0; k < nt; ++k) {
    const double t = data[0].t[k];
    if (t < 600 - 1e-9 || std::fmod(t + 1e-6, 600.0) > 2e-6) continue;
    const VectorXd c = cov_sigma(t);
    json row = {{"t_s", t}};
    for (int s = 0; s < 6; ++s) row[kKeys[s]] = std::sqrt(ss[k][size_t(s)] / n) / c(s);
    marks.push_back(row);
  }
  j["ratio_every_600s"] = marks;
  j["agree_final"] = agree;
  int code = agree && failed == 0 ? 0 : 1;
  try {
    ggins::hil::write_json(outp / "montecarlo.json", j);
    // The report, in the shape of ggins run's (report.hpp): every run's own report read back.
    Ensemble2 en = read_ensemble(outp, sc.name, scen, runs, seed0, run_rc);
    auto& er = en.runs;
    std::vector<ggins::hil::ConsistencyState> cs;
    for (int k = 0; k < 6; ++k)
      cs.push_back({kKeys[k], fin[kKeys[k]]["montecarlo"].get<double>(), fin[kKeys[k]]["covariance"].get<double>()});
    const json cons = ggins::hil::consistency_block(cs, n, z, lo, hi,
                                                    "s/sigma, s = sqrt(sum e^2/N) at the last common time (zero-mean "
                                                    "errors, N dof); the flight's inertial frame, x equatorial, z polar");
    json extra = {{"seed0", seed0},
                  {"seeds", "run i: accel seed seed0 + i"},
                  {"t_s", j["t_s"]},
                  {"ratio_every_600s", marks}};
    json rep = ggins::hil::ensemble_report("ggins montecarlo", "2-D", sc.name, en.source, en.description, en.mode,
                                           sc.rate_hz, sc.duration_s, er, runs, en.end, en.frame, en.definition, cons,
                                           extra);
    rep["files"] = {{"summary", "summary.json"}, {"scenario", "scenario.toml"}, {"comparison", "montecarlo.json"},
                    {"sigma_vs_time", "montecarlo.csv"}, {"run_errors", "run_errors.csv"}};
    rep["output_dir"] = outp.string();
    ggins::hil::write_json(outp / "summary.json", rep);
    // the flights' status (1 failed, 130 interrupted, 4 degraded) before the comparison's verdict
    const int st = ggins::hil::exit_status(rep);
    if (st != 0 && (code == 0 || st != 4)) code = st;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins-montecarlo: %s\n", e.what());
    return ggins::cli::kExitFailed;
  }
  if (!keep) {
    std::error_code ec;
    fs::remove_all(outp / "runs", ec);
  }

  if (!no_plot) {
    if (const std::string py = ggins::cli::find_python(python); !py.empty()) {
      const std::string cmd = "'" + py + "' '" GGINS_MC_PLOT_SCRIPT "' '" + outp.string() + "' --title '" + sc.name +
                              " (N = " + std::to_string(n) + ")' 1>&2";
      if (std::system(cmd.c_str()) != 0) std::fprintf(stderr, "ggins-montecarlo: plot failed\n");
    } else {
      std::fprintf(stderr, "ggins-montecarlo: no python with matplotlib found (try --python /usr/bin/python3); no plot\n");
    }
  }
  if (want_json) {
    std::cout << j.dump(2) << '\n';
  } else {
    std::printf("scenario %s: %d flights (%d failed), t = %.0f s; band for s/sigma: [%.4f, %.4f] (z = %g)\n",
                sc.name.c_str(), n, int(failed), data[0].t[nt - 1], lo, hi, z);
    for (int s = 0; s < 6; ++s)
      std::printf("  %-8s MC %.6g  covariance %.6g  ratio %.4f  %s\n", kKeys[s],
                  fin[kKeys[s]]["montecarlo"].get<double>(), fin[kKeys[s]]["covariance"].get<double>(),
                  fin[kKeys[s]]["ratio"].get<double>(), fin[kKeys[s]]["within"].get<bool>() ? "ok" : "OUTSIDE");
    std::printf("wrote %s\n", outp.c_str());
  }
  return code;
}
