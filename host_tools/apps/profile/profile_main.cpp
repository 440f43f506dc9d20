// ggins profile: fly a scenario host-in-the-loop (ggins run for the 2-D task,
// ggins run3d for the 3-D task with the aids its scenario switches on; no log, no
// plots) and print the firmware's per-module step time table - median, p99
// and max, from the HAL cycle counter the firmware reads around each module
// (host: CLOCK_MONOTONIC ns), the aids of the 3-D task among them - with the
// step period budget and overruns.
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>

#include "ggins/cli_checks.hpp"
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "ggins/coldatom/pf_bench.hpp"

namespace fs = std::filesystem;

// The filter kernels that run beside the navigation step at their own rates (the cold-atom particle filter's
// particle filter, 1 Hz): timed in-process on this host with the settings of
// coldatom-pf-bench (pf_bench.hpp), printed as rows of the same table.
static int print_filter_rows(int shots, int chunk) {
  using namespace ggins::coldatom;
  auto b = pf_bench_make(PfBenchModel::kRbpf, GG_PF_MAX);
  PfStepTimes t;
  if (!b || !pf_bench_run(*b, shots, chunk, &t)) {
    std::fprintf(stderr, "ggins profile: particle filter bench failed\n");
    return 1;
  }
  std::printf("filter kernels, in-process on this host (%d shots; Rao-Blackwellised particle filter, %d particles,\n"
              "gmap candidates; runs at 1 Hz beside the step; Cortex-M7 counts: scripts/m7-qemu-count pf pf250):\n",
              shots, GG_PF_MAX);
  std::printf("%-10s %10s %10s %10s\n", "module", "median ns", "p99 ns", "max ns");
  auto row = [](const char* m, std::vector<double>& v) {
    std::printf("%-10s %10.0f %10.0f %10.0f\n", m, pf_bench_quantile(v, 0.5), pf_bench_quantile(v, 0.99),
                pf_bench_quantile(v, 1.0));
  };
  row("pf_shot", t.shot);
  row("pf_begin", t.begin);
  char name[32];
  std::snprintf(name, sizeof name, "pf_chunk%d", chunk);
  row(name, t.chunk);
  row("pf_end", t.end);
  std::printf("(a shot = pf_begin + %d x pf_chunk%d + pf_end when split over navigation steps; pf_end includes "
              "the resampling shots)\n", (GG_PF_MAX + chunk - 1) / chunk, chunk);
  return 0;
}

