// The host-in-the-loop runner, one code path for both tasks: `ggins run` (2-D)
// and `ggins run3d` (3-D) are front-ends that give it a Model of their task.
//
//   transport     link.hpp (over LCM through hal_sim) or direct.hpp (in process)
//   supervision   Flight<Model>::fly: the bus or the in-process firmware, the
//                 loop, the interrupt (SIGINT/SIGTERM: the flight stops at the
//                 next step, hal_sim is stopped cleanly, the report is written
//                 marked interrupted, exit 130), the shared counters
//   evaluation    the Model's take() with evaluation.hpp's metrics
//   report        report.hpp: one summary.json shape (the head here, the task's
//                 blocks from the Model, aid blocks as a list)
//
// A Model (see run/run_main.cpp, run3d/run3d_main.cpp) provides
//   using Task;                                     Task2D or Task3D (link.hpp)
//   int64_t n_steps(); int64_t dt_us(); double rate_hz(); double duration_s();
//   std::string name(), source(), description();
//   typename Task::Config config();                 the firmware configuration
//   uint64_t scenario_id(); std::vector<std::string> maps(); Faults faults();
//   void begin(const std::filesystem::path& out, LinkBase* link, int64_t run_id);   CSV, truth channel
//   ggins::sensor_frame_t frame(int64_t k);         the sensor frame of step k (and its truth)
//   void take(const typename Task::Out& m, bool latest);   evaluation of one output
//   void end();                                     close the CSV
//   void report(nlohmann::json& s);                 errors, aids and the task's blocks
//   std::string truth_channel(); int64_t truth_published();   the truth messages on the bus
//   double progress_error_m();                      the latest |dr| for the progress line
//   static std::string final_line(const nlohmann::json& s);   the one-line result
//   static void before_plots(const RunOptions& o, const std::filesystem::path& out,
//                            const nlohmann::json& summary);
//                                                   what the plots need beyond the flight's
//                                                   files (run before the plot script)
#pragma once

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "direct.hpp"
#include "evaluation.hpp"
#include "frame_names.hpp"
#include "ggins/cli_checks.hpp"
#include "hil_common.hpp"
#include "link.hpp"
#include "report.hpp"

namespace ggins::hil {

// The options common to both runners.
struct RunOptions {
  std::string tool;  // "ggins run", "ggins run3d"
  std::string out;
  bool realtime = false, direct = false;
  std::optional<double> duration_s, csv_rate, truth_rate;
  std::optional<uint64_t> seed, fault_seed;
  std::optional<double> drop, dup, reorder, drop_output, garbage;
  double conflict = 0;
  std::string lcm_url, prefix = "GGINS_";
  int resend_timeout_ms = 50, max_resend = 100;
  bool no_log = false, no_plots = false, quiet = false;
  std::string log_mode = "internal", progress = "auto";
  std::string hal_sim, python, logger;
  int batch = 0, window = 0;
  double deadline_ms = 0;
  double deadline_allowance_ms = 1e3 * kDeadlineAllowanceS;
};

inline void add_run_options(CLI::App& app, RunOptions& o) {
  namespace cli = ggins::cli;
  app.add_option("-o,--out", o.out, "output folder (default out/<scenario>-<UTC time>)")->check(cli::OutputDir());
  app.add_flag("--realtime", o.realtime, "pace frames at the sensor rate instead of lockstep");
  app.add_flag("--direct", o.direct,
               "step the firmware in this process (no LCM, no hal_sim; hal_sim's message conversions and task\n"
               "cycle, so the same numbers bit for bit): the reference for the transport's cost");
  app.add_option("--batch", o.batch, "lockstep: frames per LCM message (default 32)")->check(cli::IntRange(1, 128));
  app.add_option("--window", o.window, "lockstep: frames in flight (default: automatic, from the round trip)")
      ->check(cli::IntRange(1, 4096));
  app.add_option("--deadline-ms", o.deadline_ms,
                 "realtime: output latency deadline, ms (default one sensor period + --deadline-allowance-ms);\n"
                 "an output later than it, or never received, makes the run degraded (exit 4)")
      ->check(cli::FiniteRange(0, 60000, cli::kOpenLow));
  app.add_option("--deadline-allowance-ms", o.deadline_allowance_ms,
                 "realtime: allowance of the default deadline over one sensor period, ms (host scheduling,\n"
                 "recovery of a lost frame)")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 60000));
  app.add_option("--duration", o.duration_s, "override the scenario's duration, s")
      ->check(cli::FiniteRange(0, 1e7, cli::kOpenLow));
  app.add_option("--seed", o.seed, "override the accelerometer error seed ([accel] seed)")->check(cli::Seed());
  app.add_option("--csv-rate", o.csv_rate, "CSV rows per second of flight (default: the scenario's, 1 Hz)")
      ->check(cli::FiniteRange(0, 1e6, cli::kOpenLow));
  app.add_option("--truth-rate", o.truth_rate, "truth messages per second on LCM (default: the scenario's, 10), 0 = every step")
      ->check(cli::FiniteRange(0, 1e6));
  const auto prob = cli::FiniteRange(0.0, 0.99);
  app.add_option("--drop-prob", o.drop, "inject: drop each frame transmission with this probability")->check(prob);
  app.add_option("--dup-prob", o.dup, "inject: send a frame twice with this probability")->check(prob);
  app.add_option("--reorder-prob", o.reorder, "inject: send frame k+1 before frame k with this probability")->check(prob);
  app.add_option("--drop-output-prob", o.drop_output, "inject: hal_sim drops each navigation output with this probability")
      ->check(prob);
  app.add_option("--garbage-prob", o.garbage,
                 "inject: before a frame, an undecodable payload on the frame channel with this probability")
      ->check(prob);
  app.add_option("--conflict-prob", o.conflict,
                 "inject: after a frame, a second, different frame with the same seq and a valid MAC, with this\n"
                 "probability, and the same for outputs in hal_sim (an authenticated sender contradicting\n"
                 "itself: counted as conflicts, the first copies flown, the run fails)")
      ->check(prob);
  app.add_option("--fault-seed", o.fault_seed, "seed of the transport fault injection (default: the scenario's)")
      ->check(cli::Seed());
  app.add_option("--resend-timeout-ms", o.resend_timeout_ms, "resend a frame whose output is this late, ms")
      ->capture_default_str()
      ->check(cli::IntRange(1, 60000));
  app.add_option("--max-resend", o.max_resend, "give up on a step after this many resends")
      ->capture_default_str()
      ->check(cli::IntRange(1, 100000));
  app.add_option("--lcm-url", o.lcm_url, "LCM URL for both directions (default: two private udpm ports, ttl=0)");
  app.add_option("--prefix", o.prefix, "LCM channel prefix")->capture_default_str();
  app.add_flag("--no-log", o.no_log, "do not record an LCM log (same as --log none)");
  app.add_option("--log", o.log_mode,
                 "LCM log writer: internal (this process records every message it sends and receives;\n"
                 "lossless), lcm-logger (separate process; may drop under load, checked in summary.json\n"
                 "log.complete), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"internal", "lcm-logger", "none"}));
  app.add_flag("--no-plots", o.no_plots, "do not make PNG plots");
  app.add_flag("-q,--quiet", o.quiet, "no progress, only errors and the output folder");
  app.add_option("--progress", o.progress, "progress display: auto (line on a terminal, every 10% otherwise), on, off")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "on", "off"}));
  app.add_option("--hal-sim", o.hal_sim, "hal_sim executable (default: beside this executable)");
  app.add_option("--python", o.python, "Python with matplotlib for the plots")->capture_default_str();
  app.add_option("--logger", o.logger, "lcm-logger executable")->capture_default_str();
}

// The flight of one Model: supervision and the shared counters; returns the report.
template <class Model>
class Flight {
 public:
  using Task = typename Model::Task;
  using Out = typename Task::Out;

  Flight(const RunOptions& o, Model& m, std::filesystem::path out) : opt_(o), m_(m), out_(std::move(out)) {}