int main(int argc, char** argv) {
  CLI::App app{
      "ggins profile: per-module firmware step time for a scenario.\n"
      "Runs `ggins run --no-log --no-plots` (2-D task) or `ggins run3d --no-log --no-plots`\n"
      "(3-D task, with the aids its scenario switches on: the gradient-map UKF aid_mm, the\n"
      "cold-atom particle filter aid_pf), lockstep over LCM with hal_sim in its own process,\n"
      "then prints median / p99 / max ns per firmware module as the firmware measured it\n"
      "through the HAL cycle counter (CLOCK_MONOTONIC on the host; DWT CYCCNT on a board),\n"
      "the share of the step period, and the deadline overruns the firmware counted.\n"
      "Then the filter kernels that run beside the step at their own rate (the cold-atom particle\n"
      "filter: whole shot, and split into begin / chunks / end), timed in-process.\n"
      "Deterministic instruction counts: scripts/bench (callgrind), scripts/m7-qemu-count."};
  std::string scenario = "welker-perfect";
  double duration = 0.0;
  std::string keep;
  bool realtime = false, no_filters = false, filters_only = false;
  int pf_shots = 200, pf_chunk = 50;
  std::string task = "auto";
  app.add_option("-s,--scenario", scenario, "scenario name or .toml path")->capture_default_str();
  app.add_option("--task", task,
                 "which navigation task flies it: 2d (ggins run), 3d (ggins run3d), or auto: 3d when the "
                 "scenario's name or file name begins with \"3d\"")
      ->check(CLI::IsMember({"auto", "2d", "3d"}))
      ->capture_default_str();
  app.add_option("--duration", duration, "override the scenario's duration, s")
      ->check(ggins::cli::FiniteRange(0, 1e7, ggins::cli::kOpenLow));
  app.add_flag("--realtime", realtime, "pace frames at the sensor rate (caches go cold between steps)");
  app.add_option("--keep", keep, "keep the run's output folder here (default: a temporary folder, removed)")
      ->check(ggins::cli::OutputDir());
  app.add_flag("--no-filters", no_filters, "skip the filter-kernel rows (particle filter, timed in-process)");
  app.add_flag("--filters-only", filters_only, "only the filter-kernel rows (no host-in-the-loop run)");
  app.add_option("--pf-shots", pf_shots, "particle-filter shots to time")->check(ggins::cli::IntRange(1, 100000))->capture_default_str();
  app.add_option("--pf-chunk", pf_chunk, "particles per chunk of the split shot")
      ->check(ggins::cli::IntRange(1, GG_PF_MAX))->capture_default_str();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? ggins::cli::kExitOk : ggins::cli::kExitBadArgs;
  }
  if (filters_only) return print_filter_rows(pf_shots, pf_chunk);
  if (task == "auto") task = fs::path(scenario).stem().string().rfind("3d", 0) == 0 ? "3d" : "2d";
  const bool is3d = task == "3d";

  std::error_code ec;
  fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) self = fs::absolute(argv[0]);
  const fs::path run = self.parent_path() / (is3d ? "ggins-run3d" : "ggins-run");
  if (!fs::exists(run)) {
    std::fprintf(stderr, "ggins profile: %s not found (build the project)\n", run.c_str());
    return 1;
  }
  fs::path out = keep.empty() ? fs::temp_directory_path() / ("ggins-profile-" + std::to_string(getpid()))
                              : fs::path(keep);
  std::vector<std::string> args = {run.string(), "--scenario", scenario, "--no-log", "--no-plots",
                                   "--out", out.string()};
  if (duration > 0) {
    args.push_back("--duration");
    args.push_back(std::to_string(duration));
  }
  if (realtime) args.push_back("--realtime");
  std::vector<char*> cargs;
  for (auto& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  std::fprintf(stderr, "ggins profile: running %s (%s task) ...\n", scenario.c_str(), task.c_str());
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("ggins profile: fork");
    return 1;
  }
  if (pid == 0) {
    execv(cargs[0], cargs.data());
    std::perror("ggins profile: exec");
    _exit(127);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    std::fprintf(stderr, "ggins profile: %s failed (status %d); see its messages above\n", run.filename().c_str(),
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 1;
  }
  nlohmann::json s;
  try {
    std::ifstream f(out / "summary.json");
    f >> s;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins profile: cannot read %s: %s\n", (out / "summary.json").c_str(), e.what());
    return 1;
  }
  const auto& fw = s.at("firmware_step_ns");
  const double rate = s.value("rate_hz", 0.0);
  struct utsname u {};
  uname(&u);
  std::printf("firmware step time, scenario %s, %lld steps, %s; machine %s %s (%ld cores)\n",
              scenario.c_str(), static_cast<long long>(s.value("steps_flown", 0)),
              realtime ? "realtime" : "lockstep", u.sysname, u.machine, sysconf(_SC_NPROCESSORS_ONLN));
  std::printf("%-10s %10s %10s %10s\n", "module", "median ns", "p99 ns", "max ns");
  // the aids run inside the step (their cycles are part of "total"); rows of modules the
  // scenario did not run (all zero) are left out
  const char* order[] = {"diff", "gravdr", "mech", "vchan", "aid_mm", "aid_pf", "total"};
  for (const char* m : order) {
    if (!fw.contains("modules") || !fw["modules"].contains(m)) continue;
    const auto& r = fw["modules"][m];
    if (std::string(m) != "total" && r.value("max", 0.0) <= 0.0) continue;
    std::printf("%-10s %10.0f %10.0f %10.0f\n", m, r.value("median", 0.0), r.value("p99", 0.0),
                r.value("max", 0.0));
  }
  if (rate > 0) {
    const double period_ns = 1e9 / rate;
    std::printf("step period %.0f ns: median total uses %.3f %% of it, the largest %.3f %%\n", period_ns,
                100.0 * fw.value("median", 0.0) / period_ns, 100.0 * fw.value("max", 0.0) / period_ns);
  }
  if (s.contains("transport") && s["transport"].contains("hal_sim") &&
      s["transport"]["hal_sim"].contains("deadline_overruns"))
    std::printf("deadline overruns (steps flagged GG_HEALTH_DEADLINE): %lld\n",
                static_cast<long long>(s["transport"]["hal_sim"]["deadline_overruns"].get<double>()));
  if (keep.empty()) fs::remove_all(out, ec);
  if (!no_filters) return print_filter_rows(pf_shots, pf_chunk);
  return 0;
}