  nlohmann::json fly() {
    n_ = m_.n_steps();
    tty_ = isatty(2) != 0;
    const double t_setup = mono_s();
    typename Task::Config cfg = m_.config();
    std::unique_ptr<Direct<Task>> direct;
    std::unique_ptr<Link<Task>> link;
    if (opt_.direct) {
      run_id_ = new_run_id();
      cfg.run_id = run_id_;
      direct = std::make_unique<Direct<Task>>(cfg);
      for (const auto& p : m_.maps()) direct->add_map(p);
    } else {
      LinkOptions lo;
      lo.tool = opt_.tool;
      lo.hal_sim = opt_.hal_sim;
      lo.prefix = opt_.prefix;
      lo.lcm_url = opt_.lcm_url;
      lo.log_mode = opt_.log_mode;
      lo.logger = opt_.logger;
      lo.resend_timeout_ms = opt_.resend_timeout_ms;
      lo.max_resend = opt_.max_resend;
      lo.batch = opt_.batch;
      lo.window = opt_.window;
      lo.realtime = opt_.realtime;
      lo.deadline_s = 1e-3 * opt_.deadline_ms;
      lo.deadline_allowance_s = 1e-3 * opt_.deadline_allowance_ms;
      lo.faults = m_.faults();
      for (const auto& p : m_.maps()) lo.hal_args.insert(lo.hal_args.end(), {"--map", p});
      link = std::make_unique<Link<Task>>(lo, out_, n_, m_.dt_us());
      run_id_ = link->run_id();
    }
    m_.begin(out_, link.get(), run_id_);
    if (link) link->start(cfg, m_.scenario_id());
    if (!opt_.quiet) {
      if (link)
        std::fprintf(stderr, "%s: %s, %lld steps at %g Hz (%s), LCM %s (to hal_sim) %s (back), output %s\n",
                     opt_.tool.c_str(), m_.name().c_str(), static_cast<long long>(n_), m_.rate_hz(),
                     opt_.realtime ? "realtime" : "lockstep", link->url_to_hal().c_str(), link->url_from_hal().c_str(),
                     out_.c_str());
      else
        std::fprintf(stderr, "%s: %s, %lld steps at %g Hz (direct, in process), output %s\n", opt_.tool.c_str(),
                     m_.name().c_str(), static_cast<long long>(n_), m_.rate_hz(), out_.c_str());
    }

    t_start_ = mono_s();
    const double cpu0 = LinkBase::cpu_s();
    double fw_ns = 0;  // --direct: the firmware steps (cycles[TOTAL])
    const double setup_s = t_start_ - t_setup;
    FlightEnd end;
    try {
      if (direct) {
        for (int64_t k = 0; k < n_; ++k) {
          if ((k & 1023) == 0) {
            if (interrupted()) throw Fail("interrupted", 130);
            progress(false);
          }
          const Out o = direct->step(m_.frame(k));
          fw_ns += static_cast<double>(static_cast<uint32_t>(o.cycles[GG_MOD_TOTAL]));
          take(o);
        }
      } else {
        link->run([this](int64_t k) { return m_.frame(k); }, [this](const Out& o) { take(o); },
                  [this](int64_t) { progress(false); });
      }
    } catch (const Fail& e) {
      end.error = e.what();
      end.code = e.code;
    }
    const double wall = mono_s() - t_start_;
    const double cpu_loop = LinkBase::cpu_s() - cpu0;
    progress(true);
    // STOP hal_sim and wait for it (also when interrupted: it runs in its own
    // process group, so a terminal's SIGINT reaches only this process)
    if (link && end.code != 3) {
      try {
        link->finish();
      } catch (const Fail&) {
      }
    }
    m_.end();
    if (link) link->close_log();
    // Two different authenticated messages for one seq: the key holder (this
    // process or hal_sim) contradicted itself, or the key is no longer secret.
    // Which copy is right cannot be known, so the run is not completed.
    const nlohmann::json bus = link ? link->bus_auth_summary(link->outputs_conflict()) : nlohmann::json();
    if (link && bus["conflicts_total"].template get<int64_t>() > 0 && end.error.empty()) {
      end.error = "conflicting authenticated messages (" + bus["conflicts"].dump() +
                  "): two different messages for one seq carried a valid MAC; the run cannot be trusted";
      end.code = 1;
    }
    // degraded: flown to the end, but not every frame's readings entered the
    // navigation (frames rejected, or an axis group that lost more readings than
    // parity rebuilds: components held), or the last step's output is missing,
    // or the run ended in an outage, or (real time) an output came later than
    // its deadline; each reason is stated in summary.json (degraded_reasons)
    if (counts_.steps_rejected > 0)
      end.reasons.push_back(std::to_string(counts_.steps_rejected) + " steps rejected by the firmware");
    if (!last_ || last_->seq != n_ - 1) end.reasons.push_back("the last step's output is missing");
    if (last_ && last_->outage_s != 0.0) {
      char why[96];
      std::snprintf(why, sizeof why, "the run ended in an outage of %.6g s", last_->outage_s);
      end.reasons.push_back(why);
    }
    if ((health_or_ & GG_HEALTH_ACC_DEGRADED) != 0)
      end.reasons.push_back("an accelerometer axis group lost more readings than parity rebuilds (ACC_DEGRADED)");
    if ((health_or_ & GG_HEALTH_FORCE_COAST) != 0)
      end.reasons.push_back("specific-force components held (FORCE_COAST)");
    nlohmann::json rt;
    if (link && opt_.realtime) {
      rt = link->realtime_summary();
      const int64_t over = rt["deadline_overruns"].template get<int64_t>();
      if (over > 0) {
        char why[320];
        std::snprintf(why, sizeof why,
                      "%lld outputs later than the real-time deadline of %.6g ms (%s; output latency max %.6g ms, "
                      "%lld outputs never received)",
                      static_cast<long long>(over), rt["deadline_us"].template get<double>() * 1e-3,
                      rt["deadline_definition"].template get<std::string>().c_str(),
                      rt["output_latency_us"].value("max", 0.0) * 1e-3,
                      static_cast<long long>(rt["outputs_never_received"].template get<int64_t>()));
        end.reasons.push_back(why);
      }
    }
    end.degraded = !end.reasons.empty();

    counts_.steps_expected = n_;
    counts_.dt_s = static_cast<double>(m_.dt_us()) * 1e-6;
    const auto& hst = link ? link->hal_status() : std::optional<ggins::hal_status_t>();
    counts_.frames_recovered = hst ? hst->frames_recovered : 0;
    nlohmann::json s = report_head(opt_.tool, Task::kName, m_.name(), m_.source(), m_.description(),
                                   opt_.direct ? "direct" : (opt_.realtime ? "realtime" : "lockstep"), m_.rate_hz(),
                                   m_.duration_s(), counts_, end);
    if (last_) {  // the navigation at the last step flown: how it got there (navtask.h)
      s["recovery"] = {{"resyncs", last_->resync_count},
                       {"coast_steps", last_->coast_steps},
                       {"final_outage_s", last_->outage_s},
                       {"final_state_lag_s", last_->state_lag_s}};
    }
    s["health_seen"] = health_word(health_or_);
    nlohmann::json hc = nlohmann::json::object();
    for (int b = 0; b < 32; ++b)
      if (health_count_[static_cast<size_t>(b)] > 0) hc[health_bit_name(1u << b)] = health_count_[static_cast<size_t>(b)];
    s["health_counts"] = hc;
    s["aids"] = nlohmann::json::array();
    m_.report(s);
    // the model's own reasons (an aid inconsistent or refused for part of the flight)
    if (s["status"] == "completed" && !s["degraded_reasons"].empty()) {
      s["status"] = "degraded";
      s["degraded"] = true;
    }

    s["wall_s"] = wall;
    s["setup_s"] = setup_s;
    s["cpu_s"] = {{"runner", cpu_loop}};  // CPU (user + system) of the flight
    if (link && link->cpu_s_hal_sim() >= 0) s["cpu_s"]["hal_sim"] = link->cpu_s_hal_sim();
    if (direct) s["cpu_s"]["firmware_steps"] = 1e-9 * fw_ns;
    // flight time actually navigated per wall second
    s["realtime_factor"] = wall > 0 ? s["flown_s"].template get<double>() / wall : 0.0;
    s["steps_per_s"] = wall > 0 ? static_cast<double>(counts_.steps_flown) / wall : 0.0;
    nlohmann::json ft;
    for (int j = 0; j < GG_MOD_COUNT; ++j) {
      const Percentiles pc = cyc_[j].percentiles();
      nlohmann::json e = {{"median", pc.median}, {"p99", pc.p99}, {"max", pc.max}};
      if (j == GG_MOD_TOTAL) {
        ft["median"] = pc.median;
        ft["p99"] = pc.p99;
        ft["max"] = pc.max;
      }
      ft["modules"][module_name(j)] = e;
    }
    ft["source"] = "nav output cycles (HAL cycle counter: CLOCK_MONOTONIC ns truncated to uint32)";
    s["firmware_step_ns"] = ft;
    s["run_id"] = run_id_;
    s["channel_prefix"] = opt_.prefix;
    if (link) {
      nlohmann::json tr = link->transport_summary();
      tr["truth_published"] = m_.truth_published();
      s["transport"] = tr;
      s["hal_sim"] = link->hal_sim_summary();
      s["bus_auth"] = bus;
      if (opt_.realtime) s["realtime"] = rt;
      s["lcm_url"] = link->url_to_hal();
      s["lcm_url_from_hal"] = link->url_from_hal();
      if (opt_.log_mode != "none") {
        s["log"] = link->verify_log(m_.truth_channel(), m_.truth_published());
        s["log"]["writer"] = opt_.log_mode;
      }
    }
    s["files"] = {{"summary", "summary.json"}, {"timeseries", "timeseries.csv"}, {"scenario", "scenario.toml"}};
    if (link) s["files"]["hal_sim_log"] = "hal_sim.log";
    if (link && opt_.log_mode != "none") s["files"]["lcm_log"] = "run.lcmlog";
    s["output_dir"] = out_.string();
    return s;
  }

 private:
  void take(const Out& m) {
    ++counts_.steps_flown;
    if (m.status != 0) ++counts_.steps_rejected;
    const uint32_t h = static_cast<uint32_t>(m.health);
    health_or_ |= h;
    for (int b = 0; b < 32; ++b)
      if (h & (1u << b)) ++health_count_[static_cast<size_t>(b)];
    for (int j = 0; j < GG_MOD_COUNT; ++j) cyc_[j].add(j < m.n_cycles ? static_cast<uint32_t>(m.cycles[j]) : 0u);
    const bool latest = !last_ || m.seq > last_->seq;
    if (latest) {
      last_ = m;
      counts_.final_seq = m.seq;
    }
    m_.take(m, latest);
  }

  void progress(bool final) {
    if (opt_.quiet) return;
    const double now = mono_s();
    const bool show_tty = tty_ && opt_.progress != "off";
    const double frac = n_ > 0 ? static_cast<double>(counts_.steps_flown) / static_cast<double>(n_) : 1.0;
    const double sim_t = static_cast<double>(std::max<int64_t>(counts_.final_seq, 0)) * static_cast<double>(m_.dt_us()) * 1e-6;
    const double el = now - t_start_;
    char msg[256];
    std::snprintf(msg, sizeof msg, "t = %7.1f / %.0f s  %5.1f%%  wall %6.1f s  x%.0f real time  |dr| %.3g m", sim_t,
                  m_.duration_s(), 100.0 * frac, el, el > 0 ? sim_t / el : 0.0, m_.progress_error_m());
    if (show_tty) {
      if (!final && now - t_last_progress_ < 0.25) return;
      t_last_progress_ = now;
      std::fprintf(stderr, "\r%s", msg);
      if (final) std::fprintf(stderr, "\n");
    } else if (opt_.progress != "off") {  // not a terminal: one line per 10%
      const int pct = static_cast<int>(frac * 10.0) * 10;
      if (pct > last_pct_reported_) {
        last_pct_reported_ = pct;
        std::fprintf(stderr, "%s: %s\n", opt_.tool.c_str(), msg);
      }
    }
  }

  const RunOptions& opt_;
  Model& m_;
  std::filesystem::path out_;
  int64_t n_ = 0, run_id_ = 0;
  FlightCounts counts_;
  uint32_t health_or_ = 0;
  std::array<int64_t, 32> health_count_{};
  CycleStats cyc_[GG_MOD_COUNT];
  std::optional<Out> last_;
  double t_start_ = 0, t_last_progress_ = 0;
  bool tty_ = false;
  int last_pct_reported_ = -1;
};

// The error model's covariance for the scenario as flown, for the plots' one-sigma
// envelopes: the command `tool` (ggins-covariance, ggins-covariance3d: beside this one) run
// on <out>/scenario.toml, its files in <out>/covariance/. A scenario the model does not
// cover (an anomaly field, the gravity-model navigation mode) gets no envelope;
// covariance/covariance.log says why and the plot names the reason. Never fails the run.
inline void error_model_covariance(const RunOptions& o, const std::filesystem::path& out, const char* tool) {
  namespace fs = std::filesystem;
  const fs::path exe = self_dir() / tool;
  std::error_code ec;
  fs::create_directories(out / "covariance", ec);
  if (ec || access(exe.c_str(), X_OK) != 0) return;
  try {
    pid_t pid = spawn({exe.string(), "-s", (out / "scenario.toml").string(), "--no-plot", "-o",
                       (out / "covariance").string()},
                      out / "covariance" / "covariance.log");
    if (wait_child(pid, 120.0) == -1) {
      stop_child(pid);
      std::fprintf(stderr, "%s: %s took over 120 s; plots without its envelope\n", o.tool.c_str(), tool);
    }
  } catch (const Fail&) {
  }
}

// After the flight: plots (a Python script on the output folder), the result
// lines, the exit status.
inline int finish_run(const RunOptions& o, const nlohmann::json& s, const std::string& plot_script,
                      const std::string& line) {
  const std::filesystem::path out = s["output_dir"].get<std::string>();
  if (!o.no_plots && !interrupted()) {
    if (o.python.empty()) {
      std::fprintf(stderr, "%s: no Python with matplotlib was found at build time; plots skipped (--python)\n",
                   o.tool.c_str());
    } else {
      int st = -1;
      try {
        const pid_t pid = spawn({o.python, plot_script, out.string()}, out / "plot.log");
        st = wait_child(pid, 300.0);
      } catch (const Fail&) {
      }
      if (st != 0) std::fprintf(stderr, "%s: plotting failed; see %s\n", o.tool.c_str(), (out / "plot.log").c_str());
    }
  }
  if (!o.quiet) {
    std::printf("%s\n", line.c_str());
    std::printf("  steps flown %lld of %lld (unflown %lld, rejected %lld), frames lost %lld, recovered %lld; wall %.2f s, "
                "real-time factor %.1f; step %.0f ns median, %.0f p99, %.0f max\n",
                static_cast<long long>(s["steps_flown"].get<int64_t>()),
                static_cast<long long>(s["steps_expected"].get<int64_t>()),
                static_cast<long long>(s["steps_unflown"].get<int64_t>()),
                static_cast<long long>(s["steps_rejected"].get<int64_t>()),
                static_cast<long long>(s["frames_lost"].get<int64_t>()),
                static_cast<long long>(s["frames_recovered"].get<int64_t>()), s["wall_s"].get<double>(),
                s["realtime_factor"].get<double>(), s["firmware_step_ns"]["median"].get<double>(),
                s["firmware_step_ns"]["p99"].get<double>(), s["firmware_step_ns"]["max"].get<double>());
  }
  if (s.contains("bus_auth") && s["bus_auth"]["rejected_total"].get<int64_t>() > 0)
    std::fprintf(stderr,
                 "%s: %lld messages without a valid MAC were dropped (someone without the key published on the "
                 "run's channels): %s\n",
                 o.tool.c_str(), static_cast<long long>(s["bus_auth"]["rejected_total"].get<int64_t>()),
                 s["bus_auth"]["rejected_unauthenticated"].dump().c_str());
  if (s.contains("error")) std::fprintf(stderr, "%s: %s\n", o.tool.c_str(), s["error"].get<std::string>().c_str());
  if (s["status"] == "degraded") {
    std::string why;
    for (const auto& r : s.value("degraded_reasons", nlohmann::json::array())) why += (why.empty() ? "" : "; ") + r.get<std::string>();
    std::fprintf(stderr, "%s: completed but degraded (%s; see summary.json)\n", o.tool.c_str(), why.c_str());
  }
  std::printf("report: %s\n", out.c_str());
  return exit_status(s);
}

// The front-end's flight, once the scenario is loaded and its overrides applied:
// the checks of the options that depend on each other, the output folder, the
// scenario as flown (the file's text with `effective` set: report.hpp), the
// model (make_model(out), which may throw; out: the output folder), the flight,
// the report, the plots.
template <class Model, class MakeModel>
int fly_scenario(RunOptions& o, const std::string& name, const std::string& source, const std::string& text,
                 const nlohmann::json& effective, const std::string& plot_script, MakeModel&& make_model) {
  namespace fs = std::filesystem;
  const char* tool = o.tool.c_str();
  if (o.no_log) o.log_mode = "none";
  if (o.direct && o.realtime) {
    std::fprintf(stderr, "%s: --direct and --realtime exclude each other\n", tool);
    return ggins::cli::kExitBadArgs;
  }
  if (!o.direct) {
    if (o.hal_sim.empty()) o.hal_sim = (self_dir() / "hal_sim").string();
    if (access(o.hal_sim.c_str(), X_OK) != 0) {
      std::fprintf(stderr, "%s: hal_sim not found at %s (build it, give --hal-sim, or --direct)\n", tool,
                   o.hal_sim.c_str());
      return ggins::cli::kExitBadArgs;
    }
  }
  std::error_code ec;
  fs::path out = create_output_dir(o.out, name, ec);
  if (ec) {
    std::fprintf(stderr, "%s: cannot create %s: %s\n", tool, out.c_str(), ec.message().c_str());
    return ggins::cli::kExitBadArgs;
  }
  out = fs::absolute(out);
  install_interrupt_handlers();
  nlohmann::json summary;
  try {
    write_effective_scenario(out / "scenario.toml", name, source, text, effective);
    auto model = make_model(out);
    Flight<Model> flight(o, *model, out);
    summary = flight.fly();
    write_json(out / "summary.json", summary);
  } catch (const Fail& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return e.code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return ggins::cli::kExitFailed;
  }
  if (!o.no_plots && !interrupted()) Model::before_plots(o, out, summary);
  return finish_run(o, summary, plot_script, Model::final_line(summary));
}

// A task's front-end (ggins run, ggins run3d) around fly_scenario, the same for every task:
// --list-scenarios, --print-scenario [--defaults], the scenario read, the options that override
// it (--duration, --seed, then the task's own), the step count checked, the scenario printed or
// flown. S is the task's scenario (description, duration_s, accel.seed, n_steps()).
template <class S>
struct ScenarioFrontEnd {
  std::function<std::vector<std::string>()> names;       // the built-in scenarios
  // by name or path; adjust (--duration, --seed, then apply) goes on the scenario as read,
  // before anything the task derives from the flight
  std::function<S(const std::string&, const std::function<void(S&)>& adjust)> load;
  std::function<std::string()> template_toml;            // every key at its default, commented
  std::function<void(S&)> apply;                         // the task's own overrides (after --duration, --seed)
  std::function<std::string(const S&)> as_flown;         // printed, and written beside the report
  std::function<int(S&, const std::string& as_flown)> fly;
};

struct FrontEndFlags {
  bool list = false, print = false, defaults = false;
};

inline void add_scenario_flags(CLI::App& app, FrontEndFlags& f) {
  app.add_flag("--list-scenarios", f.list, "list the built-in scenarios and exit");
  app.add_flag("--print-scenario", f.print,
               "print the scenario as it would fly (every key: defaults filled in, overrides applied, the files\n"
               "it names absolute; a threshold derived from other keys only where the file gives it) and exit");
  app.add_flag("--defaults", f.defaults,
               "with --print-scenario: a complete template instead (every key at its default, commented\n"
               "with unit, allowed range and meaning; docs/scenario-reference.md)");
}

template <class S>
int scenario_main(RunOptions& o, const std::string& scenario, const FrontEndFlags& f, const ScenarioFrontEnd<S>& fe) {
  const char* tool = o.tool.c_str();
  if (f.list) {
    for (const auto& n : fe.names()) std::printf("%-20s %s\n", n.c_str(), fe.load(n, {}).description.c_str());
    return ggins::cli::kExitOk;
  }
  if (f.defaults && !f.print) {
    std::fprintf(stderr, "%s: --defaults: allowed only with --print-scenario\n", tool);
    return ggins::cli::kExitBadArgs;
  }
  if (f.defaults) {
    std::fputs(fe.template_toml().c_str(), stdout);
    return ggins::cli::kExitOk;
  }
  S sc;
  std::string text;
  try {
    sc = fe.load(scenario, [&](S& s) {
      if (o.duration_s) s.duration_s = *o.duration_s;
      if (o.seed) s.accel.seed = *o.seed;
      fe.apply(s);
    });
    if (sc.n_steps() < 2) throw std::runtime_error("the scenario needs at least two steps");
    if (sc.n_steps() > 100000000)
      throw std::runtime_error("more than 1e8 steps in one run (" + std::to_string(sc.n_steps()) +
                               "): shorten the duration or lower the rate");
    text = fe.as_flown(sc);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", tool, e.what());
    return ggins::cli::kExitBadArgs;
  }
  if (f.print) {
    std::fputs(text.c_str(), stdout);
    return ggins::cli::kExitOk;
  }
  return fe.fly(sc, text);
}

}  // namespace ggins::hil
